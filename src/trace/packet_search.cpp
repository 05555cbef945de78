// SPDX-License-Identifier: MIT
/// @file packet_search.cpp
/// The packet search of packet_search.h, compiled by Google Highway once per instruction set
/// (foreach_target.h includes this file again for each) and dispatched at run time. Lane by lane
/// it is ReliefTracer's scalar arithmetic in the same order (the target is built with
/// -ffp-contract=off, so no multiply-add is fused): glm's min and max are written out as it
/// defines them, so that even the sign of a zero matches.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/trace/packet_search.cpp"  // from the project root, an include path
#include <hwy/foreach_target.h>                           // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "cellrelief/trace/packet_search.h"

HWY_BEFORE_NAMESPACE();
namespace cellrelief::trace {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Capped: a wider vector (SVE) must not run past the kPacketLanes arrays.
using D = hn::CappedTag<float, kPacketLanes>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// Must match trace_options.h (constants::kEmptyField, kFootprintProbes); the scalar tracer's
// header brings OpenVDB, which this file keeps out.
constexpr float kEmptyField = 4.0f;
constexpr int kFootprintProbes = 3;

/// glm's max and min: (a < b) ? b : a and (b < a) ? b : a.
HWY_INLINE V GlmMax(V a, V b) {
  return hn::IfThenElse(hn::Lt(a, b), b, a);
}
HWY_INLINE V GlmMin(V a, V b) {
  return hn::IfThenElse(hn::Lt(b, a), b, a);
}
HWY_INLINE V Clamp01(D d, V x) {
  return GlmMin(GlmMax(x, hn::Zero(d)), hn::Set(d, 1.0f));
}

struct Point {
  V c[3];
};

/// Where a point projects: the face (as a float), its face coordinates, its distance.
struct Projected {
  V face, u, v, distance;
};

/// glm::length of a 3-vector: sqrt((x x + y y) + z z).
HWY_INLINE V Length3(V x, V y, V z) {
  return hn::Sqrt(hn::Add(hn::Add(hn::Mul(x, x), hn::Mul(y, y)), hn::Mul(z, z)));
}

/// projection::faceUV of a face on a known axis a: the next two axes, cyclically.
HWY_INLINE void FaceUV(int axis, const Point& p, V& u, V& v) {
  u = p.c[(axis + 1) % 3];
  v = p.c[(axis + 2) % 3];
}

/// projection::detail::exitPoint: where the line from o along w leaves the unit cell (skipping
/// `skipAxis`), lanes where w is zero on every axis excluded by the caller.
HWY_INLINE Projected ExitPoint(D d, const Point& o, const Point& w, const Point& p, int skipAxis) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  V best = hn::Set(d, std::numeric_limits<float>::infinity()), axis = hn::Set(d, -1.0f),
    positive = zero;
  for (int a = 0; a < 3; ++a) {
    if (a == skipAxis) continue;
    const M up = hn::Gt(w.c[a], zero);
    const V t = hn::Div(hn::Sub(hn::IfThenElseZero(up, one), o.c[a]), w.c[a]);
    const M take = hn::And(hn::Ne(w.c[a], zero), hn::Lt(t, best));
    best = hn::IfThenElse(take, t, best);
    axis = hn::IfThenElse(take, hn::Set(d, float(a)), axis);
    positive = hn::IfThenElse(take, hn::IfThenElseZero(up, one), positive);
  }
  Point hit;
  for (int a = 0; a < 3; ++a) {
    const V onPlane = hn::Add(o.c[a], hn::Mul(best, w.c[a]));
    hit.c[a] = Clamp01(d, hn::IfThenElse(hn::Eq(axis, hn::Set(d, float(a))), positive, onPlane));
  }
  const M ax0 = hn::Eq(axis, zero), ax1 = hn::Eq(axis, one);
  Projected out;
  out.face = hn::Add(hn::Add(axis, axis), positive);
  out.u = hn::IfThenElse(ax0, hit.c[1], hn::IfThenElse(ax1, hit.c[2], hit.c[0]));
  out.v = hn::IfThenElse(ax0, hit.c[2], hn::IfThenElse(ax1, hit.c[0], hit.c[1]));
  out.distance =
      Length3(hn::Sub(hit.c[0], p.c[0]), hn::Sub(hit.c[1], p.c[1]), hn::Sub(hit.c[2], p.c[2]));
  return out;
}

/// Where a point on a face's plane, with its other coordinates those of `p`, projects from
/// `p`: the centre (or axis) case of the central projections.
HWY_INLINE Projected OntoFace(D d, int face, const Point& p, const Point& onFace) {
  Projected out;
  const int axis = face / 2;
  out.face = hn::Set(d, float(face));
  FaceUV(axis, onFace, out.u, out.v);
  out.distance = Length3(hn::Sub(onFace.c[0], p.c[0]), hn::Sub(onFace.c[1], p.c[1]),
                         hn::Sub(onFace.c[2], p.c[2]));
  return out;
}

HWY_INLINE Projected Select(M m, const Projected& a, const Projected& b) {
  return {hn::IfThenElse(m, a.face, b.face), hn::IfThenElse(m, a.u, b.u),
          hn::IfThenElse(m, a.v, b.v), hn::IfThenElse(m, a.distance, b.distance)};
}

/// The projections of projections.h, for a point of the closed unit cell.
HWY_INLINE Projected Project(D d, const PacketCell& cell, const Point& p) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f), half = hn::Set(d, 0.5f);
  Projected out;
  switch (cell.projectionType) {
    case 0: {  // parallel: along the normal of one face
      const int face = cell.faceOrAxis, axis = face / 2;
      out.face = hn::Set(d, float(face));
      FaceUV(axis, p, out.u, out.v);
      out.distance = hn::Abs(hn::Sub(face % 2 ? one : zero, p.c[axis]));
      return out;
    }
    case 1: {  // planar: onto the nearer face of the axis
      const int axis = cell.faceOrAxis;
      const M upper = hn::Ge(p.c[axis], half);
      out.face = hn::Add(hn::Set(d, float(2 * axis)), hn::IfThenElseZero(upper, one));
      FaceUV(axis, p, out.u, out.v);
      out.distance = hn::IfThenElse(upper, hn::Sub(one, p.c[axis]), p.c[axis]);
      return out;
    }
    case 3: {  // axial: from the foot on the axis line, perpendicular to it
      const int axis = cell.faceOrAxis;
      Point q, w;
      for (int a = 0; a < 3; ++a) q.c[a] = a == axis ? p.c[a] : hn::Set(d, cell.point[a]);
      for (int a = 0; a < 3; ++a) w.c[a] = hn::Sub(p.c[a], q.c[a]);
      const M onAxis =
          hn::And(hn::And(hn::Eq(w.c[0], zero), hn::Eq(w.c[1], zero)), hn::Eq(w.c[2], zero));
      const Projected exit = ExitPoint(d, q, w, p, axis);
      if (hn::AllFalse(d, onAxis)) return exit;
      Point onFace = p;
      onFace.c[cell.centreFace / 2] = cell.centreFace % 2 ? one : zero;
      return Select(onAxis, OntoFace(d, cell.centreFace, p, onFace), exit);
    }
    default: {  // perspective: from the centre
      Point c, w;
      for (int a = 0; a < 3; ++a) c.c[a] = hn::Set(d, cell.point[a]);
      for (int a = 0; a < 3; ++a) w.c[a] = hn::Sub(p.c[a], c.c[a]);
      const M atCentre =
          hn::And(hn::And(hn::Eq(w.c[0], zero), hn::Eq(w.c[1], zero)), hn::Eq(w.c[2], zero));
      const Projected exit = ExitPoint(d, c, w, p, -1);
      if (hn::AllFalse(d, atCentre)) return exit;
      Point faceCentre;
      for (int a = 0; a < 3; ++a) faceCentre.c[a] = half;
      faceCentre.c[cell.centreFace / 2] = cell.centreFace % 2 ? one : zero;
      return Select(atCentre, OntoFace(d, cell.centreFace, p, faceCentre), exit);
    }
  }
}

/// The four codes of each lane's texel cell, as floats.
struct Corners {
  V c00, c10, c01, c11;
};

/// 16-bit codes by two gathers of 32-bit words: the word at a sample holds it (low half) and its
/// right neighbour (high half), so the rows b0 and b0 + 1 need one gather each. Offsets in bytes
/// fit in 32 bits (packetCell checks the size); a lane without a layer reads the first word.
HWY_INLINE Corners GatherCorners16(D d, const PacketCell& cell, V layer, V a0, V b0) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const auto texels = hn::Set(di, cell.texels);
  const auto index = hn::Add(
      hn::Mul(hn::Add(hn::Mul(hn::ConvertTo(di, layer), texels), hn::ConvertTo(di, b0)), texels),
      hn::ConvertTo(di, a0));
  const auto offset =
      hn::IfThenElseZero(hn::RebindMask(di, hn::Ge(layer, hn::Zero(d))), hn::Add(index, index));
  const std::int32_t* base = static_cast<const std::int32_t*>(cell.codes);
  const auto row0 = hn::BitCast(du, hn::GatherOffset(di, base, offset));
  const auto row1 =
      hn::BitCast(du, hn::GatherOffset(di, base, hn::Add(offset, hn::Add(texels, texels))));
  const auto low = hn::Set(du, 0xFFFFu);
  auto toFloat = [&](auto code) { return hn::ConvertTo(d, hn::BitCast(di, code)); };
  return {toFloat(hn::And(row0, low)), toFloat(hn::ShiftRight<16>(row0)),
          toFloat(hn::And(row1, low)), toFloat(hn::ShiftRight<16>(row1))};
}

template <class Code>
HWY_INLINE Corners LoadCorners(D d, const PacketCell& cell, V layer, V a0, V b0) {
  const Code* codes = static_cast<const Code*>(cell.codes);
  const std::size_t texels = std::size_t(cell.texels);
  HWY_ALIGN float l[kPacketLanes], a[kPacketLanes], b[kPacketLanes];
  HWY_ALIGN float c00[kPacketLanes], c10[kPacketLanes], c01[kPacketLanes], c11[kPacketLanes];
  hn::Store(layer, d, l);
  hn::Store(a0, d, a);
  hn::Store(b0, d, b);
  for (std::size_t i = 0; i < hn::Lanes(d); ++i) {
    if (l[i] < 0) {  // no layer: the field ignores the codes
      c00[i] = c10[i] = c01[i] = c11[i] = 0;
      continue;
    }
    const Code* at =
        codes + (std::size_t(l[i]) * texels + std::size_t(b[i])) * texels + std::size_t(a[i]);
    c00[i] = float(at[0]);
    c10[i] = float(at[1]);
    c01[i] = float(at[texels]);
    c11[i] = float(at[texels + 1]);
  }
  return {hn::Load(d, c00), hn::Load(d, c10), hn::Load(d, c01), hn::Load(d, c11)};
}

/// ReliefTracer::field: positive inside the object, negative outside; the projection of the
/// point into `where`.
HWY_INLINE V Field(D d, const PacketCell& cell, const Point& unclamped, Projected& where) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  Point p;
  for (int a = 0; a < 3; ++a) p.c[a] = Clamp01(d, unclamped.c[a]);
  where = Project(d, cell, p);
  V layer = hn::Set(d, float(cell.layerOfFace[0]));
  for (int f = 1; f < 6; ++f)
    layer = hn::IfThenElse(hn::Eq(where.face, hn::Set(d, float(f))),
                           hn::Set(d, float(cell.layerOfFace[f])), layer);
  // ReliefTracer::stored: bilinear filtering of the vertex-centred samples.
  const V last = hn::Set(d, float(cell.texels - 1)),
          beforeLast = hn::Set(d, float(cell.texels - 2));
  const hn::RebindToSigned<D> di;
  const V x = hn::Mul(hn::IfThenElseZero(hn::Gt(where.u, zero), GlmMin(where.u, one)), last);
  const V y = hn::Mul(hn::IfThenElseZero(hn::Gt(where.v, zero), GlmMin(where.v, one)), last);
  // std::min(T - 2, int(x)): (b < a) ? b : a on integers, exact in float.
  const V a0 = GlmMin(beforeLast, hn::ConvertTo(d, hn::ConvertTo(di, x)));
  const V b0 = GlmMin(beforeLast, hn::ConvertTo(d, hn::ConvertTo(di, y)));
  const V fx = hn::Sub(x, a0), fy = hn::Sub(y, b0);
  Corners c = cell.gather16         ? GatherCorners16(d, cell, layer, a0, b0)
              : cell.codeBits == 16 ? LoadCorners<std::uint16_t>(d, cell, layer, a0, b0)
                                    : LoadCorners<std::uint8_t>(d, cell, layer, a0, b0);
  const V empty = hn::Set(d, cell.emptyCode);
  const M e00 = hn::Ge(c.c00, empty), e10 = hn::Ge(c.c10, empty), e01 = hn::Ge(c.c01, empty),
          e11 = hn::Ge(c.c11, empty);
  const V emptyCount =
      hn::Add(hn::Add(hn::Add(hn::IfThenElseZero(e00, one), hn::IfThenElseZero(e10, one)),
                      hn::IfThenElseZero(e01, one)),
              hn::IfThenElseZero(e11, one));
  const M anyEmpty = hn::Gt(emptyCount, zero);
  M noSurface = hn::Lt(layer, zero);
  if (!cell.interior) {
    noSurface = hn::Or(noSurface, anyEmpty);
  } else if (!hn::AllFalse(d, anyEmpty)) {
    // ReliefTracer::mixedTexel.
    noSurface = hn::Or(noSurface, hn::Eq(emptyCount, hn::Set(d, 4.0f)));
    auto min0 = [&](V v) { return GlmMin(v, zero); };  // std::min(v, 0)
    const V n00 = min0(hn::Sub(hn::Add(c.c10, c.c01), c.c11));
    const V n10 = min0(hn::Sub(hn::Add(c.c00, c.c11), c.c01));
    const V n01 = min0(hn::Sub(hn::Add(c.c00, c.c11), c.c10));
    const V n11 = min0(hn::Sub(hn::Add(c.c10, c.c01), c.c00));
    auto filled = [&](M e, V v) { return hn::IfThenZeroElse(e, v); };
    const V sum =
        hn::Add(hn::Add(hn::Add(filled(e00, c.c00), filled(e10, c.c10)), filled(e01, c.c01)),
                filled(e11, c.c11));
    const V beforeFace =
        hn::Div(hn::Mul(hn::Set(d, -0.5f), sum), hn::Sub(hn::Set(d, 4.0f), emptyCount));
    const M single = hn::Eq(emptyCount, one);
    c.c00 = hn::IfThenElse(e00, hn::IfThenElse(single, n00, beforeFace), c.c00);
    c.c10 = hn::IfThenElse(e10, hn::IfThenElse(single, n10, beforeFace), c.c10);
    c.c01 = hn::IfThenElse(e01, hn::IfThenElse(single, n01, beforeFace), c.c01);
    c.c11 = hn::IfThenElse(e11, hn::IfThenElse(single, n11, beforeFace), c.c11);
  }
  const V top = hn::Add(c.c00, hn::Mul(fx, hn::Sub(c.c10, c.c00)));
  const V bottom = hn::Add(c.c01, hn::Mul(fx, hn::Sub(c.c11, c.c01)));
  const V stored =
      hn::Mul(hn::Add(top, hn::Mul(fy, hn::Sub(bottom, top))), hn::Set(d, cell.distanceScale));
  const bool flipped = cell.interior && !cell.centreInside;
  const V f = flipped ? hn::Sub(stored, where.distance) : hn::Sub(where.distance, stored);
  const V emptyValue = hn::Set(d, cell.interior && cell.centreInside ? kEmptyField : -kEmptyField);
  return hn::IfThenElse(noSurface, emptyValue, f);
}

/// The ray's lanes [lane, lane + Lanes(d)).
struct LaneRays {
  Point o, dir;
  V t0, t1;
};

HWY_INLINE LaneRays LoadRays(D d, const PacketRays& r, std::size_t lane) {
  return {{{hn::Load(d, r.ox + lane), hn::Load(d, r.oy + lane), hn::Load(d, r.oz + lane)}},
          {{hn::Load(d, r.dx + lane), hn::Load(d, r.dy + lane), hn::Load(d, r.dz + lane)}},
          hn::Load(d, r.t0 + lane),
          hn::Load(d, r.t1 + lane)};
}

/// The ray's point at t (frame.origin + t * frame.direction).
HWY_INLINE Point At(const LaneRays& r, V t) {
  return {{hn::Add(r.o.c[0], hn::Mul(t, r.dir.c[0])), hn::Add(r.o.c[1], hn::Mul(t, r.dir.c[1])),
           hn::Add(r.o.c[2], hn::Mul(t, r.dir.c[2]))}};
}

HWY_INLINE Point ClampedAt(D d, const LaneRays& r, V t) {
  Point p = At(r, t);
  for (auto& c : p.c) c = Clamp01(d, c);
  return p;
}

void EnterCell(const PacketCell& cell, PacketRays& rays) {
  const D d;
  for (std::size_t lane = 0; lane < std::size_t(rays.count); lane += hn::Lanes(d)) {
    const LaneRays r = LoadRays(d, rays, lane);
    Projected start;
    const V f = Field(d, cell, At(r, r.t0), start);
    // The footprint of the segment on the maps (linearBinarySearch), from kFootprintProbes
    // points past its start; a change of face counts as a whole face.
    V footprint = hn::Zero(d);
    Projected a = start;
    for (int k = 1; k <= kFootprintProbes; ++k) {
      const V t = hn::Add(r.t0, hn::Div(hn::Mul(hn::Sub(r.t1, r.t0), hn::Set(d, float(k))),
                                        hn::Set(d, float(kFootprintProbes))));
      const Projected b = Project(d, cell, ClampedAt(d, r, t));
      const V du = hn::Sub(b.u, a.u), dv = hn::Sub(b.v, a.v);
      const V length = hn::Sqrt(hn::Add(hn::Mul(du, du), hn::Mul(dv, dv)));
      footprint =
          hn::Add(footprint, hn::IfThenElse(hn::Eq(a.face, b.face), length, hn::Set(d, 1.0f)));
      a = b;
    }
    hn::Store(f, d, rays.fStart + lane);
    hn::Store(start.face, d, rays.faceStart + lane);
    hn::Store(start.u, d, rays.uStart + lane);
    hn::Store(start.v, d, rays.vStart + lane);
    hn::Store(footprint, d, rays.footprint + lane);
  }
}

void SearchCell(const PacketCell& cell, int binarySteps, PacketRays& rays) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f), emptyField = hn::Set(d, kEmptyField);
  const bool planar = cell.projectionType == 1;
  for (std::size_t lane = 0; lane < std::size_t(rays.count); lane += hn::Lanes(d)) {
    const LaneRays r = LoadRays(d, rays, lane);
    const V linear = hn::Load(d, rays.linear + lane);
    const M searched = hn::Gt(linear, zero);
    float mostSteps = 0;
    for (std::size_t i = 0; i < hn::Lanes(d); ++i)
      mostSteps = std::max(mostSteps, rays.linear[lane + i]);
    V fPrev = hn::Load(d, rays.fStart + lane), tPrev = r.t0,
      facePrev = hn::Load(d, rays.faceStart + lane);
    V steps = one, lo = zero, hi = zero, positiveLo = zero;
    M found = hn::FirstN(d, 0);  // none
    const V span = hn::Sub(r.t1, r.t0);
    for (int i = 1; i <= int(mostSteps); ++i) {
      const M live = hn::AndNot(found, hn::And(searched, hn::Le(hn::Set(d, float(i)), linear)));
      if (hn::AllFalse(d, live)) break;
      const V t = hn::Add(r.t0, hn::Div(hn::Mul(span, hn::Set(d, float(i))), linear));
      Projected where;
      const V f = Field(d, cell, At(r, t), where);
      steps = hn::Add(steps, hn::IfThenElseZero(live, one));
      // A step across a planar cell's mid-plane is no crossing; nor, in a cell with a hole's
      // rim, one between an empty line and one with surface.
      const M otherHalf = planar ? hn::Ne(where.face, facePrev) : hn::FirstN(d, 0);
      facePrev = hn::IfThenElse(live, where.face, facePrev);
      M crossing = hn::AndNot(otherHalf, hn::Xor(hn::Gt(fPrev, zero), hn::Gt(f, zero)));
      if (cell.openCell)
        crossing = hn::AndNot(
            hn::Or(hn::Ge(hn::Abs(fPrev), emptyField), hn::Ge(hn::Abs(f), emptyField)), crossing);
      const M hit = hn::And(live, crossing), moved = hn::AndNot(crossing, live);
      lo = hn::IfThenElse(hit, tPrev, lo);
      hi = hn::IfThenElse(hit, t, hi);
      positiveLo = hn::IfThenElse(hit, hn::IfThenElseZero(hn::Gt(fPrev, zero), one), positiveLo);
      found = hn::Or(found, hit);
      fPrev = hn::IfThenElse(moved, f, fPrev);
      tPrev = hn::IfThenElse(moved, t, tPrev);
    }
    hn::Store(fPrev, d, rays.fEnd + lane);
    Projected where{zero, zero, zero, zero};
    if (!hn::AllFalse(d, found)) {
      const M loPositive = hn::Gt(positiveLo, zero);
      for (int k = 0; k < binarySteps; ++k) {
        const V mid = hn::Mul(hn::Set(d, 0.5f), hn::Add(lo, hi));
        Projected unused;
        const M positive = hn::Gt(Field(d, cell, At(r, mid), unused), zero);
        const M toLo = hn::Not(hn::Xor(positive, loPositive));
        lo = hn::IfThenElse(hn::And(found, toLo), mid, lo);
        hi = hn::IfThenElse(hn::AndNot(toLo, found), mid, hi);
        steps = hn::Add(steps, hn::IfThenElseZero(found, one));
      }
      Field(d, cell, At(r, hi), where);
    }
    hn::Store(hn::IfThenElseZero(found, one), d, rays.found + lane);
    hn::Store(hi, d, rays.tHit + lane);
    hn::Store(where.face, d, rays.face + lane);
    hn::Store(where.u, d, rays.u + lane);
    hn::Store(where.v, d, rays.v + lane);
    hn::Store(steps, d, rays.steps + lane);
  }
}

const char* InstructionSet() {
  return hwy::TargetName(HWY_TARGET);
}

}  // namespace HWY_NAMESPACE
}  // namespace cellrelief::trace
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cellrelief::trace {

HWY_EXPORT(EnterCell);
HWY_EXPORT(SearchCell);
HWY_EXPORT(InstructionSet);

void packetEnterCell(const PacketCell& cell, PacketRays& rays) {
  HWY_DYNAMIC_DISPATCH(EnterCell)(cell, rays);
}

void packetSearchCell(const PacketCell& cell, int binarySteps, PacketRays& rays) {
  HWY_DYNAMIC_DISPATCH(SearchCell)(cell, binarySteps, rays);
}

const char* packetInstructionSet() {
  return HWY_DYNAMIC_DISPATCH(InstructionSet)();
}

int packetTargets(PacketTarget* out, int capacity) {
  int n = 0;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets())
    if (n < capacity) out[n++] = {target, hwy::TargetName(target)};
  return n;
}

void packetRestrictTargets(std::int64_t bits) {
  hwy::SetSupportedTargetsForTest(bits);
}

}  // namespace cellrelief::trace
#endif
