// SPDX-License-Identifier: MIT
/// @file relief_tracer.h
/// Ray casting of a relief model (Apaza & Andujar, 3.5.2) on the CPU, the reference the GPU
/// backends will follow. A 3D DDA walks the ray through the grid and stops only at grey cells
/// (looked up in an OpenVDB grid through a cached accessor; white and black cells cost one lookup).
/// Inside a grey cell the ray segment is searched for a sign change of
///   f(p) = |p - P'(p)| - stored distance at P'(p),
/// the point's distance from its projection on the domain face minus the surface's: a linear
/// search finds the first sample past the surface, a binary search refines it. The number of
/// linear steps follows the ray's slant to the face it entered through (de Toledo et al.): a ray
/// along the projection direction crosses few samples, a grazing ray many. Empty samples (no
/// surface on the projection line) count as "between face and surface". The stored distances are read with bilinear filtering of the
/// vertex-centred samples, as a GPU's hardware filter reads them.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <openvdb/openvdb.h>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/hit.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::trace {

struct TraceOptions {
  int minLinearSteps = 4;   ///< a ray along the projection direction
  int maxLinearSteps = 64;  ///< a ray grazing the face
  int binarySteps = 8;      ///< refinement after the linear search (1 / 256 of a linear step)
};

/// Where a ray met the relief surface.
struct ReliefHit {
  double t = std::numeric_limits<double>::infinity();
  Vec3d position{0};
  Vec3f normal{0};   ///< shading normal: the normal map, or the local surface of the samples
  Color8 color{200, 200, 200, 255};
  int cell = -1;     ///< index into the model's cell table
  int face = -1;     ///< domain face whose map held the surface
  Vec2f uv{0};       ///< face coordinates on that face
  std::uint32_t steps = 0;  ///< search samples taken (for statistics)
  bool valid() const { return cell >= 0; }
};

class ReliefTracer {
 public:
  explicit ReliefTracer(const relief::ReliefModel& model, const TraceOptions& options = {})
      : mModel(model), mOptions(options), mGrid(openvdb::Int32Grid::create(-1)) {
    auto acc = mGrid->getAccessor();
    for (std::size_t i = 0; i < model.cells.size(); ++i) {
      const Vec3i p = model.cells[i].ijk();
      acc.setValueOn(openvdb::Coord(p.x, p.y, p.z), std::int32_t(i));
    }
    mBounds = Aabbd(model.originWS, model.originWS + Vec3d(model.cellSizeWS * model.gridSize));
  }

  const relief::ReliefModel& model() const { return mModel; }
  const Aabbd& boundsWS() const { return mBounds; }

  /// The nearest hit of the ray (world space) within [ray.tmin, ray.tmax].
  ReliefHit intersect(const Rayd& ray) const {
    ReliefHit best;
    const RayInterval<double> span = cellrelief::intersect(ray, mBounds);
    if (!span.hit) return best;
    openvdb::Int32Grid::ConstAccessor acc = mGrid->getConstAccessor();
    const int n = mModel.gridSize;
    const double h = mModel.cellSizeWS;
    // DDA in index space, starting where the ray enters the grid.
    const double tStart = span.t0;
    const Vec3d entry = (ray.at(tStart) - mModel.originWS) / h;
    Vec3i cell = glm::clamp(Vec3i(glm::floor(entry)), Vec3i(0), Vec3i(n - 1));
    Vec3i step;
    Vec3d tMax, tDelta;
    for (int a = 0; a < 3; ++a) {
      const double d = ray.direction[a];
      if (d > 0) {
        step[a] = 1;
        tMax[a] = tStart + ((cell[a] + 1) * h + mModel.originWS[a] - ray.at(tStart)[a]) / d;
        tDelta[a] = h / d;
      } else if (d < 0) {
        step[a] = -1;
        tMax[a] = tStart + (cell[a] * h + mModel.originWS[a] - ray.at(tStart)[a]) / d;
        tDelta[a] = -h / d;
      } else {
        step[a] = 0;
        tMax[a] = std::numeric_limits<double>::infinity();
        tDelta[a] = std::numeric_limits<double>::infinity();
      }
    }
    double tCell = tStart;
    while (true) {
      const double tExit = std::min({tMax.x, tMax.y, tMax.z, span.t1});
      const std::int32_t index = acc.getValue(openvdb::Coord(cell.x, cell.y, cell.z));
      if (index >= 0) {
        ReliefHit hit = searchCell(ray, index, tCell, tExit);
        if (hit.valid()) return hit;
      }
      if (tExit >= span.t1) break;
      const int axis = tMax.x < tMax.y ? (tMax.x < tMax.z ? 0 : 2) : (tMax.y < tMax.z ? 1 : 2);
      cell[axis] += step[axis];
      if (cell[axis] < 0 || cell[axis] >= n) break;
      tCell = tMax[axis];
      tMax[axis] += tDelta[axis];
    }
    return best;
  }

 private:
  /// f at a unit-cell point: distance from its face point minus the stored distance (negative =
  /// between the face and the surface, positive = beyond the surface); `face` and `uv` report
  /// where it projected. No surface on the projection line reads as "between" (-1).
  double field(const relief::CellRecord& r, const projection::CellProjection<double>& proj,
               const Vec3d& p, int& face, Vec2d& uv) const {
    const projection::FacePoint<double> fp = proj.project(glm::clamp(p, Vec3d(0), Vec3d(1)));
    face = fp.face;
    uv = fp.uv;
    const int layer = r.layerOf(fp.face);
    if (layer < 0) return -1.0;  // no surface projects onto this face
    const int T = mModel.texels;
    const double x = fp.uv.x * (T - 1), y = fp.uv.y * (T - 1);
    const int a0 = std::min(T - 2, int(x)), b0 = std::min(T - 2, int(y));
    const double fx = x - a0, fy = y - b0;
    double stored = 0, weight = 0;
    for (int k = 0; k < 4; ++k) {
      const int a = a0 + (k & 1), b = b0 + (k >> 1);
      const double d = mModel.distance(layer, a, b);
      if (std::isnan(d)) return -1.0;  // an empty sample nearby: no surface here
      const double w = ((k & 1) ? fx : 1 - fx) * ((k >> 1) ? fy : 1 - fy);
      stored += w * d;
      weight += w;
    }
    return fp.distance - stored / weight;
  }

  ReliefHit searchCell(const Rayd& ray, std::int32_t index, double t0, double t1) const {
    ReliefHit hit;
    const relief::CellRecord& r = mModel.cells[index];
    const auto proj = r.projection<double>();
    const Vec3d origin = mModel.originWS + Vec3d(r.ijk()) * mModel.cellSizeWS;
    const double h = mModel.cellSizeWS;
    auto local = [&](double t) { return (ray.at(t) - origin) / h; };
    int face = -1;
    Vec2d uv;
    double fPrev = field(r, proj, local(t0), face, uv);
    // Linear steps from the slant between the ray and the entry face's projection direction.
    const Vec3d dirUnit = glm::normalize(ray.direction);
    const double slant = face >= 0 ? std::abs(glm::dot(dirUnit, Vec3d(cells::faceNormal(face)))) : 1.0;
    const double lengthCells = (t1 - t0) * glm::length(ray.direction) / h;
    // Parallel and planar cells have one projection direction, so f changes monotonically with
    // depth and the slant rule applies. Perspective and axial cells switch faces along the ray,
    // and the region behind the surface can be a thin sliver next to a face: they always take
    // the full number of steps.
    const bool singleDirection = proj.type == projection::ProjectionType::Parallel ||
                                 proj.type == projection::ProjectionType::Planar;
    const double perCell = singleDirection
        ? mOptions.minLinearSteps + (1.0 - slant) * (mOptions.maxLinearSteps - mOptions.minLinearSteps)
        : double(mOptions.maxLinearSteps);
    const int linear = std::clamp(int(std::ceil(lengthCells * perCell)), 2, mOptions.maxLinearSteps);
    double tPrev = t0;
    std::uint32_t steps = 1;
    for (int i = 1; i <= linear; ++i) {
      const double t = t0 + (t1 - t0) * double(i) / linear;
      double f = field(r, proj, local(t), face, uv);
      ++steps;
      if ((fPrev > 0) != (f > 0)) {
        // Binary search between tPrev and t.
        double lo = tPrev, hi = t, fLo = fPrev;
        for (int k = 0; k < mOptions.binarySteps; ++k) {
          const double mid = 0.5 * (lo + hi);
          const double fm = field(r, proj, local(mid), face, uv);
          ++steps;
          if ((fm > 0) == (fLo > 0)) {
            lo = mid;
            fLo = fm;
          } else {
            hi = mid;
          }
        }
        hit.t = hi;
        hit.position = ray.at(hi);
        hit.cell = index;
        field(r, proj, local(hi), face, uv);
        hit.face = face;
        hit.uv = Vec2f(uv);
        hit.steps = steps;
        shade(r, proj, hit);
        if (hit.normal == Vec3f(0)) hit.normal = Vec3f(-dirUnit);  // a sample with no neighbours
        return hit;
      }
      fPrev = f;
      tPrev = t;
    }
    return hit;
  }

  /// Shading normal and color at a hit: from the maps when stored, else from the unprojected
  /// neighbouring samples (the local surface of the distance map).
  void shade(const relief::CellRecord& r, const projection::CellProjection<double>& proj,
             ReliefHit& hit) const {
    const int layer = r.layerOf(hit.face);
    if (layer < 0) return;
    const int T = mModel.texels;
    const int a = std::clamp(int(std::lround(hit.uv.x * (T - 1))), 0, T - 1);
    const int b = std::clamp(int(std::lround(hit.uv.y * (T - 1))), 0, T - 1);
    if (mModel.normalFormat != relief::NormalFormat::None) {
      hit.normal = mModel.normal(layer, a, b);
    } else {
      auto point = [&](int x, int y) -> std::optional<Vec3d> {
        x = std::clamp(x, 0, T - 1);
        y = std::clamp(y, 0, T - 1);
        const double d = mModel.distance(layer, x, y);
        if (std::isnan(d)) return std::nullopt;
        return proj.unproject(hit.face, Vec2d(double(x) / (T - 1), double(y) / (T - 1)), d);
      };
      // Central differences where both neighbours exist, one-sided ones at the edge of the
      // surface; the reverse ray direction when the sample stands alone.
      const auto centre = point(a, b);
      auto derivative = [&](int dx, int dy) -> std::optional<Vec3d> {
        const auto plus = point(a + dx, b + dy), minus = point(a - dx, b - dy);
        if (plus && minus) return *plus - *minus;
        if (plus && centre) return *plus - *centre;
        if (minus && centre) return *centre - *minus;
        return std::nullopt;
      };
      const auto du = derivative(1, 0), dv = derivative(0, 1);
      Vec3d n(0);
      if (du && dv) n = glm::cross(*du, *dv);
      if (cells::faceSign(hit.face) < 0) n = -n;
      hit.normal = glm::length(n) > 0 ? Vec3f(glm::normalize(n)) : Vec3f(0);
    }
    if (mModel.colorFormat == relief::ColorFormat::Rgba8)
      for (int c = 0; c < 4; ++c) hit.color[c] = mModel.colors.at(a, b, layer, c);
  }

  const relief::ReliefModel& mModel;
  TraceOptions mOptions;
  openvdb::Int32Grid::Ptr mGrid;
  Aabbd mBounds;
};

}  // namespace cellrelief::trace
