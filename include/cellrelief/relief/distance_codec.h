// SPDX-License-Identifier: MIT
/// @file distance_codec.h
/// The distance texel format of a relief model, in one place: codes zeroCode..maxCode() stand for
/// distances spread evenly over [0, distanceMax] cell units, codes below zeroCode for distances
/// before the face (the same step: interior cells keep there where the surface crosses an empty
/// line's continuation outside the cell), and emptyCode() (the largest code) for a projection line
/// that met no surface. The width (8 or 16 bits) is chosen once per model;
/// conversion encodes with it, the model, its file, the tracer and its pyramid decode with it, and
/// inner loops read the codes through DistanceCodes<Code>, whose width is a type, so reading a
/// sample has no branch on it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace cellrelief::relief {

struct DistanceCodec {
  int bits = 16;              ///< 8 or 16
  float distanceMax = 0;      ///< the distance maxCode() stands for, in cell units
  std::uint32_t zeroCode = 0; ///< the code of distance 0; the codes below it stand for negative distances

  static constexpr bool supports(int bits) { return bits == 8 || bits == 16; }
  /// The code of a sample without surface.
  std::uint32_t emptyCode() const { return (1u << bits) - 1u; }
  /// The code that stands for distanceMax.
  std::uint32_t maxCode() const { return emptyCode() - 1u; }
  bool isEmpty(std::uint32_t code) const { return code >= emptyCode(); }
  /// A code of a line that met the surface within its reach (not empty, not before the face).
  bool hasSurface(std::uint32_t code) const { return code >= zeroCode && code < emptyCode(); }
  /// A zero code that leaves room for distances down to -before (cell units) below 0 and keeps
  /// distanceMax at maxCode(): round up, so that -before is representable.
  static std::uint32_t zeroCodeFor(int bits, double distanceMax, double before) {
    const double maxCode = double((1u << bits) - 2u);
    if (!(before > 0) || !(distanceMax > 0)) return 0;
    return std::uint32_t(std::min(maxCode / 2, std::ceil(maxCode * before / (distanceMax + before))));
  }
  /// Cell units per code step (0 for a model without distances).
  double scale() const {
    return distanceMax > 0 && zeroCode < maxCode() ? double(distanceMax) / double(maxCode() - zeroCode) : 0.0;
  }
  /// The smallest distance a code stands for (0 unless zeroCode > 0).
  double distanceMin() const { return -double(zeroCode) * scale(); }
  /// The distance of a code, in cell units; NaN for the empty code.
  float decode(std::uint32_t code) const {
    return isEmpty(code) ? std::numeric_limits<float>::quiet_NaN()
                         : float((double(code) - double(zeroCode)) * scale());
  }
  /// The nearest code of a distance in [distanceMin(), distanceMax] (clamped to the range). A
  /// negative distance stays before the face: below zeroCode when there are such codes, so that
  /// hasSurface() and the sign agree.
  std::uint32_t encode(double distance) const {
    const double s = scale();
    if (!(s > 0)) return zeroCode;
    const double steps = distance / s + double(zeroCode);
    if (!(steps > 0)) return 0;
    const std::uint32_t code = std::min<std::uint32_t>(maxCode(), std::uint32_t(std::lround(steps)));
    return distance < 0 && zeroCode > 0 ? std::min(code, zeroCode - 1) : code;
  }
  /// Largest error of the quantization, in cell units.
  double quantizationError() const { return 0.5 * scale(); }
  std::size_t bytesPerCode() const { return std::size_t(bits) / 8; }
};

/// The level-0 codes of a model's distance layers, read in place: `Code` is the width the model
/// stores (std::uint8_t or std::uint16_t). ReliefModel::visitDistanceCodes hands one over.
template <class Code>
struct DistanceCodes {
  const Code* data = nullptr;
  std::size_t texels = 0;
  std::uint32_t operator()(int layer, int a, int b) const {
    return data[(std::size_t(layer) * texels + std::size_t(b)) * texels + std::size_t(a)];
  }
};

}  // namespace cellrelief::relief
