// SPDX-License-Identifier: MIT
/// @file frame_comparison.h
/// How far two frames of the same scene and camera agree, channel by channel: the measure of the
/// backend-switching suite, `cellrelief compare-backends` and bench_backends, so all three report
/// the same figures. Depth is compared in sample spacings of the model (its natural unit of
/// error), normals as angles, colors as the largest channel difference (0..255).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cellrelief/core/image.h"
#include "cellrelief/metrics/ray_comparison.h"
#include "cellrelief/render/frame.h"

namespace cellrelief::render {

struct FrameAgreement {
  std::size_t pixels = 0;       ///< compared
  std::size_t bothHit = 0;      ///< pixels both frames hit
  std::size_t maskDiffers = 0;  ///< pixels one frame hit and the other missed
  double maskFraction = 0;      ///< maskDiffers / pixels
  double medianTexels = 0, p95Texels = 0, maxTexels = 0;  ///< depth error, in sample spacings
  double medianDegrees = 0, p95Degrees = 0;                ///< normal angle
  double meanColor = 0, medianColor = 0, p99Color = 0;     ///< largest channel difference
  double cellFraction = 0;  ///< of the pixels both hit, those whose hit cell differs
  double meanSteps = 0;     ///< mean |steps a - steps b| per pixel
};

/// Compares the channels both frames hold (the mask is required). `sampleSpacing`: world units
/// per sample of the model, to express depth errors in texels.
inline FrameAgreement compareFrames(const Frame& a, const Frame& b, double sampleSpacing) {
  FrameAgreement r;
  if (!a.has(kMask) || !b.has(kMask) || a.width != b.width || a.height != b.height) return r;
  const bool depth = a.has(kDepth) && b.has(kDepth), normal = a.has(kNormal) && b.has(kNormal);
  const bool color = a.has(kColor) && b.has(kColor), cell = a.has(kCell) && b.has(kCell);
  const bool steps = a.has(kSteps) && b.has(kSteps);
  std::vector<double> depthErrors, angles, colors;
  std::size_t cellsDiffer = 0;
  double stepSum = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      ++r.pixels;
      if (steps) stepSum += std::abs(double(a.steps.at(x, y, 0)) - double(b.steps.at(x, y, 0)));
      const bool ha = a.mask.at(x, y, 0) != 0, hb = b.mask.at(x, y, 0) != 0;
      if (ha != hb) {
        ++r.maskDiffers;
        continue;
      }
      if (color) {
        int worst = 0;
        for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(int(a.color.at(x, y, c)) - int(b.color.at(x, y, c))));
        colors.push_back(worst);
      }
      if (!ha) continue;
      ++r.bothHit;
      if (depth)
        depthErrors.push_back(std::abs(double(a.depth.at(x, y, 0)) - double(b.depth.at(x, y, 0))) / sampleSpacing);
      if (normal) {
        const Vec3d na(a.normal.at(x, y, 0), a.normal.at(x, y, 1), a.normal.at(x, y, 2));
        const Vec3d nb(b.normal.at(x, y, 0), b.normal.at(x, y, 1), b.normal.at(x, y, 2));
        // atan2 of sine and cosine: acos loses all precision near 0 (0.02 degrees for equal floats).
        angles.push_back(std::atan2(glm::length(glm::cross(na, nb)), glm::dot(na, nb)) * 180 / M_PI);
      }
      if (cell) cellsDiffer += a.cell.at(x, y, 0) != b.cell.at(x, y, 0);
    }
  r.maskFraction = double(r.maskDiffers) / double(std::max<std::size_t>(1, r.pixels));
  const metrics::Distribution depthDistribution = metrics::distributionOf(std::move(depthErrors));
  const metrics::Distribution angleDistribution = metrics::distributionOf(std::move(angles));
  const metrics::Distribution colorDistribution = metrics::distributionOf(std::move(colors));
  r.medianTexels = depthDistribution.median;
  r.p95Texels = depthDistribution.p95;
  r.maxTexels = depthDistribution.max;
  r.medianDegrees = angleDistribution.median;
  r.p95Degrees = angleDistribution.p95;
  r.meanColor = colorDistribution.mean;
  r.medianColor = colorDistribution.median;
  r.p99Color = colorDistribution.p99;
  r.cellFraction = double(cellsDiffer) / double(std::max<std::size_t>(1, r.bothHit));
  r.meanSteps = stepSum / double(std::max<std::size_t>(1, r.pixels));
  return r;
}

/// A picture of the disagreement: red where only `a` hit, blue where only `b` did, grey by depth
/// error where both hit (light grey: equal, black: a sample spacing or more), white where neither.
inline Image<std::uint8_t> frameDiffImage(const Frame& a, const Frame& b, double sampleSpacing) {
  Image<std::uint8_t> image(a.width, a.height, 3, 255);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const bool ha = a.mask.at(x, y, 0) != 0, hb = b.mask.at(x, y, 0) != 0;
      Vec3f c(1);
      if (ha && hb) {
        const double e = std::abs(double(a.depth.at(x, y, 0)) - double(b.depth.at(x, y, 0))) / sampleSpacing;
        c = Vec3f(float(0.85 * (1.0 - std::min(1.0, e))));
      } else if (ha) {
        c = Vec3f(1, 0, 0);
      } else if (hb) {
        c = Vec3f(0, 0, 1);
      }
      for (int k = 0; k < 3; ++k) image.at(x, y, k) = std::uint8_t(std::lround(255 * c[k]));
    }
  return image;
}

}  // namespace cellrelief::render
