// SPDX-License-Identifier: MIT
/// @file grid.h
/// The parameterization both optimizers produce: the map M from texture space (s, t) in [0, 1]^2 to
/// the base plane (u, v) of the relief, sampled at the (g+1)^2 vertices of a regular grid in texture
/// space; vertex (i, j) sits at texture (i / g, j / g) and stores M there.
///
/// Between vertices M is *piecewise linear* on two triangles per cell, split along the diagonal
/// (i, j)-(i+1, j+1). Everything downstream uses this same split: the distortion measure, the flip
/// count, the inverse rasterized into the indirection map and the refinement from g to 2g. With one
/// convention the round trip M(M^-1(x)) = x is exact to rounding, and refining a flip-free grid
/// keeps it flip-free (every fine triangle lies inside one coarse triangle, where M is linear).
/// Coordinates are stored structure-of-arrays in float: the spring loop streams them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/math.h"

namespace cellrelief::indirection {

/// Largest grid resolution accepted: (g+1)^2 vertices must stay a sane amount of memory and work.
inline constexpr int kMaxGridSize = 4096;

/// Throws a clear error unless 2 <= g <= kMaxGridSize.
inline void checkGridSize(int g) {
  if (g < 2 || g > kMaxGridSize)
    throw Error(ErrorKind::InvalidArgument,
                "grid size g = " + std::to_string(g) + " is out of range (2 to " +
                    std::to_string(kMaxGridSize) + " cells a side)");
}

class Grid {
 public:
  Grid() = default;
  /// The identity map at resolution g.
  explicit Grid(int g) : mG(g) {
    checkGridSize(g);
    const std::size_t n = std::size_t(g + 1) * (g + 1);
    mU.resize(n);
    mV.resize(n);
    for (int j = 0; j <= g; ++j)
      for (int i = 0; i <= g; ++i) {
        mU[index(i, j)] = float(i) / float(g);
        mV[index(i, j)] = float(j) / float(g);
      }
  }

  int g() const { return mG; }
  int side() const { return mG + 1; }
  std::size_t vertexCount() const { return mU.size(); }
  std::size_t index(int i, int j) const { return std::size_t(j) * (mG + 1) + i; }
  Vec2f vertex(int i, int j) const { return {mU[index(i, j)], mV[index(i, j)]}; }
  void setVertex(int i, int j, Vec2f p) {
    mU[index(i, j)] = p.x;
    mV[index(i, j)] = p.y;
  }
  std::vector<float>& u() { return mU; }
  std::vector<float>& v() { return mV; }
  const std::vector<float>& u() const { return mU; }
  const std::vector<float>& v() const { return mV; }

  /// M(s, t): piecewise linear on the cell's two triangles. (s, t) is clamped to [0, 1]^2.
  Vec2f map(Vec2f st) const {
    const float x = std::clamp(st.x, 0.0f, 1.0f) * float(mG);
    const float y = std::clamp(st.y, 0.0f, 1.0f) * float(mG);
    const int i = std::min(int(x), mG - 1), j = std::min(int(y), mG - 1);
    const float a = x - float(i), b = y - float(j);
    const Vec2f p00 = vertex(i, j), p11 = vertex(i + 1, j + 1);
    if (a >= b) {  // lower triangle (i,j), (i+1,j), (i+1,j+1)
      const Vec2f p10 = vertex(i + 1, j);
      return p00 + a * (p10 - p00) + b * (p11 - p10);
    }
    const Vec2f p01 = vertex(i, j + 1);  // upper triangle (i,j), (i+1,j+1), (i,j+1)
    return p00 + b * (p01 - p00) + a * (p11 - p01);
  }

  /// The same map at resolution `g`, sampled from this one (used to go from g to 2g).
  Grid resampled(int g) const {
    Grid out(g);
    for (int j = 0; j <= g; ++j)
      for (int i = 0; i <= g; ++i)
        out.setVertex(i, j, map({float(i) / float(g), float(j) / float(g)}));
    return out;
  }

  /// True when every coordinate is a finite number.
  bool isFinite() const {
    return std::all_of(mU.begin(), mU.end(), [](float x) { return std::isfinite(x); }) &&
           std::all_of(mV.begin(), mV.end(), [](float x) { return std::isfinite(x); });
  }

 private:
  int mG = 0;
  std::vector<float> mU, mV;
};

/// Twice the signed area of the triangle (a, b, c) in the base plane (positive: counter-clockwise).
inline float signedArea2(Vec2f a, Vec2f b, Vec2f c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// The two triangles of cell (i, j), as vertex offsets (di, dj): lower, then upper.
inline constexpr int kCellTriangles[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};

}  // namespace cellrelief::indirection
