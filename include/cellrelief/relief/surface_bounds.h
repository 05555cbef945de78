// SPDX-License-Identifier: MIT
/// @file surface_bounds.h
/// Where a ray can meet a relief model's surface: the surface's box over the whole grid
/// (surfaceBoundsWS) and, per grey cell, the box where its field can change side (CellReach).
///
/// The box around a relief model's surface, the part of the grid where a ray can meet it. Every
/// tracer and shader clips rays to it instead of to the grid's cube: the cube is the mesh's
/// longest side on every axis, so a ray through the cube beside a flat or slender mesh searched
/// a grey cell for nothing (Igea at N = 1, 512 x 512 primary rays: one in five of those through
/// the cube misses the mesh's box, and they cross 31% less of the box than of the cube).
///
/// Why the box holds every crossing the tracers can find: a crossing is a zero of the field, so it
/// lies on the surface the samples rebuild. Between four samples that surface is the bilinear
/// blend of their distances along their lines: within the samples' box for parallel and planar
/// lines, and within a fraction of a sample of it for perspective and axial lines, whose
/// directions turn across a texel. Interior cells (case 0) also read an empty sample beside a
/// filled one as a distance at or before the face (ReliefTracer::mixedTexel), so their filled
/// samples' face points count too. The field also jumps where a filled line meets an empty one
/// (CellReach says where); such a jump bounds a region read as inside, which surface of this or
/// other cells encloses. Outside the box, then, a ray is outside the object (a closed surface
/// encloses its inside; an open one has none), and a ray that starts there starts outside; the
/// test probes every grey cell's part outside the box for a field read as inside.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/projection/projections.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::relief {

/// Sample spacings the box grows by on every side. Central lines turn across a texel, so the
/// surface between their samples bulges past the samples' box by about s^2 / (8 r) (s the spacing,
/// r the distance from the centre), under a hundredth of a spacing where r >= 0.1 cell at T = 33;
/// with the tracers' float rounding it stays well inside half a spacing. (The test finds the field
/// reading outside everywhere past the samples' own box, without the margin.)
inline constexpr double kSurfaceBoundsMarginSamples = 0.5;

/// Where in one grey cell its field can change sign, as a unit-cell box in 8-bit fixed point
/// (rounded outwards, clipped to the cell), two 32-bit words as the GPU reads them: lo x, y, z and
/// hi x in the bytes of the first, hi y and z in the low bytes of the second. A ray's segment in
/// the cell that misses it reads one side of the surface all along, so the tracers take the
/// fewest linear steps there (trace::constants::kLinearStepsOutsideReach: the exit, which
/// carries the side on), not a search.
struct CellReach {
  std::uint32_t words[2] = {0x00ffffffu, 0};  ///< the empty box: lo 255 > hi 0

  static CellReach of(const Aabbd& unit) {
    CellReach r;
    if (unit.isEmpty()) return r;
    auto down = [](double x) { return std::uint32_t(std::clamp(std::floor(x * 255.0), 0.0, 255.0)); };
    auto up = [](double x) { return std::uint32_t(std::clamp(std::ceil(x * 255.0), 0.0, 255.0)); };
    r.words[0] = down(unit.min.x) | down(unit.min.y) << 8 | down(unit.min.z) << 16 | up(unit.max.x) << 24;
    r.words[1] = up(unit.max.y) | up(unit.max.z) << 8;
    return r;
  }
  Vec3f lo() const {
    return Vec3f(float(words[0] & 255u), float((words[0] >> 8) & 255u), float((words[0] >> 16) & 255u)) / 255.0f;
  }
  Vec3f hi() const {
    return Vec3f(float(words[0] >> 24), float(words[1] & 255u), float((words[1] >> 8) & 255u)) / 255.0f;
  }
  /// Narrows [t0, t1] to the part of the segment origin + t direction (unit-cell coordinates)
  /// inside the box; false when none is. The slab test of core/aabb.h, written as the shader's
  /// clipToReach is.
  template <Real T>
  bool clip(const Vec3<T>& origin, const Vec3<T>& direction, T& t0, T& t1) const {
    const Vec3f l = lo(), h = hi();
    for (int a = 0; a < 3; ++a) {
      if (l[a] > h[a]) return false;  // the empty box
      if (direction[a] == T(0)) {
        if (origin[a] < T(l[a]) || origin[a] > T(h[a])) return false;
        continue;
      }
      const T inverse = T(1) / direction[a];
      T tNear = (T(l[a]) - origin[a]) * inverse, tFar = (T(h[a]) - origin[a]) * inverse;
      if (tNear > tFar) std::swap(tNear, tFar);
      t0 = std::max(t0, tNear);
      t1 = std::min(t1, tFar);
      if (t0 > t1) return false;
    }
    return true;
  }
  /// Whether the segment, t in [t0, t1], meets the box.
  template <Real T>
  bool reaches(const Vec3<T>& origin, const Vec3<T>& direction, T t0, T t1) const {
    return clip(origin, direction, t0, t1);
  }
};
static_assert(sizeof(CellReach) == 8);

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

/// Calls visit(proj, face, layer, a, b, uv, distance) for every filled sample of a cell (one whose
/// line met the surface, not empty and not before its face), with its projection in double
/// (unit-cell coordinates) and the distance decoded.
template <class Codes, class Visit>
void forEachFilledSample(const ReliefModel& model, const Codes& codes, const CellRecord& record, Visit&& visit) {
  const int texels = model.texels;
  const DistanceCodec& codec = model.distanceCodec;
  record.projection<double>().visit([&](const auto& proj) {
    for (int f = 0; f < 6; ++f) {
      const int layer = record.layerOf(f);
      if (layer < 0) continue;
      for (int b = 0; b < texels; ++b)
        for (int a = 0; a < texels; ++a) {
          const std::uint32_t code = codes(layer, a, b);
          if (!codec.hasSurface(code)) continue;
          visit(proj, f, layer, a, b, Vec2d(double(a) / (texels - 1), double(b) / (texels - 1)),
                (double(code) - double(codec.zeroCode)) * codec.scale());
        }
    }
  });
}

/// The face points of the texels around a filled sample of an interior cell: its field can change
/// sign over each of them (a neighbour before the face or empty reads as mixedTexel says).
inline void extendByTexelsAround(Aabbd& box, int f, const Vec2d& uv, int texels) {
  const double spacing = 1.0 / double(texels - 1);
  box.extend(projection::facePoint(f, glm::max(uv - spacing, Vec2d(0))));
  box.extend(projection::facePoint(f, glm::min(uv + spacing, Vec2d(1))));
}

/// The unit-cell box of one cell's filled samples: their surface points, and in interior cells
/// the face points of the texels around them too.
template <class Codes>
Aabbd cellSampleBounds(const ReliefModel& model, const Codes& codes, const CellRecord& record) {
  Aabbd box;
  const bool interior = record.configuration == 0;
  forEachFilledSample(model, codes, record, [&](const auto& proj, int f, int, int, int, const Vec2d& uv, double d) {
    box.extend(proj.unproject(f, uv, d));
    if (interior) extendByTexelsAround(box, f, uv, model.texels);
  });
  return box;
}

/// The unit-cell box of every point where one cell's field can change sign: the surface points of
/// its filled samples; where a filled sample borders an empty one (in its layer, or, in a central
/// cell with a domain face that has no layer, on its layer's edge), the line from its surface
/// point to the line's end, for the field jumps there from "beyond the surface" to "no surface";
/// in interior cells the face points of the texels around filled samples (extendByTexelsAround). Grown by
/// kSurfaceBoundsMarginSamples spacings.
template <class Codes>
Aabbd cellReachBox(const ReliefModel& model, const Codes& codes, const CellRecord& record) {
  Aabbd box;
  const int texels = model.texels;
  const bool interior = record.configuration == 0;
  const std::uint32_t empty = model.distanceCodec.emptyCode();
  const auto type = static_cast<projection::ProjectionType>(record.projectionType);
  const bool central = type == projection::ProjectionType::Perspective || type == projection::ProjectionType::Axial;
  const bool faceWithoutLayer = (record.presentFaces & 63u) != (cells::domainFacesOf(record.configuration) & 63u);
  forEachFilledSample(model, codes, record,
                      [&](const auto& proj, int f, int layer, int a, int b, const Vec2d& uv, double d) {
    auto emptyAt = [&](int x, int y) {
      return x >= 0 && y >= 0 && x < texels && y < texels && codes(layer, x, y) >= empty;
    };
    const Vec3d onFace = projection::facePoint(f, uv);
    box.extend(proj.unproject(f, uv, d));
    if (interior) extendByTexelsAround(box, f, uv, texels);
    bool bordersEmpty = central && faceWithoutLayer && (a == 0 || b == 0 || a == texels - 1 || b == texels - 1);
    for (int db = -1; db <= 1 && !bordersEmpty; ++db)
      for (int da = -1; da <= 1 && !bordersEmpty; ++da) bordersEmpty = emptyAt(a + da, b + db);
    if (bordersEmpty) box.extend(proj.lineEnd(f, onFace));
  });
  if (box.isEmpty()) return box;
  const double margin = kSurfaceBoundsMarginSamples / double(std::max(1, texels - 1));
  return Aabbd(box.min - margin, box.max + margin);
}

}  // namespace detail

/// CellReach of every cell of the model, in the cell table's order.
inline std::vector<CellReach> cellReaches(const ReliefModel& model) {
  std::vector<CellReach> reaches(model.cells.size());
  if (model.layerCount() == 0) return reaches;
  model.visitDistanceCodes([&](const auto& codes) {
    parallelFor(0, model.cells.size(), [&](std::size_t i) {
      reaches[i] = CellReach::of(detail::cellReachBox(model, codes, model.cells[i]));
    }, 16);
  });
  return reaches;
}

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
