// SPDX-License-Identifier: MIT
/// @file reconstruct.h
/// Geometry textures back to triangles, to measure them as surfaces: per chart, each filled
/// texel's centre at its height is a vertex (the tracer's surface passes through these points: it
/// interpolates texel centres bilinearly), and each 2 x 2 block of texels gives two triangles where
/// all four are filled, one where three are. In world space, facing the box's +z (outwards).
///
/// The charts' rings overlap their neighbours, so the result is the union of the charts, not one
/// manifold: it is for two-sided distances against the original mesh (metrics::surfaceError, the
/// RMS and Hausdorff error of the representation, as relief::reconstruct gives the cell complex's),
/// not for editing.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/geotex/geotex_model.h"

namespace cellrelief::geotex {

namespace detail {

/// Appends chart `c`'s filled texel centres and their triangles to `mesh`.
inline void appendChartSurface(const GeoTexModel& model, const ChartBox& c, TriangleMesh& mesh) {
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  const std::uint16_t empty = model.heightCodec.emptyCode();
  const std::uint32_t w = c.width, h = c.height;
  std::vector<std::uint32_t> vertexOf(std::size_t(w) * h, kNone);
  for (std::uint32_t j = 0; j < h; ++j)
    for (std::uint32_t i = 0; i < w; ++i) {
      const std::uint16_t code = model.heights[c.firstTexel + std::uint64_t(j) * w + i];
      if (code == empty) continue;
      const double x = (i + 0.5) / w * c.sizeWS.x, y = (j + 0.5) / h * c.sizeWS.y;
      const double z = model.heightCodec.decode<double>(code) * c.sizeWS.z;
      vertexOf[std::size_t(j) * w + i] = std::uint32_t(mesh.positions.size());
      mesh.positions.push_back(Vec3f(c.originWS + x * c.axisWS[0] + y * c.axisWS[1] + z * c.axisWS[2]));
    }
  for (std::uint32_t j = 0; j + 1 < h; ++j)
    for (std::uint32_t i = 0; i + 1 < w; ++i) {
      // Counter-clockwise seen from +z: (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1).
      const std::uint32_t corner[4] = {vertexOf[std::size_t(j) * w + i], vertexOf[std::size_t(j) * w + i + 1],
                                        vertexOf[std::size_t(j + 1) * w + i + 1], vertexOf[std::size_t(j + 1) * w + i]};
      std::uint32_t filled[4];
      int n = 0;
      for (const std::uint32_t v : corner)
        if (v != kNone) filled[n++] = v;
      if (n == 4) {
        mesh.triangles.push_back({corner[0], corner[1], corner[2]});
        mesh.triangles.push_back({corner[0], corner[2], corner[3]});
      } else if (n == 3) {
        mesh.triangles.push_back({filled[0], filled[1], filled[2]});
      }
    }
}

}  // namespace detail

/// The charts' surfaces as one triangle mesh (see the file comment); empty when no chart has a
/// 2 x 2 block with three filled texels.
inline TriangleMesh reconstruct(const GeoTexModel& model) {
  TriangleMesh mesh;
  for (const ChartBox& c : model.charts) detail::appendChartSurface(model, c, mesh);
  mesh.sourcePolygons = mesh.triangles.size();
  return mesh;
}

}  // namespace cellrelief::geotex
