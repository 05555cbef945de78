// SPDX-License-Identifier: MIT
/// @file relief_tracer.h
/// Ray casting of a relief model (Apaza & Andujar, 3.5.2) on the CPU: the reference that the GPU
/// backends follow. A 3D DDA (grid_dda.h) walks the ray through the grid and stops only at grey cells (looked up
/// in a sparse OpenVDB grid through a cached accessor; white and black cells cost one lookup).
/// Inside a grey cell the ray segment is searched for a sign change of
///   f(p) = |p - P'(p)| - stored distance at P'(p),
/// the point's distance from its projection on the domain face minus the surface's, read with
/// bilinear filtering of the vertex-centred samples as a GPU's hardware filter reads them.
///
/// Two ways to search a cell:
/// - linear + binary (the paper): a linear search finds the first sample past the surface and a
///   binary search refines it. The number of linear steps is the search policy's choice; the
///   default, BalancedSearch, balances it to the segment's footprint on the maps (de Toledo et al.,
///   Geometry Textures 4.1, generalized from the slant to every projection): a ray along the
///   projection direction crosses few texels and needs few samples, a grazing ray one or two per
///   texel it crosses. The footprint is measured by projecting points of the segment (central
///   projection maps a straight segment to a straight one on a face; axial is sampled).
/// - empty-space skipping (TraceOptions::skipEmptySpace, beyond the paper): in parallel and planar
///   cells, whose distance is linear along the ray, the ray walks a min pyramid of the layer
///   (empty_space.h) and skips every node it provably cannot hit; in each texel cell it still has
///   to cross, it meets the bilinear surface exactly (a quadratic in the ray parameter). This is
///   conservative: it can find more hits than the sampled search, never fewer. Perspective and
///   axial cells (TraceOptions::skipCentralCells) walk the same pyramid face by face, with a
///   bound that holds along the central projection (centralSkipSearch), and sample the texel
///   cells they cannot skip.
///
/// Cell boundaries: a surface lying in the face shared by two grey cells, or thinner than a
/// sample where it pokes into a cell, may show no sign change inside either cell. The tracer
/// carries the side of the surface (inside or outside) across cell faces, and entering a cell on
/// the other side is a hit at the face. For this the field is signed by inside and outside rather
/// than by the face's side; interior cells (case 0) need a bit of the look-up table for that (see
/// field()).
///
/// Open surfaces: a mesh with holes separates no inside from an outside. White space reaches both
/// sides of the surface through the holes, and a cell's side reads true only within the cell, so
/// in a model of an open mesh (ReliefModel::openSurface()) no side is carried across cell faces:
/// measured against Embree, carrying it there made most of the disagreement (bunny: 144 rays of
/// 40000 disagree with it, 21 without). In the cells that hold a hole's rim, an empty projection
/// line may look through the hole, so a step between an empty line and one with surface is no
/// crossing there (CellRecord::kOpenSurface).
///
/// The projection type is a template parameter of the cell search (dispatched once per cell), so
/// the inner loops have no virtual or switch-per-sample call; the scalar type (float or double)
/// and the search policy are template parameters of the tracer.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>
#include <optional>
#include <type_traits>

#include <openvdb/openvdb.h>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/ray.h"
#include "cellrelief/relief/relief_model.h"
#include "cellrelief/trace/empty_space.h"
#include "cellrelief/trace/grid_dda.h"
#include "cellrelief/trace/trace_options.h"

namespace cellrelief::trace {

/// Where a ray met the relief surface.
template <Real T>
struct ReliefHit {
  T t = std::numeric_limits<T>::infinity();
  Vec3<T> position{0};
  Vec3f normal{0};   ///< shading normal: the normal map, or the local surface of the samples
  Color8 color{200, 200, 200, 255};
  int cell = -1;     ///< index into the model's cell table
  int face = -1;     ///< domain face whose map held the surface
  Vec2f uv{0};       ///< face coordinates on that face, [0, 1]^2
  Vec2f texel{0};    ///< the same in sample units, [0, T - 1]^2
  std::uint32_t steps = 0;  ///< field evaluations and skip steps over the whole ray (a miss reports them too)
  bool valid() const { return cell >= 0; }
};

template <Real T, SearchPolicy Search = BalancedSearch>
class ReliefTracer {
 public:
  using Scalar = T;
  using Hit = ReliefHit<T>;

  /// The tracer reads the model in place: it must outlive the tracer (a temporary is refused).
  ReliefTracer(relief::ReliefModel&&, const TraceOptions& = {}) = delete;
  explicit ReliefTracer(const relief::ReliefModel& model, const TraceOptions& options = {})
      : mModel(model), mOptions(options), mGrid(openvdb::Int32Grid::create(-1)) {
    auto acc = mGrid->getAccessor();
    for (std::size_t i = 0; i < model.cells.size(); ++i) {
      const Vec3i p = model.cells[i].ijk();
      acc.setValueOn(openvdb::Coord(p.x, p.y, p.z), std::int32_t(i));
    }
    mBounds = Aabb<T>(Vec3<T>(model.originWS),
                      Vec3<T>(model.originWS + Vec3d(model.cellSizeWS * model.gridSize)));
    mOrigin = Vec3<T>(model.originWS);
    mCellSize = T(model.cellSizeWS);
    mDistanceScale = T(model.distanceCodec.scale());
    if (options.skipEmptySpace) mPyramid = EmptySpacePyramid(model);
    mOpenModel = model.openSurface();
  }

  const relief::ReliefModel& model() const { return mModel; }
  const TraceOptions& options() const { return mOptions; }
  const Aabb<T>& boundsWS() const { return mBounds; }
  /// Bytes the tracer adds to the model (the pyramid; the sparse grid mirrors the cell table).
  std::size_t accelerationBytes() const { return mPyramid.byteSize(); }

  /// The nearest hit of the ray (world space) within [ray.tmin, ray.tmax]. The direction need not
  /// be normalized; t is in units of it.
  Hit intersect(const Ray<T>& ray) const { return trace(ray, true); }

  /// Whether anything lies on the ray within [tmin, tmax] (shadow rays): the search without the
  /// shading of the hit.
  bool occluded(const Ray<T>& ray) const { return trace(ray, false).valid(); }

  /// The signed field the search reads at a world point (positive inside the object), or nullopt
  /// outside every grey cell: for diagnostics, such as telling a search that stepped over the
  /// surface from a relief that has none there (bench_silhouettes).
  std::optional<T> fieldAt(const Vec3<T>& pointWS) const {
    const Vec3<T> u = (pointWS - mOrigin) / mCellSize;
    if (!(glm::all(glm::greaterThanEqual(u, Vec3<T>(0))) && glm::all(glm::lessThanEqual(u, Vec3<T>(mModel.gridSize)))))
      return std::nullopt;
    const Vec3i c = glm::min(Vec3i(glm::floor(u)), Vec3i(mModel.gridSize - 1));
    const std::int32_t index = mGrid->getConstAccessor().getValue(openvdb::Coord(c.x, c.y, c.z));
    if (index < 0) return std::nullopt;
    const relief::CellRecord& record = mModel.cells[index];
    return mModel.visitDistanceCodes([&](const auto& codes) {
      return record.projection<T>().visit([&](const auto& p) {
        projection::FacePoint<T> fp;
        return std::optional<T>(field(codes, p, record, u - Vec3<T>(c), fp));
      });
    });
  }

 private:
  /// The texel width is chosen here, once per ray: below, reading a sample has no branch on it.
  Hit trace(const Ray<T>& input, bool shadeHit) const {
    return mModel.visitDistanceCodes([&](const auto& codes) { return traceWith(codes, input, shadeHit); });
  }

  template <class Codes>
  Hit traceWith(const Codes& codes, const Ray<T>& input, bool shadeHit) const {
    // The inverse direction is recomputed: the ray's fields are public and may disagree.
    Ray<T> ray = input;
    ray.setDirection(input.direction);
    // A ray without a finite origin and a finite, non-zero direction, or with an empty or NaN
    // interval, meets nothing (and must not reach the index arithmetic below).
    const bool finite = std::isfinite(ray.origin.x) && std::isfinite(ray.origin.y) &&
                        std::isfinite(ray.origin.z) && std::isfinite(ray.direction.x) &&
                        std::isfinite(ray.direction.y) && std::isfinite(ray.direction.z);
    if (!finite || ray.direction == Vec3<T>(0) || !(ray.tmin <= ray.tmax)) return {};
    const RayInterval<T> span = cellrelief::intersect(ray, mBounds);
    if (!span.hit) return {};
    // Unregistered: a registered accessor takes a lock in the tree on creation, once per ray.
    auto acc = mGrid->getConstUnsafeAccessor();
    GridDda<T> walk(ray, mOrigin, mCellSize, mModel.gridSize, span.t0, span.t1);
    // The side of the surface the ray is on, carried from cell to cell: outside when it enters
    // the grid from outside (the grid holds the whole mesh), unknown when it starts within it.
    // White and black cells hold no surface, so they keep the side.
    Side side{span.t0 > ray.tmin ? Side::Outside : Side::Unknown};
    std::uint32_t steps = 0;  // over every grey cell searched (a search that misses reports its steps too)
    do {
      const Vec3i& cell = walk.cell();
      const std::int32_t index = acc.getValue(openvdb::Coord(cell.x, cell.y, cell.z));
      if (index >= 0) {
        const relief::CellRecord& record = mModel.cells[index];
        const auto proj = record.projection<T>();
        const CellFrame frame = cellFrame(ray, record);
        Hit hit = proj.visit([&](const auto& p) {
          Hit found = searchCell(codes, p, record, index, ray, frame, walk.tEntry(), walk.tExit(), side);
          if (found.valid() && shadeHit) {
            shade(codes, p, record, found);
            if (found.normal == Vec3f(0)) found.normal = Vec3f(-glm::normalize(Vec3d(ray.direction)));
          }
          return found;
        });
        steps += hit.steps;
        if (hit.valid()) {
          hit.steps = steps;
          return hit;
        }
      } else {
        side.exitField = std::numeric_limits<T>::infinity();
      }
    } while (walk.next());
    return missAfter(steps);
  }

  static Hit missAfter(std::uint32_t steps) {
    Hit miss;
    miss.steps = steps;
    return miss;
  }

  /// The ray in a cell's unit coordinates: p(t) = origin + t * direction.
  struct CellFrame {
    Vec3<T> origin{0};
    Vec3<T> direction{0};
  };
  /// |f| on a projection line without surface: beyond any real value (at most sqrt(3) in a cell),
  /// so that "no surface here" stays distinguishable from a distance.
  static constexpr T kEmptyField = T(constants::kEmptyField);
  static bool isEmptyField(T f) { return std::abs(f) >= kEmptyField; }

  /// Where the ray is relative to the surface, and |f| where it left the last grey cell
  /// (infinity after a white or black cell, where no surface can be).
  struct Side {
    enum { Unknown, Outside, Inside } where = Unknown;
    T exitField = std::numeric_limits<T>::infinity();
  };

  CellFrame cellFrame(const Ray<T>& ray, const relief::CellRecord& r) const {
    const Vec3<T> cellOrigin = mOrigin + Vec3<T>(r.ijk()) * mCellSize;
    return {(ray.origin - cellOrigin) / mCellSize, ray.direction / mCellSize};
  }

  /// Bilinearly filtered stored distance at face coordinates, or nullopt when one of the four
  /// samples is empty (the rim of the surface's projection: the field changes side there). With
  /// `emptyLinesCrossed` (interior cells), a texel with some samples empty is read as mixedTexel
  /// says, and nullopt means all four are empty.
  template <class Codes>
  std::optional<T> stored(const Codes& codes, int layer, const Vec2<T>& uv, bool emptyLinesCrossed = false) const {
    const int texels = mModel.texels;
    // Written so that NaN lands on 0: an index from NaN would be undefined.
    const T x = (uv.x > T(0) ? std::min(uv.x, T(1)) : T(0)) * T(texels - 1);
    const T y = (uv.y > T(0) ? std::min(uv.y, T(1)) : T(0)) * T(texels - 1);
    const int a0 = std::min(texels - 2, int(x)), b0 = std::min(texels - 2, int(y));
    const T fx = x - T(a0), fy = y - T(b0);
    const relief::DistanceCodec& codec = mModel.distanceCodec;
    T c00 = T(codes(layer, a0, b0)), c10 = T(codes(layer, a0 + 1, b0));
    T c01 = T(codes(layer, a0, b0 + 1)), c11 = T(codes(layer, a0 + 1, b0 + 1));
    const T empty = T(codec.emptyCode());
    const int emptyCount = int(c00 >= empty) + int(c10 >= empty) + int(c01 >= empty) + int(c11 >= empty);
    if (emptyCount > 0) {
      if (!emptyLinesCrossed || emptyCount == 4) return std::nullopt;
      mixedTexel(c00, c10, c01, c11, empty, emptyCount);
    }
    const T top = c00 + fx * (c10 - c00);
    const T bottom = c01 + fx * (c11 - c01);
    return (top + fy * (bottom - top)) * mDistanceScale;
  }

  /// A texel of an interior cell (case 0) with some but not all of its samples empty. An empty
  /// line there lies wholly on the centre's side, so the surface crossed the face before it; a
  /// filled one, after its face point, at its distance. Read as empty, the whole texel took the
  /// centre's side, and the relief grew by up to a texel where the surface leaves the cell
  /// through a domain face (the most of the "only ours" disagreements with Embree on closed
  /// meshes). Instead each empty sample reads as the negated mean of the filled ones: the
  /// interpolated surface then crosses the face halfway between an empty and a filled sample.
  static void mixedTexel(T& c00, T& c10, T& c01, T& c11, T empty, int emptyCount) {
    auto filled = [&](T c) { return c < empty ? c : T(0); };
    const T mirrored = -(filled(c00) + filled(c10) + filled(c01) + filled(c11)) / T(4 - emptyCount);
    for (T* c : {&c00, &c10, &c01, &c11})
      if (*c >= empty) *c = mirrored;
  }

  /// The signed field at a unit-cell point: positive inside the object, negative outside.
  /// f = distance from the face minus the stored distance is negative between the face and the
  /// surface, positive beyond it. Domain faces of every cell but the interior ones border white
  /// space, so there "beyond" is inside and a line with no surface is outside. An interior cell
  /// (case 0) projects from its centre; a line with no surface lies on the centre's side, and a
  /// line with surface has the centre's side beyond it (CellRecord::centreInside says which).
  template <class Codes, class P>
  T field(const Codes& codes, const P& proj, const relief::CellRecord& r, const Vec3<T>& p,
          projection::FacePoint<T>& fp) const {
    fp = proj.project(glm::clamp(p, Vec3<T>(0), Vec3<T>(1)));
    const bool interior = r.configuration == 0;
    const T emptyValue = interior && r.centreInside() ? kEmptyField : -kEmptyField;
    const int layer = r.layerOf(fp.face);
    if (layer < 0) return emptyValue;
    const std::optional<T> s = stored(codes, layer, fp.uv, interior);
    if (!s) return emptyValue;
    return interior && !r.centreInside() ? *s - fp.distance : fp.distance - *s;
  }

  /// Searches the ray segment [t0, t1] inside one grey cell. `side` is where the ray was when it
  /// entered (updated to where it leaves when there is no hit). A surface lying in the face
  /// shared with the previous cell, or thinner than a sample there, shows no sign change inside
  /// either cell; the side carried across the face catches it: entering on the other side of
  /// the surface is a hit at the face.
  template <class Codes, class P>
  Hit searchCell(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index, const Ray<T>& ray,
                 const CellFrame& frame, T t0, T t1, Side& side) const {
    auto local = [&](T t) { return frame.origin + t * frame.direction; };
    projection::FacePoint<T> fp;
    const T fIn = field(codes, proj, r, local(t0), fp);
    // A crossing at the face unless both cells read a real distance far from the surface there:
    // then they disagree because one of them misreads the side (a projection line that meets the
    // surface twice, past the occlusion the grid size allows), and the entered cell is trusted.
    // An empty line (no surface sampled, as in a sliver thinner than a sample) tells nothing
    // against the crossing.
    const T nearFace = T(constants::kNearFaceSamples) / T(mModel.texels - 1);
    auto farFromSurface = [&](T f) { return std::abs(f) > nearFace && std::abs(f) < kEmptyField; };
    // An open model's cells read the side each on its own (ReliefModel::openSurface()).
    if (!mOpenModel && side.where != Side::Unknown && (fIn > 0) != (side.where == Side::Inside) &&
        !(farFromSurface(fIn) && farFromSurface(side.exitField)))
      return makeHit(index, ray, t0, fp, 1);
    // The linear search starts where the field was just read and ends where the next cell's
    // side is decided: it hands both values over instead of reading them again.
    T fOut = std::numeric_limits<T>::quiet_NaN();
    Hit hit = searchInside(codes, proj, r, index, ray, frame, t0, t1, fIn, fp, fOut);
    if (!hit.valid()) {
      if (std::isnan(fOut)) fOut = field(codes, proj, r, local(t1), fp);
      side.where = mOpenModel ? Side::Unknown : fOut > 0 ? Side::Inside : Side::Outside;
      side.exitField = std::abs(fOut);
    }
    return hit;
  }

  template <class Codes, class P>
  Hit searchInside(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index, const Ray<T>& ray,
                   const CellFrame& frame, T t0, T t1, T fStart,
                   const projection::FacePoint<T>& fpStart, T& fEnd) const {
    constexpr bool kSingleDirection = std::is_same_v<P, projection::ParallelProjection<T>> ||
                                      std::is_same_v<P, projection::PlanarProjection<T>>;
    if constexpr (kSingleDirection) {
      if (mOptions.skipEmptySpace) return skipSearch(codes, proj, r, index, ray, frame, t0, t1);
    } else {
      // Interior cells read an empty line on the centre's side, not the face's: a node that
      // mixes empty and filled texel cells tells no side there, so they keep the sampled search.
      if (mOptions.skipEmptySpace && mOptions.skipCentralCells && r.configuration != 0)
        return centralSkipSearch(codes, proj, r, index, ray, frame, t0, t1, fStart);
    }
    return linearBinarySearch(codes, proj, r, index, ray, frame, t0, t1, fStart, fpStart, fEnd);
  }

  /// fStart, fpStart: the field and projection at t0; fEnd: set to the field at the last
  /// sample (t1) when nothing is hit.
  template <class Codes, class P>
  Hit linearBinarySearch(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index,
                         const Ray<T>& ray, const CellFrame& frame, T t0, T t1, T fStart,
                         const projection::FacePoint<T>& fpStart, T& fEnd) const {
    auto local = [&](T t) { return frame.origin + t * frame.direction; };
    projection::FacePoint<T> fp = fpStart;
    T fPrev = fStart;
    // The footprint on the maps, from four points of the segment; a change of face counts as a
    // whole face crossed (conservative: the two pieces meet on the shared edge).
    T footprint = 0;
    projection::FacePoint<T> a = fp;
    for (int k = 1; k <= constants::kFootprintProbes; ++k) {
      const projection::FacePoint<T> b = proj.project(glm::clamp(
          local(t0 + (t1 - t0) * T(k) / T(constants::kFootprintProbes)), Vec3<T>(0), Vec3<T>(1)));
      footprint += a.face == b.face ? glm::length(b.uv - a.uv) : T(1);
      a = b;
    }
    const int linear = Search::linearSteps(mOptions, double(footprint * T(mModel.texels - 1)));
    T tPrev = t0;
    std::uint32_t steps = 1;
    // In a cell with a hole's rim, a step between an empty line and one with surface is no
    // crossing: the empty line may look through the hole (CellRecord::kOpenSurface).
    const bool open = r.openSurface();
    for (int i = 1; i <= linear; ++i) {
      const T t = t0 + (t1 - t0) * T(i) / T(linear);
      const T f = field(codes, proj, r, local(t), fp);
      ++steps;
      if ((fPrev > 0) != (f > 0) && !(open && (isEmptyField(fPrev) || isEmptyField(f))))
        return refineCrossing(codes, proj, r, index, ray, frame, tPrev, t, fPrev > 0, steps);
      fPrev = f;
      tPrev = t;
    }
    fEnd = fPrev;
    return missAfter(steps);
  }

  /// The binary search between a sample on one side of the surface (lo, where the field's sign
  /// is `positiveLo`) and one on the other (hi): the hit at the last bracket's far end.
  template <class Codes, class P>
  Hit refineCrossing(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index,
                     const Ray<T>& ray, const CellFrame& frame, T lo, T hi, bool positiveLo,
                     std::uint32_t steps) const {
    auto local = [&](T t) { return frame.origin + t * frame.direction; };
    projection::FacePoint<T> fp;
    for (int k = 0; k < mOptions.binarySteps; ++k) {
      const T mid = T(0.5) * (lo + hi);
      const T fm = field(codes, proj, r, local(mid), fp);
      ++steps;
      if ((fm > 0) == positiveLo) lo = mid;
      else hi = mid;
    }
    field(codes, proj, r, local(hi), fp);
    return makeHit(index, ray, hi, fp, steps);
  }

  /// The least distance code under a pyramid node; level 0 (a texel cell, not stored) from its
  /// four samples, empty when any of them is (as the tracer reads it).
  template <class Codes>
  std::uint32_t nodeCode(const Codes& codes, int layer, int level, int ix, int iy) const {
    if (level > 0) return mPyramid.code(layer, level, ix, iy);
    const std::uint32_t c[4] = {codes(layer, ix, iy), codes(layer, ix + 1, iy), codes(layer, ix, iy + 1),
                                codes(layer, ix + 1, iy + 1)};
    const relief::DistanceCodec& codec = mModel.distanceCodec;
    return codec.isEmpty(c[0]) || codec.isEmpty(c[1]) || codec.isEmpty(c[2]) || codec.isEmpty(c[3])
               ? codec.emptyCode()
               : std::min({c[0], c[1], c[2], c[3]});
  }

  /// A nudge of a few ulps of a coordinate in the direction it moves: a node boundary the walk
  /// stands on goes to the node ahead (a fixed nudge vanishes in float away from zero).
  static T nudge(T v, T dv) {
    return dv == 0 ? T(0)
                   : std::copysign(T(constants::kNudgeUlps) * std::numeric_limits<T>::epsilon() *
                                       std::max(T(1), std::abs(v)), dv);
  }

  /// Parallel and planar cells: walk the layer's min pyramid, meet the bilinear surface exactly
  /// in the texel cells that cannot be skipped. A planar cell is two parallel half-cells.
  template <class Codes, class P>
  Hit skipSearch(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index, const Ray<T>& ray,
                 const CellFrame& frame, T t0, T t1) const {
    if constexpr (std::is_same_v<P, projection::ParallelProjection<T>>) {
      return skipSearchFace(codes, r, index, ray, frame, proj.face, t0, t1, T(1));
    } else {
      const int axis = proj.axis;
      const T o = frame.origin[axis], d = frame.direction[axis];
      // Split at the mid-plane; the lower half projects onto the - face, the upper onto the +.
      T tMid = d != 0 ? (T(0.5) - o) / d : std::numeric_limits<T>::infinity();
      const bool startsUpper = o + t0 * d >= T(0.5) && !(d < 0 && o + t0 * d == T(0.5));
      const int first = 2 * axis + (startsUpper ? 1 : 0);
      if (!(tMid > t0 && tMid < t1)) {
        // One half only: decided by the segment's middle, which rounding cannot put on the plane.
        const int face = 2 * axis + (o + T(0.5) * (t0 + t1) * d >= T(0.5) ? 1 : 0);
        return skipSearchFace(codes, r, index, ray, frame, face, t0, t1, T(0.5));
      }
      const Hit hit = skipSearchFace(codes, r, index, ray, frame, first, t0, tMid, T(0.5));
      if (hit.valid()) return hit;
      Hit second = skipSearchFace(codes, r, index, ray, frame, first ^ 1, tMid, t1, T(0.5));
      second.steps += hit.steps;
      return second;
    }
  }

  template <class Codes>
  Hit skipSearchFace(const Codes& codes, const relief::CellRecord& r, std::int32_t index,
                     const Ray<T>& ray, const CellFrame& frame, int face, T t0, T t1,
                     T depthLimit) const {
    const int layer = r.layerOf(face);
    if (layer < 0 || !(t1 > t0)) return {};
    const int axis = cells::faceAxis(face), ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const T scale = T(mModel.texels - 1);
    // Along the segment, parameter s in [0, 1]: depth, and position in sample units.
    const Vec3<T> p0 = frame.origin + t0 * frame.direction;
    const Vec3<T> dp = (t1 - t0) * frame.direction;
    const bool upper = cells::faceSign(face) > 0;
    const T depth0 = upper ? T(1) - p0[axis] : p0[axis];
    const T dDepth = upper ? -dp[axis] : dp[axis];
    const T x0 = p0[ua] * scale, dx = dp[ua] * scale;
    const T y0 = p0[va] * scale, dy = dp[va] * scale;
    auto depthAt = [&](T s) { return glm::clamp(depth0 + s * dDepth, T(0), depthLimit); };
    const int top = mPyramid.levels() - 1;
    int level = top;
    T s = 0;
    std::uint32_t steps = 0;
    auto hitAt = [&](T sHit) {
      const T t = t0 + sHit * (t1 - t0);
      projection::FacePoint<T> fp;
      fp.face = face;
      const Vec3<T> p = glm::clamp(frame.origin + t * frame.direction, Vec3<T>(0), Vec3<T>(1));
      fp.uv = Vec2<T>(p[ua], p[va]);
      fp.distance = depthAt(sHit);
      return makeHit(index, ray, t, fp, steps);
    };
    // Which side of the surface the ray is on, as the sampled search reads it: an empty texel
    // cell (the rim of the surface's projection) reads as outside, so entering a texel cell
    // below its surface, or leaving one into the rim, is a crossing at the texel cell's edge.
    // In a cell with a hole's rim an empty texel cell tells no side (`known` false): the next
    // texel cell with surface decides it instead of making a crossing.
    const bool open = r.openSurface();
    bool inside = false, known = true;
    if (const std::optional<T> d = stored(codes, layer, Vec2<T>(p0[ua], p0[va]))) inside = depthAt(0) > *d;
    else known = !open;
    constexpr T kProgress = T(constants::kSkipProgress);  // a floor on each advance, against rounding stalls
    while (s < T(1)) {
      ++steps;
      const int size = 1 << level, nodes = mPyramid.size(level);
      // The node the ray is in, nudged along the ray so boundaries go to the node ahead.
      const T x = x0 + s * dx, y = y0 + s * dy;
      const int ix = std::clamp(int(std::floor((x + nudge(x, dx)) / T(size))), 0, nodes - 1);
      const int iy = std::clamp(int(std::floor((y + nudge(y, dy)) / T(size))), 0, nodes - 1);
      // An axis along which the ray is already past the layer's edge and moving away never
      // exits a node: it must not hold the walk at s (rounding puts a ray there near cell edges).
      const T edge = T(mPyramid.size(0));
      T sExit = T(1);
      if (dx != 0 && !(dx > 0 ? x >= edge : x <= 0))
        sExit = std::min(sExit, (T(dx > 0 ? (ix + 1) * size : ix * size) - x0) / dx);
      if (dy != 0 && !(dy > 0 ? y >= edge : y <= 0))
        sExit = std::min(sExit, (T(dy > 0 ? (iy + 1) * size : iy * size) - y0) / dy);
      sExit = std::max(sExit, s + kProgress);
      const std::uint32_t code = nodeCode(codes, layer, level, ix, iy);
      const T deepest = std::max(depthAt(s), depthAt(std::min(sExit, T(1))));
      if (mPyramid.isEmptyCode(code) || deepest < T(code) * mDistanceScale) {
        // No surface under the node, or all of it beyond the ray here: outside, unless the node
        // is empty in a cell with a hole's rim, where that tells no side.
        if (open && mPyramid.isEmptyCode(code)) {
          known = false;
        } else {
          if (inside && known) return hitAt(s);
          known = true;
        }
        inside = false;
        s = sExit;
        level = std::min(level + 1, top);
        continue;
      }
      if (level > 0) {
        --level;
        continue;
      }
      // A texel cell: f(s) = depth(s) - bilinear(x(s), y(s)) is a quadratic in s.
      const T s1 = std::min(sExit, T(1));
      const T d00 = T(codes(layer, ix, iy)) * mDistanceScale;
      const T d10 = T(codes(layer, ix + 1, iy)) * mDistanceScale;
      const T d01 = T(codes(layer, ix, iy + 1)) * mDistanceScale;
      const T d11 = T(codes(layer, ix + 1, iy + 1)) * mDistanceScale;
      const T ax = x0 - T(ix), ay = y0 - T(iy);  // local coordinates at s = 0, slopes dx, dy
      const T e = d00 - d10 - d01 + d11;
      // bilinear = d00 + (d10 - d00) fx + (d01 - d00) fy + e fx fy with fx = ax + dx s, fy = ay + dy s
      const T c0 = d00 + (d10 - d00) * ax + (d01 - d00) * ay + e * ax * ay;
      const T c1 = (d10 - d00) * dx + (d01 - d00) * dy + e * (ax * dy + ay * dx);
      const T c2 = e * dx * dy;
      // Depth is clamped to the half-cell in planar cells; the texel walk stays inside it.
      const T qa = -c2, qb = dDepth - c1, qc = depth0 - c0;
      auto f = [&](T at) { return (qa * at + qb) * at + qc; };
      if (!known) inside = f(s) > 0, known = true;
      if ((f(s) > 0) != inside) return hitAt(s);
      if (const std::optional<T> root = firstRoot(qa, qb, qc, s, s1)) return hitAt(*root);
      inside = f(s1) > 0;
      s = sExit;
      level = std::min(level + 1, top);
    }
    return missAfter(steps);
  }

  /// A ratio of linear functions of the ray parameter, (n0 + n1 t) / (d0 + d1 t): a face
  /// coordinate of a central projection along a ray. Monotone wherever the denominator keeps
  /// its sign, as it does within one face's stretch of the ray.
  struct LinearRatio {
    T n0 = 0, n1 = 0, d0 = 1, d1 = 0;
    T at(T t) const { return (n0 + n1 * t) / (d0 + d1 * t); }
    /// Where at() takes `value`.
    T solve(T value) const { return (value * d0 - n0) / (n1 - value * d1); }
    /// The sign of its derivative.
    T direction() const { return n1 * d0 - n0 * d1; }
  };

  /// A central projection (perspective, or axial: the centre is the foot on the axis) along a
  /// ray in cell units. With w(t) = p(t) - centre, linear in t, the point lies at the fraction
  /// r_F(t) = w_a(t) / (plane_F - centre_a) of the line from the centre to its point on face F
  /// (axis a), so the line leaves through the face of largest r_F; r_F, and with it the
  /// point's depth fraction 1 - r_F, is linear in t, and each face coordinate is a LinearRatio.
  struct CentralRay {
    Vec3<T> origin{0}, direction{0};  ///< the ray
    Vec3<T> centre{0};                ///< axial: a point of the axis
    Vec3<T> w0{0}, w1{0};             ///< w(t) = w0 + t w1
    int axis = -1;                    ///< axial: the axis, whose faces are never reached; else -1

    T reach(int face) const { return (cells::faceSign(face) > 0 ? T(1) : T(0)) - centre[cells::faceAxis(face)]; }
    /// A line from the centre can leave through the face (the centre does not lie in its plane).
    bool reachable(int face) const { return cells::faceAxis(face) != axis && reach(face) != T(0); }
    T ratio0(int face) const { return w0[cells::faceAxis(face)] / reach(face); }
    T ratio1(int face) const { return w1[cells::faceAxis(face)] / reach(face); }
    LinearRatio coordinate(int face, int along) const {
      if (along == axis) return {origin[along], direction[along], T(1), T(0)};
      const int a = cells::faceAxis(face);
      const T k = reach(face);
      return {centre[along] * w0[a] + k * w0[along], centre[along] * w1[a] + k * w1[along], w0[a], w1[a]};
    }
  };

  template <class P>
  static CentralRay centralRay(const P& proj, const CellFrame& frame) {
    CentralRay c;
    c.origin = frame.origin;
    c.direction = frame.direction;
    if constexpr (std::is_same_v<P, projection::AxialProjection<T>>) {
      c.centre = proj.point;
      c.axis = proj.axis;
    } else {
      c.centre = proj.centre;
    }
    c.w0 = frame.origin - c.centre;
    c.w1 = frame.direction;
    if (c.axis >= 0) c.w0[c.axis] = c.w1[c.axis] = T(0);
    return c;
  }

  /// The face the point at t projects onto: the largest r_F, a tie to the one growing faster.
  static int exitFaceAt(const CentralRay& c, T t) {
    int best = -1;
    T bestRatio = -std::numeric_limits<T>::infinity(), bestSlope = bestRatio;
    for (int f = 0; f < cells::kFaceCount; ++f) {
      if (!c.reachable(f)) continue;
      const T ratio = c.ratio0(f) + t * c.ratio1(f), slope = c.ratio1(f);
      if (ratio > bestRatio || (ratio == bestRatio && slope > bestSlope)) best = f, bestRatio = ratio, bestSlope = slope;
    }
    return best;
  }

  /// Where the ray's points stop projecting onto `face` after t (before tEnd), and onto which
  /// face they go then (-1: none before tEnd). r_F is linear, so each face has one stretch.
  static std::pair<T, int> faceChange(const CentralRay& c, int face, T t, T tEnd) {
    T when = tEnd;
    int next = -1;
    for (int g = 0; g < cells::kFaceCount; ++g) {
      if (g == face || !c.reachable(g)) continue;
      const T gap0 = c.ratio0(g) - c.ratio0(face), gap1 = c.ratio1(g) - c.ratio1(face);
      if (!(gap1 > 0)) continue;  // never overtakes as t grows
      const T at = -gap0 / gap1;
      if (at > t && at < when) when = at, next = g;
    }
    return {when, next};
  }

  /// The side of the surface a central skip walk is on: the field's sign, and whether it is
  /// known (a cell with a hole's rim reads no side from an empty line).
  struct WalkSide {
    bool positive = false;
    bool known = true;
  };

  /// Perspective and axial cells (not interior ones): the ray is split where its points change
  /// face, and on each face it walks the layer's min pyramid as in skipSearchFace. A node is
  /// skipped when no line through it can hold the surface on the ray: the ray's deepest point
  /// there (depth fraction, linear in t) times the longest line of the node (at a corner: the
  /// distance from the centre is convex on the face) stays below the node's least distance.
  /// The texel cells it cannot skip are sampled (kCentralTexelSamples each) and a crossing is
  /// refined by the binary search, as in the linear search.
  template <class Codes, class P>
  Hit centralSkipSearch(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index,
                        const Ray<T>& ray, const CellFrame& frame, T t0, T t1, T fStart) const {
    const CentralRay central = centralRay(proj, frame);
    WalkSide side{fStart > 0, !(r.openSurface() && isEmptyField(fStart))};
    std::uint32_t steps = 1;  // the field at t0
    T t = t0;
    int face = exitFaceAt(central, t), previous = -1;
    while (face >= 0 && t < t1) {
      const auto [tEnd, next] = faceChange(central, face, t, t1);
      const Hit hit =
          centralSkipFace(codes, proj, r, index, ray, frame, central, face, previous, t, tEnd, side, steps);
      if (hit.valid()) return hit;
      t = tEnd;
      previous = face;
      face = next;
    }
    return missAfter(steps);
  }

  template <class Codes, class P>
  Hit centralSkipFace(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index,
                      const Ray<T>& ray, const CellFrame& frame, const CentralRay& central, int face,
                      int previous, T ta, T tb, WalkSide& side, std::uint32_t& steps) const {
    auto local = [&](T t) { return frame.origin + t * frame.direction; };
    auto hitAt = [&](T t) {
      projection::FacePoint<T> fp;
      field(codes, proj, r, local(t), fp);
      return makeHit(index, ray, t, fp, steps);
    };
    const bool open = r.openSurface();
    // A stretch the walk proves to be on one side: entering it from the other is a crossing
    // at its start. An empty node in a cell with a hole's rim tells no side.
    auto enter = [&](bool positive, bool tellsSide, T t) {
      const bool crossed = tellsSide && side.known && side.positive != positive;
      side = {positive, tellsSide};
      return crossed ? hitAt(t) : Hit{};
    };
    const int layer = r.layerOf(face);
    if (layer < 0 || !(tb > ta)) {
      ++steps;
      return layer < 0 ? enter(false, !open, ta) : Hit{};  // no map: every line here is empty
    }
    const T scale = T(mModel.texels - 1);
    const LinearRatio u = central.coordinate(face, projection::faceUAxis(face));
    const LinearRatio v = central.coordinate(face, projection::faceVAxis(face));
    const T du = u.direction(), dv = v.direction();
    const T r0 = central.ratio0(face), r1 = central.ratio1(face);
    auto depthAt = [&](T t) { return glm::clamp(T(1) - (r0 + r1 * t), T(0), T(1)); };
    // Squared: the longest of a node's four lines takes one square root, not four (the root
    // is monotonic and correctly rounded, so the result is the same).
    auto squaredLineLength = [&](int x, int y) {
      const Vec3<T> q = projection::facePoint<T>(face, Vec2<T>(T(x), T(y)) / scale);
      const Vec3<T> e = q - proj.lineEnd(face, q);
      return e.x * e.x + e.y * e.y + e.z * e.z;
    };
    // The floor on each advance: a fraction of the stretch, and never below a few ulps of t.
    auto advance = [&](T from) {
      return from + std::max(T(constants::kSkipProgress) * (tb - ta),
                             T(constants::kNudgeUlps) * std::numeric_limits<T>::epsilon() * std::max(T(1), std::abs(from)));
    };
    const int top = mPyramid.levels() - 1;
    const T edge = T(mPyramid.size(0));
    int level = top;
    // The position in texel units. Where the walk crossed a node boundary it is that boundary,
    // exactly: recomputed from the rounded t it can land a few ulps short, a rounding that
    // differs between the CPU and a GPU (there the next node would depend on the driver).
    T t = ta, x = u.at(t) * scale, y = v.at(t) * scale;
    // Coming from the previous face, the walk enters on the edge the two faces share: there the
    // coordinate along the previous face's axis is that face's plane, exactly.
    if (previous >= 0) {
      const T plane = cells::faceSign(previous) > 0 ? scale : T(0);
      if (cells::faceAxis(previous) == projection::faceUAxis(face)) x = plane;
      if (cells::faceAxis(previous) == projection::faceVAxis(face)) y = plane;
    }
    T xBoundary = 0, yBoundary = 0;
    auto moveTo = [&](T next, bool acrossU, bool acrossV) {
      t = next;
      x = acrossU ? xBoundary : u.at(t) * scale;
      y = acrossV ? yBoundary : v.at(t) * scale;
    };
    while (t < tb) {
      ++steps;
      const int size = 1 << level, nodes = mPyramid.size(level);
      if (!std::isfinite(x) || !std::isfinite(y)) {  // at the centre itself (0 / 0): step past it
        moveTo(std::min(tb, advance(t)), false, false);
        continue;
      }
      const int ix = std::clamp(int(std::floor((x + nudge(x, du)) / T(size))), 0, nodes - 1);
      const int iy = std::clamp(int(std::floor((y + nudge(y, dv)) / T(size))), 0, nodes - 1);
      // An axis along which the ray is past the layer's edge and moving away never exits. The
      // ratio takes the boundary's value once more on its other branch (past its pole), where
      // the denominator has the other sign: that one is no exit.
      T tExit = tb;
      bool acrossU = false, acrossV = false;
      auto exitAt = [&](const LinearRatio& c, T boundary, bool& across) {
        const T at = c.solve(boundary / scale);
        if ((c.d0 + c.d1 * at > 0) != (c.d0 + c.d1 * t > 0) || at > tExit) return;
        if (at < tExit) acrossU = acrossV = false;
        tExit = at;
        across = true;
      };
      xBoundary = T(du > 0 ? (ix + 1) * size : ix * size);
      yBoundary = T(dv > 0 ? (iy + 1) * size : iy * size);
      if (du != 0 && !(du > 0 ? x >= edge : x <= 0)) exitAt(u, xBoundary, acrossU);
      if (dv != 0 && !(dv > 0 ? y >= edge : y <= 0)) exitAt(v, yBoundary, acrossV);
      if (const T least = advance(t); !(tExit >= least)) tExit = least, acrossU = acrossV = false;
      if (tExit >= tb) tExit = tb, acrossU = acrossV = false;
      const std::uint32_t code = nodeCode(codes, layer, level, ix, iy);
      bool skip = mPyramid.isEmptyCode(code);
      if (!skip) {
        const int xa = ix * size, xb = std::min((ix + 1) * size, mModel.texels - 1);
        const int ya = iy * size, yb = std::min((iy + 1) * size, mModel.texels - 1);
        const T longest = std::sqrt(std::max({squaredLineLength(xa, ya), squaredLineLength(xb, ya),
                                              squaredLineLength(xa, yb), squaredLineLength(xb, yb)}));
        skip = std::max(depthAt(t), depthAt(tExit)) * longest < T(code) * mDistanceScale;
      }
      if (skip) {
        // No surface under the node, or all of it beyond the ray here: outside (f < 0).
        if (const Hit hit = enter(false, !(open && mPyramid.isEmptyCode(code)), t); hit.valid()) return hit;
        moveTo(tExit, acrossU, acrossV);
        level = std::min(level + 1, top);
        continue;
      }
      if (level > 0) {
        --level;
        continue;
      }
      // A texel cell the bound cannot skip: sample it.
      T tPrev = t;
      projection::FacePoint<T> fp;
      for (int k = 1; k <= constants::kCentralTexelSamples; ++k) {
        const T ts = t + (tExit - t) * T(k) / T(constants::kCentralTexelSamples);
        const T f = field(codes, proj, r, local(ts), fp);
        ++steps;
        if (open && isEmptyField(f)) {
          side.known = false;
        } else {
          if (side.known && (f > 0) != side.positive)
            return refineCrossing(codes, proj, r, index, ray, frame, tPrev, ts, side.positive, steps);
          side = {f > 0, true};
        }
        tPrev = ts;
      }
      moveTo(tExit, acrossU, acrossV);
      level = std::min(level + 1, top);
    }
    return Hit{};
  }

  /// The smallest root of a s^2 + b s + c in [lo, hi] where the sign changes or touches zero.
  static std::optional<T> firstRoot(T a, T b, T c, T lo, T hi) {
    auto value = [&](T s) { return (a * s + b) * s + c; };
    const T fLo = value(lo), fHi = value(hi);
    // The end values decide when rounding defeats the closed form: a sign change always has a
    // root, found by bisection then.
    const bool signChange = (fLo > 0) != (fHi > 0);
    auto bisect = [&] {
      T l = lo, h = hi;
      for (int i = 0; i < constants::kRootBisections; ++i) {
        const T m = T(0.5) * (l + h);
        ((value(m) > 0) == (fLo > 0) ? l : h) = m;
      }
      return h;
    };
    const T magnitude = std::abs(a) + std::abs(b) + std::abs(c);
    if (std::abs(a) <= T(constants::kQuadraticEpsilon) * std::max(magnitude, T(1e-30))) {
      if (b != 0) {
        const T s = -c / b;
        if (s >= lo && s <= hi) return s;
      } else if (c == 0) {
        return lo;
      }
      return signChange ? std::optional<T>(bisect()) : std::nullopt;
    }
    const T disc = b * b - 4 * a * c;
    if (disc < 0) return signChange ? std::optional<T>(bisect()) : std::nullopt;
    const T q = T(-0.5) * (b + std::copysign(std::sqrt(disc), b));
    T r0 = q / a, r1 = q != 0 ? c / q : r0;
    if (r0 > r1) std::swap(r0, r1);
    if (r0 >= lo && r0 <= hi) return r0;
    if (r1 >= lo && r1 <= hi) return r1;
    // Rounding can push a root just outside while the end values still differ in sign.
    return signChange ? std::optional<T>(bisect()) : std::nullopt;
  }

  /// The hit record at t, without shading (trace() shades the one it returns).
  Hit makeHit(std::int32_t index, const Ray<T>& ray, T t, const projection::FacePoint<T>& fp,
              std::uint32_t steps) const {
    Hit hit;
    hit.t = t;
    hit.position = ray.at(t);
    hit.cell = index;
    hit.face = fp.face;
    hit.uv = Vec2f(glm::clamp(fp.uv, Vec2<T>(0), Vec2<T>(1)));
    hit.texel = hit.uv * float(mModel.texels - 1);
    hit.steps = steps;
    return hit;
  }

  /// Shading normal and color at a hit: from the maps when stored, else from the unprojected
  /// neighbouring samples (the local surface of the distance map).
  template <class Codes, class P>
  void shade(const Codes& codes, const P& proj, const relief::CellRecord& r, Hit& hit) const {
    const int layer = r.layerOf(hit.face);
    if (layer < 0) return;
    const int texels = mModel.texels;
    int a = std::clamp(int(std::lround(hit.texel.x)), 0, texels - 1);
    int b = std::clamp(int(std::lround(hit.texel.y)), 0, texels - 1);
    // A hit at the rim of the surface's projection (a crossing found at a cell face or a texel
    // edge) can round to an empty sample: shade from the nearest filled one within two samples.
    if (mModel.distanceCodec.isEmpty(codes(layer, a, b))) {
      int best = std::numeric_limits<int>::max(), bestA = a, bestB = b;
      const int radius = constants::kShadeSearchRadius;
      for (int y = std::max(0, b - radius); y <= std::min(texels - 1, b + radius); ++y)
        for (int x = std::max(0, a - radius); x <= std::min(texels - 1, a + radius); ++x) {
          const int d2 = (x - a) * (x - a) + (y - b) * (y - b);
          if (d2 < best && !mModel.distanceCodec.isEmpty(codes(layer, x, y)))
            best = d2, bestA = x, bestB = y;
        }
      a = bestA;
      b = bestB;
    }
    if (mModel.normalFormat != relief::NormalFormat::None) {
      hit.normal = mModel.normal(layer, a, b);
    } else {
      auto point = [&](int x, int y) -> std::optional<Vec3d> {
        if (x < 0 || y < 0 || x >= texels || y >= texels) return std::nullopt;
        const double d = mModel.distance(layer, x, y);
        if (std::isnan(d)) return std::nullopt;
        return Vec3d(proj.unproject(hit.face, Vec2<T>(T(x) / T(texels - 1), T(y) / T(texels - 1)), T(d)));
      };
      // Central differences where both neighbours exist, one-sided ones at the edge of the
      // surface; none (the caller's reverse ray direction) when the sample stands alone.
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
      // The samples see the surface from the face; in an interior cell whose centre is outside,
      // the outside is behind the surface, not in front of it.
      if (r.configuration == 0 && !r.centreInside()) n = -n;
      hit.normal = glm::length(n) > 0 ? Vec3f(glm::normalize(n)) : Vec3f(0);
    }
    if (mModel.colorFormat == relief::ColorFormat::Rgba8)
      for (int c = 0; c < 4; ++c) hit.color[c] = mModel.colors.at(a, b, layer, c);
  }

  const relief::ReliefModel& mModel;
  TraceOptions mOptions;
  openvdb::Int32Grid::Ptr mGrid;
  Aabb<T> mBounds;
  Vec3<T> mOrigin{0};
  T mCellSize = 1;
  T mDistanceScale = 0;
  EmptySpacePyramid mPyramid;
  bool mOpenModel = false;  ///< ReliefModel::openSurface(): no side carried across cell faces
};

using ReliefTracerf = ReliefTracer<float>;
using ReliefTracerd = ReliefTracer<double>;

}  // namespace cellrelief::trace
