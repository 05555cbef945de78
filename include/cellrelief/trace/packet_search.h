// SPDX-License-Identifier: MIT
/// @file packet_search.h
/// The SIMD part of the packet tracer (packet_tracer.h): the linear + binary search of up to
/// kPacketLanes rays inside grey cells of one projection type, one ray per lane. Each lane does the
/// arithmetic of ReliefTracer's scalar search (field(), linearBinarySearch(), refineCrossing())
/// operation for operation, in the same order and without fused multiply-adds, so that a lane and
/// the scalar tracer agree bit for bit; branches become masks.
///
/// Plain structures in, plain structures out: the search is compiled once per instruction set
/// (SSE4, AVX2, AVX-512, ... through Google Highway's dynamic dispatch,
/// src/trace/packet_search.cpp) and the best one the CPU has is chosen at run time, so the
/// header-only templates around it (the stream of rays, the cell walk, the shading) need no target
/// flags.
#pragma once

#include <cstdint>

namespace cellrelief::trace {

/// The most rays one call searches: 16 floats fill an AVX-512 register; narrower instruction
/// sets take them in 2 or 4 vectors.
inline constexpr int kPacketLanes = 16;

/// The maps every lane reads (one model's).
struct PacketMaps {
  const void* codes = nullptr;  ///< the model's level-0 distance codes, layer by layer, row by row
  int codeBits = 16;            ///< 8 (std::uint8_t codes) or 16 (std::uint16_t)
  /// 16-bit codes whose byte offsets fit in 32 bits, with a layer at least: read by gathers.
  bool gather16 = false;
  int texels = 0;
  float distanceScale = 0;  ///< cell units per code step
  float emptyCode = 0;      ///< the code of a line without surface
  float zeroCode = 0;       ///< the code of distance 0 (DistanceCodec::zeroCode)
};

/// Up to kPacketLanes rays, each in a grey cell of its own or shared, all of one projection
/// type: each lane's cell as the field reads it, and its ray in the cell's unit coordinates
/// (p(t) = o + t d); then what each call fills in. Booleans are 0 or 1.
struct PacketRays {
  int count = 0;
  int projectionType = 0;                    ///< projection::ProjectionType, of every lane's cell
  alignas(64) float axis[kPacketLanes];      ///< parallel: the face's axis; planar, axial: the axis
  alignas(64) float cellFace[kPacketLanes];  ///< parallel: the face
  alignas(64) float px[kPacketLanes], py[kPacketLanes],
      pz[kPacketLanes];  ///< centre, or a point of the axis
  /// Where a point at the centre (or on the axis) projects: the first domain face.
  alignas(64) float centreFace[kPacketLanes];
  alignas(64) float layerOfFace[6][kPacketLanes];  ///< -1: no layer
  alignas(64) float interior[kPacketLanes];  ///< configuration 0: empty lines on the centre's side
  alignas(64) float centreInside[kPacketLanes];  ///< CellRecord::centreInside()
  alignas(64) float openCell[kPacketLanes];  ///< CellRecord::openSurface(): no crossing at an empty
                                             ///< line
  alignas(64) float ox[kPacketLanes], oy[kPacketLanes], oz[kPacketLanes];
  alignas(64) float dx[kPacketLanes], dy[kPacketLanes], dz[kPacketLanes];
  alignas(64) float t0[kPacketLanes], t1[kPacketLanes];  ///< the segment inside the cell
  /// The part of it within the cell's reach (ReliefTracer::clipToReach), which the linear samples
  /// cover, and whether there is one (1); without one, [t0, t1].
  alignas(64) float from[kPacketLanes], to[kPacketLanes], reached[kPacketLanes];
  // packetEnterCell: the field where the ray enters, where that point projects, and the
  // footprint of [from, to] on the maps in face units, from the face `from` projects onto
  // (ReliefTracer::linearBinarySearch).
  alignas(64) float fStart[kPacketLanes], faceStart[kPacketLanes];
  alignas(64) float uStart[kPacketLanes], vStart[kPacketLanes], footprint[kPacketLanes];
  alignas(64) float faceFrom[kPacketLanes];
  // packetSearchCell, in: linear samples per lane (0: the lane is not searched).
  alignas(64) float linear[kPacketLanes];
  // packetSearchCell, out: a crossing found (1) or not (0); the hit's t, face and face
  // coordinates; field evaluations in the cell; the field at t1 when nothing is hit.
  alignas(64) float found[kPacketLanes], tHit[kPacketLanes], face[kPacketLanes];
  alignas(64) float u[kPacketLanes], v[kPacketLanes], steps[kPacketLanes], fEnd[kPacketLanes];
};

/// Fills fStart, faceStart, uStart, vStart, footprint and faceFrom for the first `count` lanes
/// (lanes past it read no maps; their outputs are unspecified).
void packetEnterCell(const PacketMaps& maps, PacketRays& rays);

/// The linear search (rays.linear samples per lane) and the binary refinement (binarySteps) of
/// every lane with linear > 0; fills found, tHit, face, u, v, steps and fEnd.
void packetSearchCell(const PacketMaps& maps, int binarySteps, PacketRays& rays);

/// The lanes of one vector of the instruction set chosen (4 to 16; 1 without SIMD).
int packetVectorLanes();

/// The instruction set the two calls above run on this CPU (Highway's name, e.g. "AVX3").
const char* packetInstructionSet();

/// Restricts the instruction sets to those in `mask` (Highway target bits; 0 restores them
/// all): for tests that run the search on each one the CPU has. Returns the names of the
/// instruction sets compiled in and supported here, best first, with their bits.
struct PacketTarget {
  std::int64_t bits = 0;
  const char* name = "";
};
int packetTargets(PacketTarget* out, int capacity);
void packetRestrictTargets(std::int64_t bits);

}  // namespace cellrelief::trace
