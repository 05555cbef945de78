// SPDX-License-Identifier: MIT
/// @file quantize.h
/// UNORM quantization as GPUs define it (value = q / (2^bits - 1)), so that a texel written here
/// samples to the same value in OpenGL and Vulkan. Rounding is to nearest, out-of-range inputs are
/// clamped and NaN maps to 0, so the round-trip error for x in [0, 1] is at most half a step.
#pragma once

#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>

#include "cellrelief/core/math.h"

namespace cellrelief {

template <class U>
concept UnormStorage = std::same_as<U, std::uint8_t> || std::same_as<U, std::uint16_t>;

/// The largest code of U: 255 or 65535.
template <UnormStorage U>
constexpr double unormMax() {
  return static_cast<double>(std::numeric_limits<U>::max());
}

/// The spacing of representable values, 1 / (2^bits - 1).
template <UnormStorage U>
constexpr double unormStep() {
  return 1.0 / unormMax<U>();
}

/// Nearest code for x; clamps to [0, 1]; NaN gives 0.
template <UnormStorage U, Real T>
inline U quantizeUnorm(T x) {
  if (!(x > T(0))) return U(0);  // also catches NaN
  if (x >= T(1)) return std::numeric_limits<U>::max();
  return static_cast<U>(std::lround(static_cast<double>(x) * unormMax<U>()));
}

template <UnormStorage U, Real T = float>
constexpr T dequantizeUnorm(U q) {
  return static_cast<T>(static_cast<double>(q) / unormMax<U>());
}

/// Maps [lo, hi] onto UNORM codes (distances with their stored scale and offset). The largest error
/// of a round trip for values inside the range is maxError() = (hi - lo) / (2 (2^bits - 1)).
template <UnormStorage U, Real T = float>
struct RangeQuantizer {
  T lo = 0;
  T hi = 1;

  U encode(T x) const { return quantizeUnorm<U>((x - lo) / (hi - lo)); }
  T decode(U q) const { return lo + (hi - lo) * dequantizeUnorm<U, T>(q); }
  T maxError() const { return (hi - lo) * static_cast<T>(0.5 * unormStep<U>()); }
};

}  // namespace cellrelief
