// SPDX-License-Identifier: MIT
/// @file geotex_model.h
/// A geometry-texture model (de Toledo, Wang, Levy, CGF 2008): charts, each an oriented box with a
/// height map inside it (the surface as heights above the box's base plane, along the box's z
/// axis) and a normal map and, where the mesh has colour, a colour map. All charts' texels sit in
/// one array per signal, as a GPU backend uploads them; a chart records where its texels start.
///
/// Chart coordinates: x in [0, width] and y in [0, height] in texels, z in world units above the
/// base plane, so a ray keeps its parameter t when it moves into a chart (the map is affine), and
/// texel (i, j) covers [i, i+1) x [j, j+1) with its sample at the centre.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/math.h"

namespace cellrelief::geotex {

/// Heights as unsigned codes of 8 or 16 bits over [0, the box's z size]: codes up to
/// largestCode() are heights, emptyCode() marks a texel no triangle of the chart covers.
struct HeightCodec {
  int bits = 16;

  static bool supports(int b) { return b == 8 || b == 16; }
  std::uint16_t emptyCode() const { return std::uint16_t((1u << bits) - 1); }
  std::uint16_t largestCode() const { return std::uint16_t((1u << bits) - 2); }
  int bytesPerCode() const { return bits / 8; }
  /// `fraction` of the box's z size, in [0, 1].
  std::uint16_t encode(double fraction) const {
    const double c = std::round(std::clamp(fraction, 0.0, 1.0) * largestCode());
    return std::uint16_t(c);
  }
  template <Real T>
  T decode(std::uint16_t code) const {
    return T(code) / T(largestCode());
  }
};

/// One chart's oriented box and the place of its maps.
struct ChartBox {
  Vec3d originWS{0};                                   ///< the box corner at chart (0, 0, 0)
  Vec3d axisWS[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  ///< orthonormal, right-handed; z = up
  Vec3d sizeWS{0};                                     ///< extent along each axis
  std::uint32_t width = 0, height = 0;                 ///< texels
  std::uint64_t firstTexel = 0;                        ///< texel (0, 0) in the model's arrays

  std::uint64_t texelCount() const { return std::uint64_t(width) * height; }
  /// World units per texel along x and y.
  Vec2d texelSizeWS() const { return {sizeWS.x / width, sizeWS.y / height}; }
  /// A world point in chart coordinates (texels in x and y, world units in z).
  Vec3d toChart(const Vec3d& pWS) const {
    const Vec3d d = pWS - originWS;
    return {glm::dot(d, axisWS[0]) * width / sizeWS.x, glm::dot(d, axisWS[1]) * height / sizeWS.y,
            glm::dot(d, axisWS[2])};
  }
  Vec3d toWorld(const Vec3d& pChart) const {
    return originWS + axisWS[0] * (pChart.x * sizeWS.x / width) +
           axisWS[1] * (pChart.y * sizeWS.y / height) + axisWS[2] * pChart.z;
  }
  /// The box's world-space bounds (its eight corners).
  Aabbd boundsWS() const {
    Aabbd box;
    for (int c = 0; c < 8; ++c)
      box.extend(originWS + axisWS[0] * ((c & 1) ? sizeWS.x : 0.0) +
                 axisWS[1] * ((c & 2) ? sizeWS.y : 0.0) + axisWS[2] * ((c & 4) ? sizeWS.z : 0.0));
    return box;
  }
};

/// The range of coordinates and sizes a model may hold: single precision keeps them apart from
/// zero and infinity, with room for the products a tracer forms.
inline constexpr double kMaxCoordinate = 1e30, kMinSize = 1e-30;

struct GeoTexModel {
  std::vector<ChartBox> charts;
  HeightCodec heightCodec;
  std::vector<std::uint16_t> heights;  ///< one code per texel (8-bit codes too, widened in memory)
  std::vector<std::uint32_t> normals;  ///< per texel, world-space octahedral, 2 x 16-bit UNORM (x low)
  std::vector<Color8> colors;          ///< per texel, RGBA8; empty when the mesh had no colour

  std::uint64_t texelCount() const { return heights.size(); }
  bool hasColors() const { return !colors.empty(); }
  Aabbd boundsWS() const {
    Aabbd box;
    for (const ChartBox& c : charts) box.extend(c.boundsWS());
    return box;
  }
  /// Bytes the representation needs on disk and on a GPU (8-bit heights count one byte).
  std::uint64_t byteSize() const;
  /// Throws Error(InvalidInput, `source`) naming the first broken invariant: array sizes, chart
  /// texel ranges that overlap or run past the arrays, axes that are not orthonormal, sizes that
  /// are not positive and finite, codes above the largest.
  void validate(const std::string& source = "geometry-texture model") const;
};

/// Bytes of one chart record in the file: origin, 3 axes and size as 15 doubles, width, height
/// and the first texel.
inline constexpr std::uint64_t kChartRecordBytes = 15 * 8 + 4 + 4 + 8;

inline std::uint64_t GeoTexModel::byteSize() const {
  return charts.size() * kChartRecordBytes + heights.size() * std::uint64_t(heightCodec.bytesPerCode()) +
         normals.size() * 4 + colors.size() * 4;
}

inline void GeoTexModel::validate(const std::string& source) const {
  auto fail = [&](const std::string& problem) { throw Error(ErrorKind::InvalidInput, source, problem); };
  if (!HeightCodec::supports(heightCodec.bits))
    fail("height bits " + std::to_string(heightCodec.bits) + " (8 or 16 are supported)");
  if (normals.size() != heights.size()) fail("the normal map's texel count differs from the height map's");
  if (!colors.empty() && colors.size() != heights.size())
    fail("the colour map's texel count differs from the height map's");
  std::uint64_t next = 0;
  for (std::size_t i = 0; i < charts.size(); ++i) {
    const ChartBox& c = charts[i];
    const std::string chart = "chart " + std::to_string(i) + ": ";
    if (c.width < 1 || c.height < 1 || c.width > 4096 || c.height > 4096)
      fail(chart + "map size " + std::to_string(c.width) + " x " + std::to_string(c.height) +
           " is outside 1 to 4096");
    if (c.firstTexel != next) fail(chart + "its texels do not follow the previous chart's");
    next += c.texelCount();
    if (next > heights.size()) fail(chart + "its texels run past the end of the maps");
    // Tracers and GPUs work in single precision: every value must keep its meaning there.
    const auto inFloatRange = [](double v) { return std::abs(v) <= kMaxCoordinate; };
    const auto sizeOk = [](double v) { return v >= kMinSize && v <= kMaxCoordinate; };
    if (!inFloatRange(c.originWS.x) || !inFloatRange(c.originWS.y) || !inFloatRange(c.originWS.z))
      fail(chart + "the box's corner is not a number within +-1e30");
    if (!sizeOk(c.sizeWS.x / c.width) || !sizeOk(c.sizeWS.y / c.height) || !sizeOk(c.sizeWS.z) ||
        !sizeOk(c.sizeWS.x) || !sizeOk(c.sizeWS.y))
      fail(chart + "the box's size or texel size is outside 1e-30 to 1e30");
    for (int a = 0; a < 3; ++a) {
      if (!isFinite(c.axisWS[a]) || std::abs(glm::length(c.axisWS[a]) - 1) > 1e-6)
        fail(chart + "axis " + std::to_string(a) + " is not of unit length");
      if (std::abs(glm::dot(c.axisWS[a], c.axisWS[(a + 1) % 3])) > 1e-6) fail(chart + "the axes are not orthogonal");
    }
    if (glm::dot(glm::cross(c.axisWS[0], c.axisWS[1]), c.axisWS[2]) < 0) fail(chart + "the axes are left-handed");
  }
  if (next != heights.size()) fail("the maps hold texels that no chart uses");
  const std::uint16_t largest = heightCodec.largestCode(), empty = heightCodec.emptyCode();
  for (std::size_t t = 0; t < heights.size(); ++t)
    if (heights[t] > largest && heights[t] != empty)
      fail("height code " + std::to_string(heights[t]) + " at texel " + std::to_string(t) +
           " is above the largest of " + std::to_string(heightCodec.bits) + " bits");
}

}  // namespace cellrelief::geotex
