// SPDX-License-Identifier: MIT
/// @file test_support_indirection.h
/// Relief maps the indirection tests share: analytic ones built in memory, and the real height maps
/// of ../shared/data/heightmaps (downsampled where a test only needs the shape).
#pragma once

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include <cellrelief/indirection/relief_map.h>

#include "test_support.h"

namespace cellrelief::test {

/// A relief map of n x n texels with H(u, v) = f(u, v) at texel centres.
inline indirection::ReliefMap analyticRelief(int n, float scale,
                                             const std::function<float(float, float)>& f,
                                             Wrap wrap = Wrap::Clamp) {
  std::vector<float> h(std::size_t(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) h[std::size_t(y) * n + x] = f((x + 0.5f) / n, (y + 0.5f) / n);
  return indirection::ReliefMap(n, n, std::move(h), scale, wrap);
}

/// The paper's figure 10: a raised box (one step) or a cube-shaped well with near-vertical walls.
inline indirection::ReliefMap boxRelief(int n, float scale, bool well = false) {
  return analyticRelief(n, scale, [well](float u, float v) {
    const bool in = u > 0.3f && u < 0.7f && v > 0.3f && v < 0.7f;
    return (in != well) ? 1.0f : 0.0f;
  });
}

/// Value noise in [0, 1] (bilinear between random lattice values), deterministic.
inline indirection::ReliefMap noiseRelief(int n, float scale, int cells, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  std::vector<float> lattice(std::size_t(cells + 1) * (cells + 1));
  for (float& x : lattice) x = uni(rng);
  return analyticRelief(n, scale, [&](float u, float v) {
    const float x = u * cells, y = v * cells;
    const int i = std::min(int(x), cells - 1), j = std::min(int(y), cells - 1);
    const float a = x - i, b = y - j;
    auto at = [&](int p, int q) { return lattice[std::size_t(q) * (cells + 1) + p]; };
    return (1 - b) * ((1 - a) * at(i, j) + a * at(i + 1, j)) +
           b * ((1 - a) * at(i, j + 1) + a * at(i + 1, j + 1));
  });
}

inline std::filesystem::path heightmap(const std::string& name) {
  return dataDir() / "heightmaps" / name;
}

}  // namespace cellrelief::test
