// SPDX-License-Identifier: MIT
/// @file configuration.h
/// Faces, rotations and face configurations of a cubic cell, as compile-time tables.
///
/// A grey cell's configuration is a 6-bit mask of its external faces (faces shared with a white
/// cell or with the outside of the grid). The 24 rotations of the cube group the 64 masks into ten
/// base cases (Apaza & Andujar, section 3.1), named by the number of external faces and, where two
/// shapes share a count, a letter:
///
/// | case | external faces (canonical) | shape |
/// |---|---|---|
/// | 0  | none                 | interior grey cell (IG) |
/// | 1  | +z                   | one face |
/// | 2a | -z, +z               | two opposite faces |
/// | 2b | +x, +y               | two adjacent faces |
/// | 3a | -x, +x, +y           | a U: two opposite faces and one between |
/// | 3b | +x, +y, +z           | a corner: three mutually adjacent faces |
/// | 4a | +x, +y, -z, +z       | the two internal faces are adjacent |
/// | 4b | -x, +x, -y, +y       | a ring: the two internal faces are opposite |
/// | 5  | all but -z           | one internal face |
/// | 6  | all                  | an isolated cell |
///
/// Every configuration is `rotate(canonical(case), rotation)` for exactly one case and at least one
/// rotation; the tables keep the lowest-numbered such rotation.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "cellrelief/core/math.h"

namespace cellrelief::cells {

/// Faces of a cell: 0 = -x, 1 = +x, 2 = -y, 3 = +y, 4 = -z, 5 = +z.
inline constexpr int kFaceCount = 6;
constexpr int faceAxis(int face) { return face >> 1; }
constexpr int faceSign(int face) { return (face & 1) ? 1 : -1; }
constexpr int makeFace(int axis, int sign) { return 2 * axis + (sign > 0 ? 1 : 0); }
constexpr int oppositeFace(int face) { return face ^ 1; }
inline constexpr std::array<std::string_view, 6> kFaceNames{"-x", "+x", "-y", "+y", "-z", "+z"};

/// Outward unit normal of a face, as integers.
constexpr Vec3i faceNormal(int face) {
  Vec3i n(0);
  n[faceAxis(face)] = faceSign(face);
  return n;
}

enum class BaseCase : std::uint8_t { k0, k1, k2a, k2b, k3a, k3b, k4a, k4b, k5, k6 };
inline constexpr int kBaseCaseCount = 10;
inline constexpr std::array<std::string_view, 10> kBaseCaseNames{"0",  "1",  "2a", "2b", "3a",
                                                                  "3b", "4a", "4b", "5",  "6"};
constexpr std::string_view toString(BaseCase c) { return kBaseCaseNames[static_cast<int>(c)]; }

/// The canonical configuration of each base case (see the table above).
inline constexpr std::array<std::uint8_t, 10> kCanonicalConfiguration{
    0b000000,  // 0
    0b100000,  // 1:  +z
    0b110000,  // 2a: -z +z
    0b001010,  // 2b: +x +y
    0b001011,  // 3a: -x +x +y
    0b101010,  // 3b: +x +y +z
    0b111010,  // 4a: +x +y -z +z
    0b001111,  // 4b: -x +x -y +y
    0b101111,  // 5:  all but -z
    0b111111,  // 6
};

/// A rotation of the cube about its centre: a signed permutation matrix with determinant +1.
/// `m[row][column]`; it maps a direction d to m * d.
struct CubeRotation {
  std::array<std::array<std::int8_t, 3>, 3> m{};

  constexpr Vec3i apply(const Vec3i& d) const {
    Vec3i r(0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i] += m[i][j] * d[j];
    return r;
  }
  template <Real T>
  Vec3<T> apply(const Vec3<T>& d) const {
    Vec3<T> r(0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i] += T(m[i][j]) * d[j];
    return r;
  }
  /// The inverse rotation (the transpose).
  constexpr CubeRotation inverse() const {
    CubeRotation t;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t.m[i][j] = m[j][i];
    return t;
  }
  constexpr int applyToFace(int face) const {
    const int a = faceAxis(face);
    for (int i = 0; i < 3; ++i)
      if (m[i][a] != 0) return makeFace(i, faceSign(face) * m[i][a]);
    return face;
  }
  /// A point of the unit cell [0,1]^3, rotated about the cell centre.
  template <Real T>
  Vec3<T> applyToPoint(const Vec3<T>& p) const {
    return apply(p - Vec3<T>(T(0.5))) + Vec3<T>(T(0.5));
  }
};

namespace detail {
constexpr std::array<CubeRotation, 24> makeRotations() {
  std::array<CubeRotation, 24> out{};
  constexpr int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  constexpr int parity[6] = {1, -1, -1, 1, 1, -1};
  int n = 0;
  for (int p = 0; p < 6; ++p)
    for (int s = 0; s < 8; ++s) {
      const int sx = (s & 1) ? -1 : 1, sy = (s & 2) ? -1 : 1, sz = (s & 4) ? -1 : 1;
      if (parity[p] * sx * sy * sz != 1) continue;
      CubeRotation r;
      const int signs[3] = {sx, sy, sz};
      for (int row = 0; row < 3; ++row) r.m[row][perms[p][row]] = static_cast<std::int8_t>(signs[row]);
      out[n++] = r;
    }
  return out;
}
}  // namespace detail

/// The 24 rotations; index 0 is the identity.
inline constexpr std::array<CubeRotation, 24> kRotations = detail::makeRotations();

constexpr std::uint8_t rotateConfiguration(std::uint8_t configuration, int rotation) {
  std::uint8_t out = 0;
  for (int f = 0; f < kFaceCount; ++f)
    if (configuration & (1u << f)) out |= std::uint8_t(1u << kRotations[rotation].applyToFace(f));
  return out;
}

struct ConfigurationInfo {
  BaseCase baseCase = BaseCase::k0;
  std::uint8_t rotation = 0;  ///< rotate(canonical(baseCase), rotation) == the configuration
};

namespace detail {
constexpr std::array<ConfigurationInfo, 64> makeConfigurationTable() {
  std::array<ConfigurationInfo, 64> table{};
  std::array<bool, 64> seen{};
  for (int c = 0; c < kBaseCaseCount; ++c)
    for (int r = 0; r < 24; ++r) {
      const std::uint8_t config = rotateConfiguration(kCanonicalConfiguration[c], r);
      if (seen[config]) continue;
      seen[config] = true;
      table[config] = {static_cast<BaseCase>(c), static_cast<std::uint8_t>(r)};
    }
  return table;
}
}  // namespace detail

/// Base case and rotation of each of the 64 configurations.
inline constexpr std::array<ConfigurationInfo, 64> kConfigurationTable =
    detail::makeConfigurationTable();

constexpr int externalFaceCount(std::uint8_t configuration) {
  int n = 0;
  for (int f = 0; f < kFaceCount; ++f) n += (configuration >> f) & 1;
  return n;
}

/// Domain faces of a configuration: its external faces, or all six for an interior cell (case 0),
/// whose surface is reached only through neighbouring grey cells.
constexpr std::uint8_t domainFacesOf(std::uint8_t configuration) {
  return configuration == 0 ? std::uint8_t(0b111111) : std::uint8_t(configuration & 63);
}

static_assert(kRotations[0].applyToFace(5) == 5, "rotation 0 is the identity");
static_assert(kConfigurationTable[0b111111].baseCase == BaseCase::k6);
static_assert(kConfigurationTable[0b000011].baseCase == BaseCase::k2a);  // -x +x: opposite

}  // namespace cellrelief::cells
