// SPDX-License-Identifier: MIT
/// @file ray_comparison.h
/// Per-ray comparison of two renderings of the same camera: hit/miss disagreement, depth error
/// (median, 95th percentile, maximum) and normal angle error over the rays both hit. It works on
/// the depth, normal and mask images every backend and the Embree reference write, so it compares
/// any two of them; the caller scales depth errors to a fraction of the diagonal or to texels.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"

namespace cellrelief::metrics {

/// Order statistics of a sample.
struct Distribution {
  double median = 0;
  double p95 = 0;
  double p99 = 0;
  double max = 0;
  double mean = 0;
};

/// Median, 95th and 99th percentiles (nearest rank), maximum and mean; zeros for an empty sample.
inline Distribution distributionOf(std::vector<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  auto rank = [&](double q) {
    const std::size_t i = std::size_t(std::ceil(q * double(values.size()))) - 1;
    return values[std::min(i, values.size() - 1)];
  };
  d.median = rank(0.5);
  d.p95 = rank(0.95);
  d.p99 = rank(0.99);
  d.max = values.back();
  for (double v : values) d.mean += v;
  d.mean /= double(values.size());
  return d;
}

struct RayComparison {
  std::size_t rays = 0;
  std::size_t bothHit = 0;
  std::size_t onlyReference = 0;  ///< the reference hit, the test missed
  std::size_t onlyTest = 0;       ///< the test hit, the reference missed
  Distribution depthError;        ///< |depth difference|, world units, over rays both hit
  Distribution normalErrorDegrees;
  std::size_t disagreements() const { return onlyReference + onlyTest; }
  double disagreementRate() const { return rays ? double(disagreements()) / double(rays) : 0.0; }
};

/// Compares a test rendering with a reference, ray by ray. Normals are compared when both have
/// them (3 channels). Throws InvalidArgument when the sizes differ.
inline RayComparison compareRays(const Image<float>& referenceDepth,
                                 const Image<std::uint8_t>& referenceMask,
                                 const Image<float>& referenceNormal, const Image<float>& testDepth,
                                 const Image<std::uint8_t>& testMask, const Image<float>& testNormal) {
  const int w = referenceMask.width(), h = referenceMask.height();
  auto sameSize = [&](const auto& image) {
    return !image.isEmpty() && image.width() == w && image.height() == h;
  };
  if (!sameSize(referenceDepth) || !sameSize(testDepth) || !sameSize(testMask))
    throw Error(ErrorKind::InvalidArgument, "compareRays: depth and mask images must have one size");
  const bool normals = sameSize(referenceNormal) && sameSize(testNormal);
  RayComparison c;
  std::vector<double> depth, angle;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ++c.rays;
      const bool r = referenceMask.at(x, y, 0) != 0, t = testMask.at(x, y, 0) != 0;
      if (r != t) {
        (r ? c.onlyReference : c.onlyTest)++;
        continue;
      }
      if (!r) continue;
      ++c.bothHit;
      depth.push_back(std::abs(double(referenceDepth.at(x, y, 0)) - double(testDepth.at(x, y, 0))));
      if (normals) {
        double dot = 0;
        for (int k = 0; k < 3; ++k) dot += double(referenceNormal.at(x, y, k)) * testNormal.at(x, y, k);
        angle.push_back(std::acos(std::clamp(dot, -1.0, 1.0)) * 180.0 / M_PI);
      }
    }
  c.depthError = distributionOf(std::move(depth));
  c.normalErrorDegrees = distributionOf(std::move(angle));
  return c;
}

}  // namespace cellrelief::metrics
