// SPDX-License-Identifier: MIT
/// @file surface_bounds.h
/// The box around a relief model's surface, the part of the grid where a ray can meet it. Every
/// tracer and shader clips rays to it instead of to the grid's cube: the cube is the mesh's
/// longest side on every axis, so a ray through the cube beside a flat or slender mesh searched
/// a grey cell for nothing (Igea at N = 1: one ray in five through the cube misses the box, and
/// the rest cross 31% less of it).
///
/// Why the box holds every crossing the tracers can find: a crossing is a zero of the field, so it
/// lies on the surface the samples rebuild. Between four samples that surface is the bilinear
/// blend of their distances along their lines: within the samples' box for parallel and planar
/// lines, and within a fraction of a sample of it for perspective and axial lines, whose
/// directions turn across a texel. Interior cells (case 0) also read an empty sample beside a
/// filled one as a distance at or before the face (ReliefTracer::mixedTexel), so their filled
/// samples' face points count too. Outside the box, then, a ray is outside the object (a closed
/// surface encloses its inside; an open one has none), and a ray that starts there starts
/// outside.
#pragma once

#include <algorithm>
#include <cmath>

#include "cellrelief/core/aabb.h"
#include "cellrelief/projection/projections.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::relief {

/// Sample spacings the box grows by on every side. Central lines turn across a texel, so the
/// surface between their samples bulges past the samples' box by about s^2 / (8 r) (s the spacing,
/// r the distance from the centre), under a hundredth of a spacing where r >= 0.1 cell at T = 33;
/// with the tracers' float rounding it stays well inside half a spacing. (The test finds the field
/// reading outside everywhere past the samples' own box, without the margin.)
inline constexpr double kSurfaceBoundsMarginSamples = 0.5;

namespace detail {

/// The cells' index range on each axis: only cells on its six outermost planes can hold the
/// box's faces, so only theirs are read sample by sample.
struct CellRange {
  Vec3i lo{1 << 30}, hi{-1};
  void extend(const Vec3i& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool onBoundary(const Vec3i& p) const {
    return glm::any(glm::equal(p, lo)) || glm::any(glm::equal(p, hi));
  }
};

/// The unit-cell box of one cell's filled samples: their surface points, and in interior cells
/// their face points too.
template <class Codes>
Aabbd cellSampleBounds(const ReliefModel& model, const Codes& codes, const CellRecord& record) {
  Aabbd box;
  const int texels = model.texels;
  const bool interior = record.configuration == 0;
  const std::uint32_t empty = model.distanceCodec.emptyCode();
  const double scale = model.distanceCodec.scale();
  record.projection<double>().visit([&](const auto& proj) {
    for (int f = 0; f < 6; ++f) {
      const int layer = record.layerOf(f);
      if (layer < 0) continue;
      for (int b = 0; b < texels; ++b)
        for (int a = 0; a < texels; ++a) {
          const std::uint32_t code = codes(layer, a, b);
          if (code >= empty) continue;
          const Vec2d uv(double(a) / (texels - 1), double(b) / (texels - 1));
          box.extend(proj.unproject(f, uv, double(code) * scale));
          if (interior) box.extend(projection::facePoint(f, uv));
        }
    }
  });
  return box;
}

}  // namespace detail

/// The world box that holds the model's surface (every zero of its field), grown by
/// kSurfaceBoundsMarginSamples sample spacings and clipped to the grid's cube; the cube itself
/// when the model has no filled sample.
inline Aabbd surfaceBoundsWS(const ReliefModel& model) {
  const Aabbd cube(model.originWS, model.originWS + Vec3d(model.cellSizeWS * model.gridSize));
  if (model.layerCount() == 0) return cube;
  detail::CellRange range;
  for (const CellRecord& r : model.cells)
    if (r.presentFaces != 0) range.extend(r.ijk());
  // A tracer reads a cell's field inside the cell only, so a cell off those planes adds its cube.
  // (The samples of parallel lines that look past the opposite face, convert.h, lie outside
  // their cell; the box may take them in, which only makes it larger.)
  const double spacing = 1.0 / double(std::max(1, model.texels - 1));
  Aabbd unit;  // in cell units from the origin
  model.visitDistanceCodes([&](const auto& codes) {
    for (const CellRecord& r : model.cells) {
      if (r.presentFaces == 0) continue;
      const Vec3d ijk(r.ijk());
      if (!range.onBoundary(r.ijk())) {
        unit.extend(Aabbd(ijk, ijk + Vec3d(1.0)));
        continue;
      }
      const Aabbd local = detail::cellSampleBounds(model, codes, r);
      if (!local.isEmpty()) unit.extend(Aabbd(ijk + local.min, ijk + local.max));
    }
  });
  if (unit.isEmpty()) return cube;
  const double margin = kSurfaceBoundsMarginSamples * spacing;
  Aabbd box(model.originWS + (unit.min - margin) * model.cellSizeWS,
            model.originWS + (unit.max + margin) * model.cellSizeWS);
  box.min = glm::clamp(box.min, cube.min, cube.max);
  box.max = glm::clamp(box.max, cube.min, cube.max);
  return box;
}

}  // namespace cellrelief::relief
