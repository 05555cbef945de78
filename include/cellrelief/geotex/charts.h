// SPDX-License-Identifier: MIT
/// @file charts.h
/// From a VSA partition to charts: each region's triangles plus the paper's extra ring (the faces
/// that share a vertex with the region), so that neighbouring boxes overlap and no crack opens
/// between their height maps; and each chart's frame: z the median of its faces' normals, x and y
/// the principal axes (2D PCA) of its triangles projected on the plane across z, the box the
/// exact bounds of the chart's vertices (ring included) in that frame.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <numeric>
#include <span>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/geotex/vsa.h"

namespace cellrelief::geotex {

/// A chart's triangles: its own region first (`ownCount` of them), then the ring.
struct ChartFaces {
  std::vector<std::uint32_t> faces;
  std::size_t ownCount = 0;
};

/// The faces of every region, each widened by `rings` rings of faces around it (faces sharing a
/// vertex, with vertices identified by position as in the partition).
inline std::vector<ChartFaces> chartFaces(const TriangleMesh& mesh, const VsaPartition& partition,
                                          int rings = 1) {
  const std::size_t nf = mesh.triangles.size(), charts = partition.proxies.size();
  std::vector<ChartFaces> result(charts);
  for (std::uint32_t f = 0; f < nf; ++f) result[partition.regionOfFace[f]].faces.push_back(f);
  for (ChartFaces& c : result) c.ownCount = c.faces.size();
  if (rings <= 0) return result;
  // Faces around each (welded) vertex.
  const std::vector<std::uint32_t> weld = weldByPosition(mesh);
  std::vector<std::uint32_t> start(mesh.positions.size() + 1, 0), fan(3 * nf);
  for (const Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++start[weld[t[k]] + 1];
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) start[v + 1] += start[v];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) fan[fill[weld[mesh.triangles[f][k]]]++] = f;
  }
  parallelFor(0, charts, [&](std::size_t c) {
    // A sorted copy of the chart's faces tells which neighbours are new (no shared marks to race on).
    std::vector<std::uint32_t>& faces = result[c].faces;
    std::vector<std::uint32_t> sorted(faces.begin(), faces.end());
    std::sort(sorted.begin(), sorted.end());
    std::size_t frontier = 0;
    for (int ring = 0; ring < rings; ++ring) {
      const std::size_t end = faces.size();
      std::vector<std::uint32_t> added;
      for (std::size_t i = frontier; i < end; ++i)
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t v = weld[mesh.triangles[faces[i]][k]];
          for (std::uint32_t j = start[v]; j < start[v + 1]; ++j) added.push_back(fan[j]);
        }
      std::sort(added.begin(), added.end());
      added.erase(std::unique(added.begin(), added.end()), added.end());
      std::vector<std::uint32_t> fresh;
      std::set_difference(added.begin(), added.end(), sorted.begin(), sorted.end(), std::back_inserter(fresh));
      frontier = end;
      faces.insert(faces.end(), fresh.begin(), fresh.end());
      std::vector<std::uint32_t> merged;
      std::merge(sorted.begin(), sorted.end(), fresh.begin(), fresh.end(), std::back_inserter(merged));
      sorted.swap(merged);
    }
  }, 1);
  return result;
}

/// The geometric median of unit normals weighted by area (Weiszfeld's iteration from the mean),
/// normalized: unlike the mean it is not pulled by the few faces of a fold or a sharp edge.
inline Vec3d medianNormal(const TriangleMesh& mesh, std::span<const std::uint32_t> faces,
                          const Vec3d& fallback) {
  std::vector<Vec3d> normals;
  std::vector<double> weights;
  Vec3d mean(0);
  for (const std::uint32_t f : faces) {
    const Vec3u& t = mesh.triangles[f];
    const Vec3d n = glm::cross(Vec3d(mesh.positions[t[1]]) - Vec3d(mesh.positions[t[0]]),
                               Vec3d(mesh.positions[t[2]]) - Vec3d(mesh.positions[t[0]]));
    const double twiceArea = glm::length(n);
    if (!(twiceArea > 0)) continue;
    normals.push_back(n / twiceArea);
    weights.push_back(twiceArea);
    mean += n;
  }
  if (!(glm::length(mean) > 0)) return fallback;
  Vec3d m = mean / std::accumulate(weights.begin(), weights.end(), 0.0);
  for (int iteration = 0; iteration < 32; ++iteration) {
    Vec3d sum(0);
    double weightSum = 0;
    for (std::size_t i = 0; i < normals.size(); ++i) {
      const double w = weights[i] / std::max(glm::length(normals[i] - m), 1e-9);
      sum += w * normals[i];
      weightSum += w;
    }
    const Vec3d next = sum / weightSum;
    const bool settled = glm::length(next - m) < 1e-9;
    m = next;
    if (settled) break;
  }
  return glm::length(m) > 0 ? glm::normalize(m) : fallback;
}

/// The chart's frame and tight box (before any padding), with z = `up`.
struct ChartFrame {
  Vec3d axis[3];
  Vec3d minimum{0}, maximum{0};  ///< bounds of the chart's vertices along the axes
};

/// z = `up`; x and y the principal axes of the chart's triangles projected on the plane across z
/// (area-weighted second moments, so a dense patch of small triangles does not dominate).
inline ChartFrame chartFrame(const TriangleMesh& mesh, std::span<const std::uint32_t> faces, const Vec3d& up) {
  ChartFrame frame;
  const Vec3d z = glm::normalize(up);
  // Any basis of the plane, then rotate it onto the principal axes.
  const Vec3d helper = std::abs(z.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
  const Vec3d u = glm::normalize(glm::cross(helper, z)), v = glm::cross(z, u);
  double area = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (const std::uint32_t f : faces) {
    const Vec3u& t = mesh.triangles[f];
    Vec2d p[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3d q(mesh.positions[t[k]]);
      p[k] = {glm::dot(q, u), glm::dot(q, v)};
    }
    const double a = 0.5 * std::abs((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y));
    const Vec2d c = (p[0] + p[1] + p[2]) / 3.0;
    // Exact second moments of the projected triangle: A/12 (sum p p^T + 9 c c^T).
    double mxx = 9 * c.x * c.x, myy = 9 * c.y * c.y, mxy = 9 * c.x * c.y;
    for (int k = 0; k < 3; ++k) {
      mxx += p[k].x * p[k].x;
      myy += p[k].y * p[k].y;
      mxy += p[k].x * p[k].y;
    }
    area += a;
    sx += a * c.x;
    sy += a * c.y;
    sxx += a / 12 * mxx;
    syy += a / 12 * myy;
    sxy += a / 12 * mxy;
  }
  double angle = 0;
  if (area > 0) {
    const double cx = sx / area, cy = sy / area;
    const double cxx = sxx - area * cx * cx, cyy = syy - area * cy * cy, cxy = sxy - area * cx * cy;
    angle = 0.5 * std::atan2(2 * cxy, cxx - cyy);  // the major axis
  }
  frame.axis[0] = std::cos(angle) * u + std::sin(angle) * v;
  frame.axis[2] = z;
  frame.axis[1] = glm::cross(z, frame.axis[0]);
  Aabbd bounds;
  for (const std::uint32_t f : faces)
    for (int k = 0; k < 3; ++k) {
      const Vec3d q(mesh.positions[mesh.triangles[f][k]]);
      bounds.extend(Vec3d(glm::dot(q, frame.axis[0]), glm::dot(q, frame.axis[1]), glm::dot(q, frame.axis[2])));
    }
  frame.minimum = bounds.min;
  frame.maximum = bounds.max;
  return frame;
}

}  // namespace cellrelief::geotex
