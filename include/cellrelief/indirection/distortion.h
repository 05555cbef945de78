// SPDX-License-Identifier: MIT
/// @file distortion.h
/// One distortion measure for every optimizer, computed on the displaced relief surface (not the
/// base plane): for each triangle of each grid cell, the singular values s1 >= s2 of the Jacobian of
/// texture space -> surface, (s, t) -> R(M(s, t)), whose corners are R at the grid vertices.
///
/// The Jacobian is first scaled so that the total surface area equals the texture area (1), so a
/// perfect parameterization has s1 = s2 = 1 everywhere. Then
///   angle distortion  (s1/s2 + s2/s1) / 2            (1 when conformal)
///   area distortion   (s1 s2 + 1/(s1 s2)) / 2        (1 when area-preserving)
///   L2 stretch        sqrt(sum_T A_T (s1^2 + s2^2)/2 / sum_T A_T) with texture areas A_T
///                     (Sander et al. 2001; 1 when isometric, and it sees both of the above)
/// Angle and area are averaged with the triangles' *surface* areas as weights (what a viewer sees)
/// and their maxima reported. A triangle whose base-plane orientation is not positive is flipped;
/// a cell with a flipped triangle counts once. The comparison app plots L2 stretch against time.
/// Per grid cell means over the surface through R at the cell's corners; measureDistortion can also
/// subdivide cells down to the texels, to show the sub-cell relief that no grid of that g can fix.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>

#include <tbb/parallel_reduce.h>
#include <tbb/blocked_range.h>

#include "cellrelief/indirection/grid.h"
#include "cellrelief/indirection/relief_map.h"

namespace cellrelief::indirection {

struct Distortion {
  double angleMean = 1, angleMax = 1;  ///< (s1/s2 + s2/s1)/2, surface-area weighted
  double areaMean = 1, areaMax = 1;    ///< (s1 s2 + 1/(s1 s2))/2 after area normalization
  double l2Stretch = 1;                ///< Sander's L2 stretch after area normalization
  double surfaceArea = 0;              ///< of the piecewise-linear surface the grid spans
  std::size_t flippedCells = 0;        ///< cells with a non-positively oriented triangle
  std::size_t cells = 0;
};

namespace detail {
struct DistortionSums {
  double area = 0, angle = 0, areaDist = 0, stretch = 0, angleMax = 1, areaMax = 1;
  std::size_t flipped = 0;
  void join(const DistortionSums& o) {
    area += o.area;
    angle += o.angle;
    areaDist += o.areaDist;
    stretch += o.stretch;
    angleMax = std::max(angleMax, o.angleMax);
    areaMax = std::max(areaMax, o.areaMax);
    flipped += o.flipped;
  }
};
}  // namespace detail

namespace detail {
inline Distortion measureOnTriangles(const Grid& grid, const ReliefMap& relief);
}

/// The distortion of `grid` on `relief` (see the file comment), per grid cell: the default. With
/// `subdivisions` > 1 each cell is measured as `subdivisions`^2 sub-cells of the same
/// piecewise-linear M, which adds the relief detail inside the cells that no g x g grid can adapt
/// to. 0 picks two sub-cells per texel the cell spans (at most 8): sub-vertices one texel apart
/// would sit at fixed offsets to the texel centres and alias (measured on the Sponza lion at
/// 128^2 and g = 32: with one per texel the identity sits on the texel corners, where the bilinear
/// relief is smoothest, and measures 1.033; with two, 1.109; with four, 1.105). The sub-grid is
/// capped at kMaxGridSize a side. Flips are always counted on the grid itself.
inline Distortion measureDistortion(const Grid& grid, const ReliefMap& relief, int subdivisions = 1) {
  if (subdivisions <= 0)
    subdivisions = std::clamp(
        int(std::lround(2.0 * std::max(relief.width(), relief.height()) / grid.g())), 1, 8);
  subdivisions = std::min(subdivisions, std::max(1, kMaxGridSize / grid.g()));
  if (subdivisions == 1) return detail::measureOnTriangles(grid, relief);
  Distortion d = detail::measureOnTriangles(grid.resampled(grid.g() * subdivisions), relief);
  const Distortion coarse = detail::measureOnTriangles(grid, relief);
  d.flippedCells = coarse.flippedCells;
  d.cells = coarse.cells;
  return d;
}

inline Distortion detail::measureOnTriangles(const Grid& grid, const ReliefMap& relief) {
  const int g = grid.g();
  const std::size_t nv = grid.vertexCount();
  std::vector<float> z(nv);
  for (std::size_t k = 0; k < nv; ++k) z[k] = relief.heightAt(grid.u()[k], grid.v()[k]);
  auto point = [&](int i, int j) {
    const std::size_t k = grid.index(i, j);
    return Vec3d(grid.u()[k], grid.v()[k], z[k]);
  };
  // Per triangle: a = dP/ds, b = dP/dt (texture edges of length 1/g, so multiply by g).
  auto jacobian = [&](int i, int j, int t, Vec3d& a, Vec3d& b) {
    if (t == 0) {
      a = (point(i + 1, j) - point(i, j)) * double(g);
      b = (point(i + 1, j + 1) - point(i + 1, j)) * double(g);
    } else {
      a = (point(i + 1, j + 1) - point(i, j + 1)) * double(g);
      b = (point(i, j + 1) - point(i, j)) * double(g);
    }
  };
  const double texArea = 0.5 / (double(g) * g);
  // Pass 1: the surface area, for the normalization.
  double area = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, g), 0.0,
      [&](const tbb::blocked_range<int>& r, double sum) {
        for (int j = r.begin(); j != r.end(); ++j)
          for (int i = 0; i < g; ++i)
            for (int t = 0; t < 2; ++t) {
              Vec3d a, b;
              jacobian(i, j, t, a, b);
              sum += glm::length(glm::cross(a, b)) * texArea;
            }
        return sum;
      },
      std::plus<double>());
  Distortion d;
  d.surfaceArea = area;
  d.cells = std::size_t(g) * g;
  if (!(area > 0)) return d;
  const double norm2 = 1.0 / area;  // scales |J|^2 so the total area is 1
  const detail::DistortionSums s = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, g), detail::DistortionSums{},
      [&](const tbb::blocked_range<int>& r, detail::DistortionSums sums) {
        for (int j = r.begin(); j != r.end(); ++j)
          for (int i = 0; i < g; ++i) {
            bool flipped = false;
            for (int t = 0; t < 2; ++t) {
              const auto& tri = kCellTriangles[t];
              const Vec2f p0 = grid.vertex(i + tri[0][0], j + tri[0][1]);
              const Vec2f p1 = grid.vertex(i + tri[1][0], j + tri[1][1]);
              const Vec2f p2 = grid.vertex(i + tri[2][0], j + tri[2][1]);
              if (!(signedArea2(p0, p1, p2) > 0)) flipped = true;
              Vec3d a, b;
              jacobian(i, j, t, a, b);
              const double e = glm::dot(a, a) * norm2, gg = glm::dot(b, b) * norm2;
              const double sigma = glm::length(glm::cross(a, b)) * norm2;  // s1 s2
              const double w = sigma * texArea;                             // surface area
              sums.stretch += 0.5 * (e + gg) * texArea;
              if (sigma <= 1e-300) {
                sums.angleMax = sums.areaMax = HUGE_VAL;
                continue;
              }
              const double angle = (e + gg) / (2 * sigma);
              const double areaDist = 0.5 * (sigma + 1 / sigma);
              sums.area += w;
              sums.angle += w * angle;
              sums.areaDist += w * areaDist;
              sums.angleMax = std::max(sums.angleMax, angle);
              sums.areaMax = std::max(sums.areaMax, areaDist);
            }
            sums.flipped += flipped;
          }
        return sums;
      },
      [](detail::DistortionSums x, const detail::DistortionSums& y) {
        x.join(y);
        return x;
      });
  d.flippedCells = s.flipped;
  if (s.area > 0) {
    d.angleMean = s.angle / s.area;
    d.areaMean = s.areaDist / s.area;
  }
  d.angleMax = s.angleMax;
  d.areaMax = s.areaMax;
  d.l2Stretch = std::sqrt(s.stretch / (2 * texArea * d.cells));
  return d;
}

}  // namespace cellrelief::indirection
