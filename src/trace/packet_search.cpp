// SPDX-License-Identifier: MIT
/// @file packet_search.cpp
/// The packet search of packet_search.h, compiled by Google Highway once per instruction set
/// (foreach_target.h includes this file again for each) and dispatched at run time. Lane by lane
/// it is ReliefTracer's scalar arithmetic in the same order (the target is built with
/// -ffp-contract=off, so no multiply-add is fused): glm's min and max are written out as it
/// defines them, so that even the sign of a zero matches.
// Not compiled for SVE and RVV: the search keeps vectors in structs and arrays, which their
// sizeless vector types cannot be. Not for NEON on 32-bit Arm: there Highway's division and
// square root are estimates, and the lanes need IEEE's correctly rounded ones to agree with the
// scalar tracer. (Those CPUs get the best remaining target: EMU128 or scalar.)
#ifndef HWY_DISABLED_TARGETS
#if defined(__arm__) && !defined(__aarch64__)
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV | HWY_NEON)
#else
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "src/trace/packet_search.cpp"  // from the project root, an include path
#include <hwy/foreach_target.h>                           // IWYU pragma: keep

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "cellrelief/trace/packet_search.h"
#include "cellrelief/trace/trace_options.h"

HWY_BEFORE_NAMESPACE();
namespace cellrelief::trace {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Capped: a wider vector (SVE) must not run past the kPacketLanes arrays.
using D = hn::CappedTag<float, kPacketLanes>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// The traversal's constants, shared with the scalar tracer and the shaders.
constexpr float kEmptyField = constants::kEmptyField;
constexpr int kFootprintProbes = constants::kFootprintProbes;

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

/// Each lane's cell, as the field reads it (PacketRays).
struct LaneCells {
  V axis, cellFace, centreFace;
  Point point;
  V layerOfFace[6];
  M interior, centreInside, openCell;
};

/// glm::length of a 3-vector: sqrt((x x + y y) + z z).
HWY_INLINE V Length3(V x, V y, V z) {
  return hn::Sqrt(hn::Add(hn::Add(hn::Mul(x, x), hn::Mul(y, y)), hn::Mul(z, z)));
}

/// Per lane, p's coordinate along `axis` (0, 1 or 2).
HWY_INLINE V Along(D d, V axis, const Point& p) {
  return hn::IfThenElse(hn::Eq(axis, hn::Zero(d)), p.c[0],
                        hn::IfThenElse(hn::Eq(axis, hn::Set(d, 1.0f)), p.c[1], p.c[2]));
}

/// projection::faceUV on a face of `axis` (per lane): the next two axes, cyclically.
HWY_INLINE void FaceUV(D d, V axis, const Point& p, V& u, V& v) {
  const M ax0 = hn::Eq(axis, hn::Zero(d)), ax1 = hn::Eq(axis, hn::Set(d, 1.0f));
  u = hn::IfThenElse(ax0, p.c[1], hn::IfThenElse(ax1, p.c[2], p.c[0]));
  v = hn::IfThenElse(ax0, p.c[2], hn::IfThenElse(ax1, p.c[0], p.c[1]));
}

/// The axis of a face (face / 2, exact for 0..5) and whether it is the positive one.
HWY_INLINE V AxisOf(D d, V face) {
  return hn::Floor(hn::Mul(face, hn::Set(d, 0.5f)));
}
HWY_INLINE M PositiveFace(D d, V face) {
  return hn::Ne(face, hn::Add(AxisOf(d, face), AxisOf(d, face)));
}

/// projection::detail::exitPoint: where the line from o along w leaves the unit cell, skipping
/// the axis `skipAxis` (per lane; -1: none); lanes where w is zero on every other axis are
/// excluded by the caller.
HWY_INLINE Projected ExitPoint(D d, const Point& o, const Point& w, const Point& p, V skipAxis) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  V best = hn::Set(d, std::numeric_limits<float>::infinity()), axis = hn::Set(d, -1.0f),
    positive = zero;
  for (int a = 0; a < 3; ++a) {
    const M up = hn::Gt(w.c[a], zero);
    const V t = hn::Div(hn::Sub(hn::IfThenElseZero(up, one), o.c[a]), w.c[a]);
    const M take = hn::AndNot(hn::Eq(skipAxis, hn::Set(d, float(a))),
                              hn::And(hn::Ne(w.c[a], zero), hn::Lt(t, best)));
    best = hn::IfThenElse(take, t, best);
    axis = hn::IfThenElse(take, hn::Set(d, float(a)), axis);
    positive = hn::IfThenElse(take, hn::IfThenElseZero(up, one), positive);
  }
  Point hit;
  for (int a = 0; a < 3; ++a) {
    const V onPlane = hn::Add(o.c[a], hn::Mul(best, w.c[a]));
    hit.c[a] = Clamp01(d, hn::IfThenElse(hn::Eq(axis, hn::Set(d, float(a))), positive, onPlane));
  }
  Projected out;
  out.face = hn::Add(hn::Add(axis, axis), positive);
  FaceUV(d, axis, hit, out.u, out.v);
  out.distance =
      Length3(hn::Sub(hit.c[0], p.c[0]), hn::Sub(hit.c[1], p.c[1]), hn::Sub(hit.c[2], p.c[2]));
  return out;
}

/// The centre (or axis) case of the central projections: onto the lane's centre face, at the
/// point `base` with its coordinate along that face's axis set to the face's plane.
HWY_INLINE Projected OntoCentreFace(D d, const LaneCells& cells, const Point& p, Point onFace) {
  const V axis = AxisOf(d, cells.centreFace);
  const V plane = hn::IfThenElseZero(PositiveFace(d, cells.centreFace), hn::Set(d, 1.0f));
  for (int a = 0; a < 3; ++a)
    onFace.c[a] = hn::IfThenElse(hn::Eq(axis, hn::Set(d, float(a))), plane, onFace.c[a]);
  Projected out;
  out.face = cells.centreFace;
  FaceUV(d, axis, onFace, out.u, out.v);
  out.distance = Length3(hn::Sub(onFace.c[0], p.c[0]), hn::Sub(onFace.c[1], p.c[1]),
                         hn::Sub(onFace.c[2], p.c[2]));
  return out;
}

HWY_INLINE Projected Select(M m, const Projected& a, const Projected& b) {
  return {hn::IfThenElse(m, a.face, b.face), hn::IfThenElse(m, a.u, b.u),
          hn::IfThenElse(m, a.v, b.v), hn::IfThenElse(m, a.distance, b.distance)};
}

HWY_INLINE M AllZero(D d, const Point& w) {
  const V zero = hn::Zero(d);
  return hn::And(hn::And(hn::Eq(w.c[0], zero), hn::Eq(w.c[1], zero)), hn::Eq(w.c[2], zero));
}

/// The projections of projections.h, for a point of the closed unit cell.
HWY_INLINE Projected Project(D d, int type, const LaneCells& cells, const Point& p) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f), half = hn::Set(d, 0.5f);
  Projected out;
  switch (type) {
    case 0: {  // parallel: along the normal of one face
      out.face = cells.cellFace;
      FaceUV(d, cells.axis, p, out.u, out.v);
      const V target = hn::IfThenElseZero(PositiveFace(d, cells.cellFace), one);
      out.distance = hn::Abs(hn::Sub(target, Along(d, cells.axis, p)));
      return out;
    }
    case 1: {  // planar: onto the nearer face of the axis
      const V along = Along(d, cells.axis, p);
      const M upper = hn::Ge(along, half);
      out.face = hn::Add(hn::Add(cells.axis, cells.axis), hn::IfThenElseZero(upper, one));
      FaceUV(d, cells.axis, p, out.u, out.v);
      out.distance = hn::IfThenElse(upper, hn::Sub(one, along), along);
      return out;
    }
    case 3: {  // axial: from the foot on the axis line, perpendicular to it
      Point q, w;
      for (int a = 0; a < 3; ++a)
        q.c[a] = hn::IfThenElse(hn::Eq(cells.axis, hn::Set(d, float(a))), p.c[a], cells.point.c[a]);
      for (int a = 0; a < 3; ++a) w.c[a] = hn::Sub(p.c[a], q.c[a]);
      const M onAxis = AllZero(d, w);
      const Projected exit = ExitPoint(d, q, w, p, cells.axis);
      if (hn::AllFalse(d, onAxis)) return exit;
      return Select(onAxis, OntoCentreFace(d, cells, p, p), exit);
    }
    default: {  // perspective: from the centre
      Point w;
      for (int a = 0; a < 3; ++a) w.c[a] = hn::Sub(p.c[a], cells.point.c[a]);
      const M atCentre = AllZero(d, w);
      const Projected exit = ExitPoint(d, cells.point, w, p, hn::Set(d, -1.0f));
      if (hn::AllFalse(d, atCentre)) return exit;
      Point faceCentre;
      for (int a = 0; a < 3; ++a) faceCentre.c[a] = half;
      (void)zero;
      return Select(atCentre, OntoCentreFace(d, cells, p, faceCentre), exit);
    }
  }
}

/// The four codes of each lane's texel cell, as floats.
struct Corners {
  V c00, c10, c01, c11;
};

/// 16-bit codes by two gathers of 32-bit words: the word at a sample holds it (low half) and its
/// right neighbour (high half), so the rows b0 and b0 + 1 need one gather each. Offsets in bytes
/// fit in 32 bits (ReliefPacketTracer checks the size); a lane without a layer reads the first
/// word.
HWY_INLINE Corners GatherCorners16(D d, const PacketMaps& maps, V layer, V a0, V b0) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const auto texels = hn::Set(di, maps.texels);
  const auto index = hn::Add(
      hn::Mul(hn::Add(hn::Mul(hn::ConvertTo(di, layer), texels), hn::ConvertTo(di, b0)), texels),
      hn::ConvertTo(di, a0));
  const auto offset =
      hn::IfThenElseZero(hn::RebindMask(di, hn::Ge(layer, hn::Zero(d))), hn::Add(index, index));
  const std::int32_t* base = static_cast<const std::int32_t*>(maps.codes);
  const auto row0 = hn::BitCast(du, hn::GatherOffset(di, base, offset));
  const auto row1 =
      hn::BitCast(du, hn::GatherOffset(di, base, hn::Add(offset, hn::Add(texels, texels))));
  const auto low = hn::Set(du, 0xFFFFu);
  auto toFloat = [&](auto code) { return hn::ConvertTo(d, hn::BitCast(di, code)); };
  return {toFloat(hn::And(row0, low)), toFloat(hn::ShiftRight<16>(row0)),
          toFloat(hn::And(row1, low)), toFloat(hn::ShiftRight<16>(row1))};
}

template <class Code>
HWY_INLINE Corners LoadCorners(D d, const PacketMaps& maps, V layer, V a0, V b0) {
  const Code* codes = static_cast<const Code*>(maps.codes);
  const std::size_t texels = std::size_t(maps.texels);
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
HWY_INLINE V Field(D d, const PacketMaps& maps, int type, const LaneCells& cells,
                   const Point& unclamped, Projected& where) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  Point p;
  for (int a = 0; a < 3; ++a) p.c[a] = Clamp01(d, unclamped.c[a]);
  where = Project(d, type, cells, p);
  V layer = cells.layerOfFace[0];
  for (int f = 1; f < 6; ++f)
    layer = hn::IfThenElse(hn::Eq(where.face, hn::Set(d, float(f))), cells.layerOfFace[f], layer);
  // ReliefTracer::stored: bilinear filtering of the vertex-centred samples.
  const V last = hn::Set(d, float(maps.texels - 1)),
          beforeLast = hn::Set(d, float(maps.texels - 2));
  const hn::RebindToSigned<D> di;
  const V x = hn::Mul(hn::IfThenElseZero(hn::Gt(where.u, zero), GlmMin(where.u, one)), last);
  const V y = hn::Mul(hn::IfThenElseZero(hn::Gt(where.v, zero), GlmMin(where.v, one)), last);
  // std::min(T - 2, int(x)): (b < a) ? b : a on integers, exact in float.
  const V a0 = GlmMin(beforeLast, hn::ConvertTo(d, hn::ConvertTo(di, x)));
  const V b0 = GlmMin(beforeLast, hn::ConvertTo(d, hn::ConvertTo(di, y)));
  const V fx = hn::Sub(x, a0), fy = hn::Sub(y, b0);
  Corners c = maps.gather16         ? GatherCorners16(d, maps, layer, a0, b0)
              : maps.codeBits == 16 ? LoadCorners<std::uint16_t>(d, maps, layer, a0, b0)
                                    : LoadCorners<std::uint8_t>(d, maps, layer, a0, b0);
  // Codes less the zero code (exact in float), as ReliefTracer::stored reads them.
  const V zeroCode = hn::Set(d, maps.zeroCode);
  c.c00 = hn::Sub(c.c00, zeroCode);
  c.c10 = hn::Sub(c.c10, zeroCode);
  c.c01 = hn::Sub(c.c01, zeroCode);
  c.c11 = hn::Sub(c.c11, zeroCode);
  const V empty = hn::Set(d, maps.emptyCode - maps.zeroCode);
  const M e00 = hn::Ge(c.c00, empty), e10 = hn::Ge(c.c10, empty), e01 = hn::Ge(c.c01, empty),
          e11 = hn::Ge(c.c11, empty);
  const V emptyCount =
      hn::Add(hn::Add(hn::Add(hn::IfThenElseZero(e00, one), hn::IfThenElseZero(e10, one)),
                      hn::IfThenElseZero(e01, one)),
              hn::IfThenElseZero(e11, one));
  const M anyEmpty = hn::Gt(emptyCount, zero);
  // Outside interior cells a texel with an empty sample has no surface; inside them, one with
  // four (ReliefTracer::stored).
  M noSurface = hn::Or(hn::Lt(layer, zero), hn::AndNot(cells.interior, anyEmpty));
  noSurface = hn::Or(noSurface, hn::Eq(emptyCount, hn::Set(d, 4.0f)));
  if (!hn::AllFalse(d, hn::And(cells.interior, anyEmpty))) {
    // ReliefTracer::mixedTexel (the lanes it does not apply to take no empty sample's value).
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
      hn::Mul(hn::Add(top, hn::Mul(fy, hn::Sub(bottom, top))), hn::Set(d, maps.distanceScale));
  const M flipped = hn::AndNot(cells.centreInside, cells.interior);
  const V f =
      hn::IfThenElse(flipped, hn::Sub(stored, where.distance), hn::Sub(where.distance, stored));
  const V emptyValue = hn::IfThenElse(hn::And(cells.interior, cells.centreInside),
                                      hn::Set(d, kEmptyField), hn::Set(d, -kEmptyField));
  return hn::IfThenElse(noSurface, emptyValue, f);
}

/// The ray's lanes [lane, lane + Lanes(d)).
struct LaneRays {
  Point o, dir;
  V t0, t1, from, to;
};

HWY_INLINE LaneRays LoadRays(D d, const PacketRays& r, std::size_t lane) {
  return {{{hn::Load(d, r.ox + lane), hn::Load(d, r.oy + lane), hn::Load(d, r.oz + lane)}},
          {{hn::Load(d, r.dx + lane), hn::Load(d, r.dy + lane), hn::Load(d, r.dz + lane)}},
          hn::Load(d, r.t0 + lane),
          hn::Load(d, r.t1 + lane),
          hn::Load(d, r.from + lane),
          hn::Load(d, r.to + lane)};
}

HWY_INLINE LaneCells LoadCells(D d, const PacketRays& r, std::size_t lane) {
  const V one = hn::Set(d, 1.0f);
  LaneCells c;
  c.axis = hn::Load(d, r.axis + lane);
  c.cellFace = hn::Load(d, r.cellFace + lane);
  c.centreFace = hn::Load(d, r.centreFace + lane);
  c.point = {{hn::Load(d, r.px + lane), hn::Load(d, r.py + lane), hn::Load(d, r.pz + lane)}};
  // Lanes past the count read no maps, whatever their arrays hold.
  const M inPacket = hn::FirstN(d, std::size_t(r.count) - lane);
  for (int f = 0; f < 6; ++f)
    c.layerOfFace[f] =
        hn::IfThenElse(inPacket, hn::Load(d, r.layerOfFace[f] + lane), hn::Set(d, -1.0f));
  c.interior = hn::Eq(hn::Load(d, r.interior + lane), one);
  c.centreInside = hn::Eq(hn::Load(d, r.centreInside + lane), one);
  c.openCell = hn::Eq(hn::Load(d, r.openCell + lane), one);
  return c;
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

void EnterCell(const PacketMaps& maps, PacketRays& rays) {
  const D d;
  const int type = rays.projectionType;
  for (std::size_t lane = 0; lane < std::size_t(rays.count); lane += hn::Lanes(d)) {
    const LaneRays r = LoadRays(d, rays, lane);
    const LaneCells cells = LoadCells(d, rays, lane);
    Projected start;
    const V f = Field(d, maps, type, cells, At(r, r.t0), start);
    // The footprint of [from, to] on the maps (linearBinarySearch), from kFootprintProbes
    // points past its start; a change of face counts as a whole face.
    V footprint = hn::Zero(d);
    Projected a = Project(d, type, cells, ClampedAt(d, r, r.from));
    hn::Store(a.face, d, rays.faceFrom + lane);
    for (int k = 1; k <= kFootprintProbes; ++k) {
      const V t = hn::Add(r.from, hn::Div(hn::Mul(hn::Sub(r.to, r.from), hn::Set(d, float(k))),
                                          hn::Set(d, float(kFootprintProbes))));
      const Projected b = Project(d, type, cells, ClampedAt(d, r, t));
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

void SearchCell(const PacketMaps& maps, int binarySteps, PacketRays& rays) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f), emptyField = hn::Set(d, kEmptyField);
  const int type = rays.projectionType;
  const bool planar = type == 1;
  for (std::size_t lane = 0; lane < std::size_t(rays.count); lane += hn::Lanes(d)) {
    const LaneRays r = LoadRays(d, rays, lane);
    const LaneCells cells = LoadCells(d, rays, lane);
    const V linear = hn::Load(d, rays.linear + lane);
    const std::size_t inPacket = std::min(hn::Lanes(d), std::size_t(rays.count) - lane);
    const M searched = hn::And(hn::FirstN(d, inPacket), hn::Gt(linear, zero));
    float mostSteps = 0;
    for (std::size_t i = 0; i < inPacket; ++i)
      mostSteps = std::max(mostSteps, rays.linear[lane + i]);
    // The samples cover [from, to]; outside the cell's reach the field keeps the side at t0.
    const M reached = hn::Eq(hn::Load(d, rays.reached + lane), one);
    V fPrev = hn::Load(d, rays.fStart + lane), tPrev = r.from,
      facePrev = hn::IfThenElse(reached, hn::Load(d, rays.faceFrom + lane),
                                hn::Load(d, rays.faceStart + lane));
    V steps = one, lo = zero, hi = zero, fLo = zero, fHi = zero;
    M found = hn::FirstN(d, 0);  // none
    const V span = hn::Sub(r.to, r.from);
    for (int i = 1; i <= int(mostSteps); ++i) {
      const M live = hn::AndNot(found, hn::And(searched, hn::Le(hn::Set(d, float(i)), linear)));
      if (hn::AllFalse(d, live)) break;
      const V t = hn::Add(r.from, hn::Div(hn::Mul(span, hn::Set(d, float(i))), linear));
      Projected where;
      const V f = Field(d, maps, type, cells, At(r, t), where);
      steps = hn::Add(steps, hn::IfThenElseZero(live, one));
      // A step across a planar cell's mid-plane is no crossing; nor, in a cell with a hole's
      // rim, one between an empty line and one with surface.
      const M otherHalf = planar ? hn::Ne(where.face, facePrev) : hn::FirstN(d, 0);
      facePrev = hn::IfThenElse(live, where.face, facePrev);
      M crossing = hn::AndNot(otherHalf, hn::Xor(hn::Gt(fPrev, zero), hn::Gt(f, zero)));
      const M emptyLine =
          hn::Or(hn::Ge(hn::Abs(fPrev), emptyField), hn::Ge(hn::Abs(f), emptyField));
      crossing = hn::AndNot(hn::And(cells.openCell, emptyLine), crossing);
      const M hit = hn::And(live, crossing), moved = hn::AndNot(crossing, live);
      lo = hn::IfThenElse(hit, tPrev, lo);
      hi = hn::IfThenElse(hit, t, hi);
      fLo = hn::IfThenElse(hit, fPrev, fLo);
      fHi = hn::IfThenElse(hit, f, fHi);
      found = hn::Or(found, hit);
      fPrev = hn::IfThenElse(moved, f, fPrev);
      tPrev = hn::IfThenElse(moved, t, tPrev);
    }
    // The field where the ray leaves, past the reach, for the next cell (crossesAtFace).
    const M pastReach = hn::AndNot(found, hn::And(searched, hn::Lt(r.to, r.t1)));
    if (!hn::AllFalse(d, pastReach)) {
      Projected unused;
      fPrev = hn::IfThenElse(pastReach, Field(d, maps, type, cells, At(r, r.t1), unused), fPrev);
      steps = hn::Add(steps, hn::IfThenElseZero(pastReach, one));
    }
    hn::Store(fPrev, d, rays.fEnd + lane);
    Projected where{zero, zero, zero, zero};
    V tHit = hi;
    if (!hn::AllFalse(d, found)) {
      const M loPositive = hn::Gt(fLo, zero);
      for (int k = 0; k < binarySteps; ++k) {
        const V mid = hn::Mul(hn::Set(d, 0.5f), hn::Add(lo, hi));
        Projected unused;
        const V fm = Field(d, maps, type, cells, At(r, mid), unused);
        const M toLo = hn::Not(hn::Xor(hn::Gt(fm, zero), loPositive));
        const M moveLo = hn::And(found, toLo), moveHi = hn::AndNot(toLo, found);
        lo = hn::IfThenElse(moveLo, mid, lo);
        fLo = hn::IfThenElse(moveLo, fm, fLo);
        hi = hn::IfThenElse(moveHi, mid, hi);
        fHi = hn::IfThenElse(moveHi, fm, fHi);
        steps = hn::Add(steps, hn::IfThenElseZero(found, one));
      }
      // ReliefTracer::secantCrossing.
      const M distances = hn::And(hn::Lt(hn::Abs(fLo), emptyField), hn::Lt(hn::Abs(fHi), emptyField));
      const V secant = hn::Add(lo, hn::Mul(hn::Sub(hi, lo), hn::Div(fLo, hn::Sub(fLo, fHi))));
      tHit = hn::IfThenElse(distances, secant, hi);
      Field(d, maps, type, cells, At(r, tHit), where);
    }
    hn::Store(hn::IfThenElseZero(found, one), d, rays.found + lane);
    hn::Store(tHit, d, rays.tHit + lane);
    hn::Store(where.face, d, rays.face + lane);
    hn::Store(where.u, d, rays.u + lane);
    hn::Store(where.v, d, rays.v + lane);
    hn::Store(steps, d, rays.steps + lane);
  }
}

const char* InstructionSet() {
  return hwy::TargetName(HWY_TARGET);
}

int VectorLanes() {
  return int(hn::Lanes(D()));
}

}  // namespace HWY_NAMESPACE
}  // namespace cellrelief::trace
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cellrelief::trace {

HWY_EXPORT(EnterCell);
HWY_EXPORT(SearchCell);
HWY_EXPORT(InstructionSet);
HWY_EXPORT(VectorLanes);

void packetEnterCell(const PacketMaps& maps, PacketRays& rays) {
  HWY_DYNAMIC_DISPATCH(EnterCell)(maps, rays);
}

void packetSearchCell(const PacketMaps& maps, int binarySteps, PacketRays& rays) {
  HWY_DYNAMIC_DISPATCH(SearchCell)(maps, binarySteps, rays);
}

const char* packetInstructionSet() {
  return HWY_DYNAMIC_DISPATCH(InstructionSet)();
}

int packetVectorLanes() {
  return HWY_DYNAMIC_DISPATCH(VectorLanes)();
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
