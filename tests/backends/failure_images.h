// SPDX-License-Identifier: MIT
/// @file failure_images.h
/// The backend-switching comparison of one scene: every GPU backend that runs here against the
/// CPU reference, per pixel, within measured bounds; and what a failed comparison leaves behind:
/// the CPU reference's frame, the backend's and their difference as PNGs under the build tree.
#pragma once

#include <algorithm>
#include <cstdio>
#include <memory>
#include <filesystem>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/render/frame_comparison.h>

#include "test_support.h"

namespace cellrelief::test {

inline void writeFailureImages(const render::Frame& expected, const render::Frame& actual, double sampleSpacing,
                               const std::string& stem) {
  const std::filesystem::path dir = std::filesystem::path(CELLRELIEF_TEST_OUTPUT_DIR) / "backend_failures";
  std::filesystem::create_directories(dir);
  io::writePng(expected.color, dir / (stem + "_expected_cpu.png"));
  io::writePng(actual.color, dir / (stem + "_actual.png"));
  io::writePng(render::frameDiffImage(expected, actual, sampleSpacing), dir / (stem + "_diff.png"));
  std::printf("wrote %s/%s_{expected_cpu,actual,diff}.png\n", dir.c_str(), stem.c_str());
}

/// How far a GPU backend's frame may stray from the CPU reference's.
struct AgreementBounds {
  std::size_t minHits = 0;  ///< pixels both hit: the view must show the scene
  double mask = 0, depthP95 = 0, normalP95 = 0, meanColour = 0, p99Colour = 0;
  double medianColour = 256;  ///< the median must stay below this (levels of 255)
  bool sameCells = false;   ///< the cell channel must agree exactly
  double meanSteps = -1;    ///< the mean steps-per-ray difference must stay at or below this (< 0: not checked)
};

/// Renders `scene` from each camera on OpenGL and Vulkan (a failure under CI where one does not
/// run) and on the CPU, prints the agreement and checks it against the bounds; writes the
/// failure images of a frame out of bounds. Returns the comparisons made.
inline int expectGpuBackendsAgree(const render::Scene& scene, std::span<const render::Camera> cameras,
                                  const render::RenderOptions& options, double sampleSpacing,
                                  const AgreementBounds& bounds, const std::string& label) {
  using namespace render;
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  int compared = 0;
  for (BackendKind kind : {BackendKind::OpenGL, BackendKind::Vulkan}) {
    const Availability available = backends::isAvailable(kind);
    if (!available) {
      if (inCI()) ADD_FAILURE() << backendName(kind) << " must run under CI: " << available.reason;
      continue;
    }
    std::unique_ptr<Backend> gpu = backends::createBackend(kind);
    gpu->upload(scene);
    for (std::size_t v = 0; v < cameras.size(); ++v) {
      const Frame expected = cpu.renderFrame(cameras[v], options);
      const Frame actual = gpu->renderFrame(cameras[v], options);
      const FrameAgreement a = compareFrames(expected, actual, sampleSpacing);
      ++compared;
      const std::string what = label + ", view " + std::to_string(v) + " on " + std::string(backendName(kind));
      std::printf("%s: %zu hits, mask %zu px, depth median %.2e p95 %.2e max %.2e (of the sample spacing), normal "
                  "median %.4f p95 %.4f deg, colour mean %.3f median %.0f p99 %.0f, cells differ %.2e, steps differ %.3f\n",
                  what.c_str(), a.bothHit, a.maskDiffers, a.medianTexels, a.p95Texels, a.maxTexels, a.medianDegrees,
                  a.p95Degrees, a.meanColor, a.medianColor, a.p99Color, a.cellFraction, a.meanSteps);
      EXPECT_GT(a.bothHit, bounds.minHits) << what;
      EXPECT_LE(a.maskFraction, bounds.mask) << what;
      EXPECT_LE(a.p95Texels, bounds.depthP95) << what;
      EXPECT_LE(a.p95Degrees, bounds.normalP95) << what;
      EXPECT_LE(a.meanColor, bounds.meanColour) << what;
      EXPECT_LE(a.p99Color, bounds.p99Colour) << what;
      EXPECT_LT(a.medianColor, bounds.medianColour) << what;
      if (bounds.sameCells) EXPECT_EQ(a.cellFraction, 0.0) << what;
      if (bounds.meanSteps >= 0) EXPECT_LE(a.meanSteps, bounds.meanSteps) << what;
      if (a.maskFraction > bounds.mask || a.meanColor > bounds.meanColour || a.p99Color > bounds.p99Colour ||
          a.medianColor >= bounds.medianColour) {
        std::string stem = label + "_view" + std::to_string(v) + "_" + std::string(backendName(kind));
        std::replace(stem.begin(), stem.end(), ' ', '_');
        writeFailureImages(expected, actual, sampleSpacing, stem);
      }
    }
  }
  return compared;
}

}  // namespace cellrelief::test
