// SPDX-License-Identifier: MIT
/// @file geometric_error.h
/// Geometric error between two surfaces: two-sided Hausdorff and RMS distance, measured by
/// area-uniform point samples on each surface and exact closest-point queries (BVH) on the other,
/// reported in world units and as a fraction of a reference diagonal. The library's own measure,
/// used to drive error-bounded conversion; the tests cross-check it against CGAL's AABB tree.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/combinable.h>

#include "cellrelief/core/bvh.h"
#include "cellrelief/core/low_discrepancy.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief::metrics {

struct OneSidedError {
  double max = 0;     ///< largest sample distance
  double rms = 0;     ///< root mean square, area-weighted
  double mean = 0;
  std::size_t samples = 0;
};

struct SurfaceError {
  OneSidedError aToB, bToA;
  double hausdorff() const { return std::max(aToB.max, bToA.max); }
  /// RMS over both directions, each weighted by its sample count (both are area-uniform).
  double rms() const {
    const double n = double(aToB.samples + bToA.samples);
    return n > 0 ? std::sqrt((aToB.rms * aToB.rms * aToB.samples + bToA.rms * bToA.rms * bToA.samples) / n)
                 : 0.0;
  }
};

/// `count` area-uniform points on the mesh (deterministic: stratified by triangle, R2 inside).
inline std::vector<Vec3d> sampleSurface(const TriangleMesh& mesh, std::size_t count) {
  std::vector<double> cumulative(mesh.triangles.size() + 1, 0.0);
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Vec3u& t = mesh.triangles[f];
    const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
    cumulative[f + 1] = cumulative[f] + 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  std::vector<Vec3d> out;
  const double total = cumulative.back();
  if (total <= 0 || count == 0) return out;
  out.resize(count);
  parallelFor(0, count, [&](std::size_t i) {
    const double target = (double(i) + 0.5) / double(count) * total;
    const std::size_t f = std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), target) -
                                      cumulative.begin()) - 1;
    const Vec3u& t = mesh.triangles[std::min(f, mesh.triangles.size() - 1)];
    out[i] = pointInTriangle(Vec3d(mesh.positions[t[0]]), Vec3d(mesh.positions[t[1]]),
                             Vec3d(mesh.positions[t[2]]), r2Point(i + 1));
  });
  return out;
}

/// Distances from points to a surface given by its BVH.
inline OneSidedError pointsToSurface(const std::vector<Vec3d>& points, const TriangleBvh<double>& bvh) {
  struct Acc {
    double max = 0, sum = 0, sum2 = 0;
  };
  tbb::combinable<Acc> acc;
  parallelFor(0, points.size(), [&](std::size_t i) {
    const double d = std::sqrt(bvh.closestPoint(points[i]).first);
    Acc& a = acc.local();
    a.max = std::max(a.max, d);
    a.sum += d;
    a.sum2 += d * d;
  }, 256);
  Acc total;
  acc.combine_each([&](const Acc& a) {
    total.max = std::max(total.max, a.max);
    total.sum += a.sum;
    total.sum2 += a.sum2;
  });
  OneSidedError e;
  e.samples = points.size();
  if (!points.empty()) {
    e.max = total.max;
    e.mean = total.sum / double(points.size());
    e.rms = std::sqrt(total.sum2 / double(points.size()));
  }
  return e;
}

/// A surface prepared for repeated distance queries (the original mesh, measured many times).
using DistanceField = MeshBvh;

/// Two-sided error between meshes a and b with `samplesPerSide` points on each.
inline SurfaceError surfaceError(const TriangleMesh& a, const DistanceField& aField,
                                 const TriangleMesh& b, std::size_t samplesPerSide = 200000) {
  const DistanceField bField(b);
  SurfaceError e;
  e.aToB = pointsToSurface(sampleSurface(a, samplesPerSide), bField.bvh);
  e.bToA = pointsToSurface(sampleSurface(b, samplesPerSide), aField.bvh);
  return e;
}

}  // namespace cellrelief::metrics
