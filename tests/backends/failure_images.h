// SPDX-License-Identifier: MIT
/// @file failure_images.h
/// What a failed backend comparison leaves behind: the CPU reference's frame, the backend's and
/// their difference as PNGs under the build tree, with their paths printed.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>

#include <cellrelief/io/image_io.h>
#include <cellrelief/render/frame_comparison.h>

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

}  // namespace cellrelief::test
