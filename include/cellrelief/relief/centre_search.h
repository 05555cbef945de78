// SPDX-License-Identifier: MIT
/// @file centre_search.h
/// CentreOfProjection::FewestCrossings (beyond the paper): where a cell's projection lines meet
/// its surface more than once, move the centre (or axis) of projection along its free coordinates
/// to a point from which fewer do. A line keeps one distance, so the side past a second crossing
/// is misread: in an interior (case 0) cell whose centre lies between two sheets (a handle, a thin
/// part), every line through both reads the gap between them as filled, and the model gains
/// spurious handles (docs/relief.md measures it). Used by the conversion and by the occlusion
/// estimate of the grid search.
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

#include "cellrelief/core/bvh.h"
#include "cellrelief/projection/choice.h"

namespace cellrelief::relief {

namespace detail {

/// Whether the projection line `line` (a segment, t in [0, 1]) meets the surface again past its
/// first hit at t: a line keeps one distance, so the second crossing is lost and the side past it
/// misread. `surface`: the mesh's TriangleBvh, or the TrianglesInBox of the line's cell.
/// Where a second crossing past a first hit at t may begin: past the rounding of the first (a
/// line through an edge hits both triangles that share it, at t equal but for rounding).
inline double pastFirstHit(double t) { return t * (1 + 1e-9) + 1e-9; }

/// The first hit of the projection line `line` (a segment, t in [0, 1]) extended to t = `reach`,
/// and whether the line meets the surface again past it: a line keeps one distance, so the second
/// crossing is lost and the side past it misread. One query (closestHitAndNext) where a nearest
/// hit and then an any-hit query past it would descend twice. `surface`: the mesh's TriangleBvh,
/// or the TrianglesInBox of the line's cell.
template <class Surface>
FirstAndNextHit<double> firstHitAndCrossingAgain(const Surface& surface, const Rayd& line, double reach) {
  Rayd extended = line;
  extended.tmax = reach;
  return surface.closestHitAndNext(extended, line.tmax, pastFirstHit);
}

/// The projection line of a face point (cell units) as a world-space segment, t in [0, 1].
inline Rayd projectionLine(const projection::CellProjection<double>& proj, int face, const Vec3d& onFace,
                           const Vec3d& cellMin, double h) {
  return Rayd(cellMin + h * onFace, h * (proj.lineEnd(face, onFace) - onFace), 0.0, 1.0);
}

}  // namespace detail

/// How many of the S x S projection lines per domain face meet the surface more than once;
/// stops counting past `limit`. `surface`: the mesh's TriangleBvh, or the cell's TrianglesInBox.
template <class Surface>
int linesCrossedTwice(const Surface& surface, const projection::CellProjection<double>& proj,
                      const Vec3d& cellMin, double h, int S, int limit) {
  int count = 0;
  for (int f = 0; f < cells::kFaceCount; ++f) {
    if (!(proj.domainFaces() & (1u << f))) continue;
    for (int b = 0; b < S; ++b)
      for (int a = 0; a < S; ++a) {
        const Vec3d onFace = projection::facePoint(f, Vec2d(double(a) / (S - 1), double(b) / (S - 1)));
        const Rayd line = detail::projectionLine(proj, f, onFace, cellMin, h);
        if (detail::firstHitAndCrossingAgain(surface, line, line.tmax).next && ++count > limit) return count;
      }
  }
  return count;
}

/// The projections FewestCrossings tries for a configuration: its point on a 5^3 lattice of the
/// cell, moved along the free coordinates only (chooseProjection), nearest the canonical point
/// first. Parallel and planar projections, and points with no free coordinate, have one: the
/// canonical projection.
inline std::vector<projection::CellProjection<double>> centreCandidates(std::uint8_t configuration) {
  using projection::CentreOfProjection;
  const auto canonical = projection::chooseProjection<double>(configuration);
  std::vector<projection::CellProjection<double>> out{canonical};
  if (canonical.type == projection::ProjectionType::Parallel || canonical.type == projection::ProjectionType::Planar)
    return out;
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 5; ++x) {
        const Vec3d point = Vec3d(0.1 + 0.2 * x, 0.1 + 0.2 * y, 0.1 + 0.2 * z);
        const auto p = projection::chooseProjection<double>(configuration, CentreOfProjection::FewestCrossings, point);
        if (std::none_of(out.begin(), out.end(), [&](const auto& c) { return c.point == p.point; }))
          out.push_back(p);
      }
  std::stable_sort(out.begin(), out.end(), [&](const auto& a, const auto& b) {
    return glm::length(a.point - canonical.point) < glm::length(b.point - canonical.point);
  });
  return out;
}

/// CentreOfProjection::FewestCrossings: the candidate (centreCandidates) with the fewest lines
/// crossed twice on a 9 x 9 sampling of each domain face, the first, thus nearest the canonical
/// point, among equals; the search ends at the first candidate with none. `surface`: the mesh's
/// TriangleBvh, or the cell's TrianglesInBox.
template <class Surface>
projection::CellProjection<double> fewestCrossingsProjection(std::uint8_t configuration, const Surface& surface,
                                                             const Vec3d& cellMin, double h) {
  constexpr int kLines = 9;
  const auto candidates = centreCandidates(configuration);
  std::size_t best = 0;
  int fewest = std::numeric_limits<int>::max();
  for (std::size_t i = 0; i < candidates.size() && fewest > 0; ++i) {
    const int crossed = linesCrossedTwice(surface, candidates[i], cellMin, h, kLines, fewest - 1);
    if (crossed < fewest) {
      fewest = crossed;
      best = i;
    }
  }
  return candidates[best];
}

}  // namespace cellrelief::relief
