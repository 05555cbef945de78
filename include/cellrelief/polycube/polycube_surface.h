// SPDX-License-Identifier: MIT
/// @file polycube_surface.h
/// The polycube's surface as a place to put points: P over the whole lattice (a point near the
/// surface goes to the dual cell of its nearest lattice vertex, and that vertex's case projects
/// it), and the outward normal of the face a surface point lies on. This is what the
/// parameterization moves texture positions on and what a renderer's fragment does per hit.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "cellrelief/polycube/lookup_table.h"
#include "cellrelief/polycube/projection.h"

namespace cellrelief::polycube {

class PolycubeSurface {
 public:
  /// Throws InvalidArgument for an empty or non-manifold polycube (the look-up table's checks).
  explicit PolycubeSurface(Polycube polycube) : mPolycube(std::move(polycube)), mLut(mPolycube) {
    mArea = double(mPolycube.surfaceStats().faces);
  }

  const Polycube& polycube() const { return mPolycube; }
  const PolycubeLut& lut() const { return mLut; }
  /// Surface area in square cubes (the number of faces).
  double area() const { return mArea; }

  /// P: a point (lattice coordinates) onto the surface through the dual cell of its nearest
  /// lattice vertex. Meant for points within half a cube of the surface; nothing when that cell
  /// holds no surface (the point is deep inside or outside).
  std::optional<Vec3d> project(const Vec3d& p) const {
    const std::optional<Vec3i> vertex = nearestSurfaceVertex(p);
    if (!vertex) return std::nullopt;
    return Vec3d(*vertex) + polycube::project(mLut.at(*vertex).configuration, p - Vec3d(*vertex));
  }

  /// The outward unit normal at a surface point: the face's inside a face; on an edge or at a
  /// corner, the normalized sum of the faces meeting there (so every triangle lying in a face
  /// sees a positive component along that face's normal at each of its corners). A point off the
  /// surface is projected first; zero when that fails.
  Vec3d normal(const Vec3d& p, double tolerance = 1e-7) const {
    Vec3d n = faceNormalSum(p, tolerance);
    if (n == Vec3d(0.0))
      if (const std::optional<Vec3d> q = project(p)) n = faceNormalSum(*q, tolerance);
    const double length = glm::length(n);
    return length > 0 ? n / length : n;
  }

 private:
  /// The lattice vertex nearest to p, if its dual cell holds surface.
  std::optional<Vec3i> nearestSurfaceVertex(const Vec3d& p) const {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return std::nullopt;
    const Vec3d nearest = glm::floor(p + Vec3d(0.5));
    if (glm::any(glm::greaterThan(glm::abs(nearest), Vec3d(Polycube::kMaxCoordinate)))) return std::nullopt;
    if (mLut.at(Vec3i(nearest)).empty()) return std::nullopt;
    return Vec3i(nearest);
  }

  /// The sum of the outward normals of the squarelets of p's nearest vertex that hold p.
  Vec3d faceNormalSum(const Vec3d& p, double tolerance) const {
    Vec3d sum(0.0);
    const std::optional<Vec3i> vertex = nearestSurfaceVertex(p);
    if (!vertex) return sum;
    const LutEntry& entry = mLut.at(*vertex);
    const Vec3d d = p - Vec3d(*vertex);
    const std::uint16_t squarelets = entry.squarelets();
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(d[axis]) > tolerance) continue;
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      const int lo = std::min(a, b), hi = std::max(a, b);
      for (int quadrant = 0; quadrant < 4; ++quadrant) {
        const int loSide = quadrant & 1, hiSide = quadrant >> 1;
        // The squarelet holds p when p is on its side of both axes (or on the line between).
        if ((loSide ? d[lo] < -tolerance : d[lo] > tolerance) || (hiSide ? d[hi] < -tolerance : d[hi] > tolerance))
          continue;
        const int lower = (loSide << lo) | (hiSide << hi);  // the octant below the squarelet
        if (!(squarelets & (1u << squareletIndex(lower, axis)))) continue;
        sum[axis] += ((entry.configuration >> lower) & 1) ? 1.0 : -1.0;
      }
    }
    return sum;
  }

  Polycube mPolycube;
  PolycubeLut mLut;
  double mArea = 0;
};

}  // namespace cellrelief::polycube
