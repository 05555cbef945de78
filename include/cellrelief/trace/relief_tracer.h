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
/// and the search policy are template parameters of the tracer. The member bodies are in
/// relief_tracer.ipp, included at the end.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>
#include <optional>
#include <type_traits>

#include "cellrelief/cells/openvdb_grids.h"
#include "cellrelief/core/aabb.h"
#include "cellrelief/core/ray.h"
#include "cellrelief/relief/relief_model.h"
#include "cellrelief/relief/surface_bounds.h"
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
  explicit ReliefTracer(const relief::ReliefModel& model, const TraceOptions& options = {});

  const relief::ReliefModel& model() const { return mModel; }
  const TraceOptions& options() const { return mOptions; }
  /// The box rays are clipped to: the surface's (relief/surface_bounds.h), not the grid's cube.
  const Aabb<T>& boundsWS() const { return mBounds; }
  /// Bytes the tracer adds to the model (the pyramid and the cells' reach boxes; the sparse grid
  /// mirrors the cell table).
  std::size_t accelerationBytes() const {
    return mPyramid.byteSize() + mCellReach.size() * sizeof(relief::CellReach);
  }
  /// The part of a ray's segment origin + t direction, t in [t0, t1], in the unit frame of cell
  /// `index` where it can meet a change of side (relief::CellReach): [t0, t1] narrowed to it, or
  /// false when there is none. Outside it the field keeps one side: the linear search samples
  /// only the narrowed part, and a segment without one takes constants::kLinearStepsOutsideReach
  /// steps (its exit).
  bool clipToReach(std::int32_t index, const Vec3<T>& origin, const Vec3<T>& direction, T& t0, T& t1) const {
    return mCellReach[std::size_t(index)].clip(origin, direction, t0, t1);
  }

  /// The nearest hit of the ray (world space) within [ray.tmin, ray.tmax]. The direction need not
  /// be normalized; t is in units of it.
  Hit intersect(const Ray<T>& ray) const { return trace(ray, true); }

  /// Whether anything lies on the ray within [tmin, tmax] (shadow rays): the search without the
  /// shading of the hit.
  bool occluded(const Ray<T>& ray) const { return trace(ray, false).valid(); }

  /// The signed field the search reads at a world point (positive inside the object), or nullopt
  /// outside every grey cell: for diagnostics, such as telling a search that stepped over the
  /// surface from a relief that has none there (bench_silhouettes).
  std::optional<T> fieldAt(const Vec3<T>& pointWS) const;

  /// For tracers that run the search elsewhere (the packet tracer, packet_tracer.h): the cell
  /// index of each grid cell (-1 for white and black ones), and the hit record intersect()
  /// returns for a search that met the surface at t in cell `index` (where the point projects:
  /// fp), shaded as intersect() shades it.
  const openvdb::Int32Grid& cellGrid() const { return *mGrid; }
  /// The ray as intersect() traces it, set up in place (its inverse direction recomputed: the
  /// ray's fields are public and may disagree), and its stretch inside the grid; nullopt when it
  /// meets nothing: a ray without a finite origin and a finite, non-zero direction, with an
  /// empty or NaN interval, or one that misses the grid.
  std::optional<RayInterval<T>> prepareRay(Ray<T>& ray) const;
  /// searchCell's rule at a cell face, for a known side in a closed model: a ray that was
  /// inside (or not) and left the last grey cell where |f| was `exitField` meets the surface at
  /// the face of a cell whose field reads fIn there.
  bool crossesAtFace(T fIn, bool inside, T exitField) const;
  Hit finishHit(std::int32_t index, const Ray<T>& ray, T t, const projection::FacePoint<T>& fp,
                std::uint32_t steps, bool shadeHit) const;

 private:
  /// The texel width is chosen here, once per ray: below, reading a sample has no branch on it.
  Hit trace(const Ray<T>& input, bool shadeHit) const {
    return mModel.visitDistanceCodes([&](const auto& codes) { return traceWith(codes, input, shadeHit); });
  }

  template <class Codes>
  Hit traceWith(const Codes& codes, const Ray<T>& input, bool shadeHit) const;

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
  std::optional<T> stored(const Codes& codes, int layer, const Vec2<T>& uv, bool emptyLinesCrossed = false) const;

  /// A texel of an interior cell (case 0) with some but not all of its samples empty: a model
  /// built without distances before the face (conversion stores them: convert.h,
  /// sampleBeforeFaces, so its interior cells have no empty sample in a layer; the rule stays for
  /// models made otherwise). Codes here are less the zero code. An empty
  /// line there lies wholly on the centre's side, so the surface crossed the face before it; a
  /// filled one, after its face point, at its distance. Read as empty, the whole texel took the
  /// centre's side, and the relief grew by up to a texel where the surface leaves the cell
  /// through a domain face (the most of the "only ours" disagreements with Embree on closed
  /// meshes). Instead an empty sample reads as a distance at or before the face:
  /// - alone, the plane through the other three (the parallelogram rule), at most 0;
  /// - with other empty ones, half the negated mean of the filled samples, which puts the
  ///   surface's crossing of the face two thirds of the way from a filled sample to an empty one.
  /// Of the values tried (0, 1/2, 1 and 2 times the negated mean; bench_silhouettes, four
  /// meshes), 1/2 disagreed least with Embree; on the ten meshes of the verification suite it is
  /// as good as or better than the negated mean alone on every one (docs/trace.md).
  static void mixedTexel(T& c00, T& c10, T& c01, T& c11, T empty, int emptyCount) {
    if (emptyCount == 1) {
      if (c00 >= empty) c00 = std::min(c10 + c01 - c11, T(0));
      if (c10 >= empty) c10 = std::min(c00 + c11 - c01, T(0));
      if (c01 >= empty) c01 = std::min(c00 + c11 - c10, T(0));
      if (c11 >= empty) c11 = std::min(c10 + c01 - c00, T(0));
      return;
    }
    auto filled = [&](T c) { return c < empty ? c : T(0); };
    const T beforeFace = T(-0.5) * (filled(c00) + filled(c10) + filled(c01) + filled(c11)) / T(4 - emptyCount);
    for (T* c : {&c00, &c10, &c01, &c11})
      if (*c >= empty) *c = beforeFace;
  }

  /// The signed field at a unit-cell point: positive inside the object, negative outside.
  /// f = distance from the face minus the stored distance is negative between the face and the
  /// surface, positive beyond it. Domain faces of every cell but the interior ones border white
  /// space, so there "beyond" is inside and a line with no surface is outside. An interior cell
  /// (case 0) projects from its centre; a line with no surface lies on the centre's side, and a
  /// line with surface has the centre's side beyond it (CellRecord::centreInside says which).
  template <class Codes, class P>
  T field(const Codes& codes, const P& proj, const relief::CellRecord& r, const Vec3<T>& p,
          projection::FacePoint<T>& fp) const;

  /// Searches the ray segment [t0, t1] inside one grey cell. `side` is where the ray was when it
  /// entered (updated to where it leaves when there is no hit). A surface lying in the face
  /// shared with the previous cell, or thinner than a sample there, shows no sign change inside
  /// either cell; the side carried across the face catches it: entering on the other side of
  /// the surface is a hit at the face.
  template <class Codes, class P>
  Hit searchCell(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index, const Ray<T>& ray,
                 const CellFrame& frame, T t0, T t1, Side& side) const;

  template <class Codes, class P>
  Hit searchInside(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index, const Ray<T>& ray,
                   const CellFrame& frame, T t0, T t1, T fStart,
                   const projection::FacePoint<T>& fpStart, T& fEnd) const;

  /// fStart, fpStart: the field and projection at t0; fEnd: set to the field at t1 when nothing
  /// is hit. `reach`: the part of [t0, t1] clipToReach leaves, which the linear samples cover;
  /// where there is none (!reach.hit), constants::kLinearStepsOutsideReach steps over [t0, t1].
  template <class Codes, class P>
  Hit linearBinarySearch(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index,
                         const Ray<T>& ray, const CellFrame& frame, T t0, T t1, T fStart,
                         const projection::FacePoint<T>& fpStart, T& fEnd,
                         const RayInterval<T>& reach) const;

  /// The binary search between a sample on one side of the surface (lo, field fLo) and one on
  /// the other (hi, fHi), then secantCrossing in the last bracket. fLo may be kUnreadField with
  /// the side's sign (a side the skip walk knows without a value).
  template <class Codes, class P>
  Hit refineCrossing(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index,
                     const Ray<T>& ray, const CellFrame& frame, T lo, T hi, T fLo, T fHi,
                     std::uint32_t steps) const;

  /// A field value not read (beyond every real one and every empty line's).
  static constexpr T kUnreadField = std::numeric_limits<T>::infinity();
  /// Where the field crosses zero in the bracket [lo, hi] (fLo and fHi of opposite sides) if it
  /// is linear between them: one secant step, which leaves a small fraction of the bracket's
  /// error for no field read (the bisections halve it per read). The far end, as the plain
  /// binary search ends, where either end reads no distance (an empty line, a value not read).
  static T secantCrossing(T lo, T hi, T fLo, T fHi) {
    if (!(std::abs(fLo) < kEmptyField && std::abs(fHi) < kEmptyField)) return hi;
    return lo + (hi - lo) * (fLo / (fLo - fHi));
  }

  /// The least distance code under a pyramid node; level 0 (a texel cell, not stored) from its
  /// four samples, empty when any of them is (as the tracer reads it).
  template <class Codes>
  std::uint32_t nodeCode(const Codes& codes, int layer, int level, int ix, int iy) const;

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
                 const CellFrame& frame, T t0, T t1) const;

  template <class Codes>
  Hit skipSearchFace(const Codes& codes, const relief::CellRecord& r, std::int32_t index,
                     const Ray<T>& ray, const CellFrame& frame, int face, T t0, T t1,
                     T depthLimit) const;

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
  static CentralRay centralRay(const P& proj, const CellFrame& frame);

  /// The face the point at t projects onto: the largest r_F, a tie to the one growing faster.
  static int exitFaceAt(const CentralRay& c, T t);

  /// Where the ray's points stop projecting onto `face` after t (before tEnd), and onto which
  /// face they go then (-1: none before tEnd). r_F is linear, so each face has one stretch.
  static std::pair<T, int> faceChange(const CentralRay& c, int face, T t, T tEnd);

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
                        const Ray<T>& ray, const CellFrame& frame, T t0, T t1, T fStart) const;

  template <class Codes, class P>
  Hit centralSkipFace(const Codes& codes, const P& proj, const relief::CellRecord& r, std::int32_t index,
                      const Ray<T>& ray, const CellFrame& frame, const CentralRay& central, int face,
                      int previous, T ta, T tb, WalkSide& side, std::uint32_t& steps) const;

  /// The smallest root of a s^2 + b s + c in [lo, hi] where the sign changes or touches zero.
  static std::optional<T> firstRoot(T a, T b, T c, T lo, T hi);

  /// The hit record at t, without shading (trace() shades the one it returns).
  Hit makeHit(std::int32_t index, const Ray<T>& ray, T t, const projection::FacePoint<T>& fp,
              std::uint32_t steps) const;

  /// Shading normal and color at a hit: from the maps when stored, else from the unprojected
  /// neighbouring samples (the local surface of the distance map).
  template <class Codes, class P>
  void shade(const Codes& codes, const P& proj, const relief::CellRecord& r, Hit& hit) const;

  /// shade(), and the ray's reverse direction where the samples give no normal.
  template <class Codes, class P>
  void shadeFound(const Codes& codes, const P& proj, const relief::CellRecord& r, const Ray<T>& ray,
                  Hit& hit) const {
    shade(codes, proj, r, hit);
    if (hit.normal == Vec3f(0)) hit.normal = Vec3f(-glm::normalize(Vec3d(ray.direction)));
  }

  const relief::ReliefModel& mModel;
  TraceOptions mOptions;
  openvdb::Int32Grid::Ptr mGrid;
  Aabb<T> mBounds;
  std::vector<relief::CellReach> mCellReach;  ///< per cell, where its field can change sign
  Vec3<T> mOrigin{0};
  T mCellSize = 1;
  T mDistanceScale = 0;
  T mZeroCode = 0;  ///< DistanceCodec::zeroCode: codes below it are distances before the face
  EmptySpacePyramid mPyramid;
  bool mOpenModel = false;  ///< ReliefModel::openSurface(): no side carried across cell faces
  T mNearFace = 0;  ///< kNearFaceSamples sample spacings in cell units (crossesAtFace)
};

using ReliefTracerf = ReliefTracer<float>;
using ReliefTracerd = ReliefTracer<double>;

}  // namespace cellrelief::trace

#include "cellrelief/trace/relief_tracer.ipp"

// The project's own programs and tests compile the common tracers once, in
// src/trace/relief_tracer_instances.cpp (target cellrelief_trace_instances, which defines this
// macro for what links it), instead of once per program: each instantiation is over ten seconds
// of the compiler's time. Users of the headers instantiate them as usual.
#ifdef CELLRELIEF_EXTERN_RELIEF_TRACER
#define CELLRELIEF_RELIEF_TRACER_INSTANCES(EXTERN, T)                                            \
  EXTERN template class ReliefTracer<T, BalancedSearch>;                                        \
  EXTERN template ReliefTracer<T, BalancedSearch>::Hit ReliefTracer<T, BalancedSearch>::traceWith( \
      const relief::DistanceCodes<std::uint8_t>&, const Ray<T>&, bool) const;                   \
  EXTERN template ReliefTracer<T, BalancedSearch>::Hit ReliefTracer<T, BalancedSearch>::traceWith( \
      const relief::DistanceCodes<std::uint16_t>&, const Ray<T>&, bool) const;
namespace cellrelief::trace {
CELLRELIEF_RELIEF_TRACER_INSTANCES(extern, float)
CELLRELIEF_RELIEF_TRACER_INSTANCES(extern, double)
}  // namespace cellrelief::trace
#endif
