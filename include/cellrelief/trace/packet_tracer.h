// SPDX-License-Identifier: MIT
/// @file packet_tracer.h
/// Ray casting of a relief model in SIMD packets: a stream of rays is walked cell by cell; at
/// every step of the walk the rays standing in grey cells are sorted by (projection type, cell,
/// ray) and searched up to kPacketLanes at a time, one ray per lane, each lane with its own cell
/// (packet_search.h). Coherent primary rays fill a packet from one cell; incoherent secondary
/// rays fill it from several cells of one projection type.
///
/// It answers what ReliefTracer<float, Search> answers with the same options and skipping off
/// (reference()): the paper's linear + binary search in every cell, the side of the surface
/// carried across cell faces, the hit shaded the same way. Each lane's arithmetic is the scalar
/// tracer's, so every hit agrees bit for bit (t, position, face coordinates, cell, face, steps,
/// normal, color; tests/trace).
///
/// Why no skipping: the empty-space walk (empty_space.h) descends and climbs a pyramid with a
/// different path per ray; in lanes it would run as long as the slowest lane. The linear search
/// has one shape for every ray in a cell (a number of samples, then a fixed bisection), which is
/// what lanes run well.
///
/// SIMD through Google Highway rather than std::experimental::simd: Highway compiles the search
/// once per instruction set and picks the best the CPU has at run time (SSSE3, SSE4, AVX2,
/// AVX-512 on x86; NEON on 64-bit Arm; not SVE, see packet_search.cpp), so neither this library
/// nor its users need -march flags, and a test can run every instruction set the machine has;
/// std::experimental::simd follows the compiler's flags only, and has no gather. The price is a
/// compiled target: link cellrelief::trace_packets (opt-in, like cellrelief::indirection_ceres).
/// It compiles its users without fused multiply-adds (-ffp-contract=off, public), so that the
/// scalar reference, compiled in the user's program, rounds as the lanes do.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/trace/packet_search.h"
#include "cellrelief/trace/relief_tracer.h"

namespace cellrelief::trace {

template <SearchPolicy Search = BalancedSearch>
class ReliefPacketTracer {
 public:
  using Hit = ReliefHit<float>;

  /// The tracer reads the model in place: it must outlive the tracer (a temporary is refused).
  ReliefPacketTracer(relief::ReliefModel&&, const TraceOptions& = {}, bool = true) = delete;
  /// The options' skipping flags are ignored (see above). `gathers`: read 16-bit codes with the
  /// CPU's gather instructions (off: scalar loads, the same values; gathers are slow on some
  /// CPUs, e.g. AMD's before Zen 4).
  explicit ReliefPacketTracer(const relief::ReliefModel& model, const TraceOptions& options = {},
                              bool gathers = true)
      : mReference(model, withoutSkipping(options)), mOpenModel(model.openSurface()) {
    // Lanes carry layer indices as floats, exact below 2^24.
    if (model.layerCount() >= (1 << 24))
      throw Error(ErrorKind::InvalidArgument, "ReliefPacketTracer: the model has " +
                                                  std::to_string(model.layerCount()) +
                                                  " layers; the packet search reads at most 2^24");
    // The gathers of 16-bit codes take 32-bit byte offsets, and read two codes of a little-endian
    // word.
    const std::size_t bytes =
        std::size_t(model.layerCount()) * std::size_t(model.texels) * std::size_t(model.texels) * 2;
    mGather16 = gathers && model.distanceCodec.bits == 16 && bytes > 0 &&
                bytes < (std::size_t(1) << 31) && std::endian::native == std::endian::little;
    mCells.reserve(model.cells.size());
    for (const relief::CellRecord& r : model.cells) mCells.push_back(laneCell(r));
  }

  /// The scalar tracer this one agrees with, ray by ray.
  const ReliefTracer<float, Search>& reference() const { return mReference; }
  const relief::ReliefModel& model() const { return mReference.model(); }
  /// The instruction set the searches run on (Highway's name: "AVX3" is AVX-512, "AVX2", "SSE4").
  static const char* instructionSet() { return packetInstructionSet(); }

  static TraceOptions withoutSkipping(TraceOptions options) {
    options.skipEmptySpace = false;
    options.skipCentralCells = false;
    return options;
  }

  /// hits[i] = reference().intersect(rays[i]) (or the search without shading when `shade` is
  /// false, as occluded() runs it), for every i. On the calling thread; callers trace blocks of
  /// a few thousand rays in parallel (a block is what one sort gathers into packets).
  void intersect(std::span<const Rayf> rays, std::span<Hit> hits, bool shade = true) const {
    if (rays.size() >
        std::numeric_limits<std::uint32_t>::max())  // the sort key holds 32 bits of ray
      throw Error(ErrorKind::InvalidArgument,
                  "ReliefPacketTracer::intersect: " + std::to_string(rays.size()) +
                      " rays in one call; at most 2^32 - 1");
    if (hits.size() != rays.size())
      throw Error(ErrorKind::InvalidArgument,
                  "ReliefPacketTracer::intersect: " + std::to_string(rays.size()) +
                      " rays but room for " + std::to_string(hits.size()) + " hits");
    model().visitDistanceCodes([&](const auto& codes) { traceStream(codes, rays, hits, shade); });
  }

  /// The most rays per intersect() call whose working memory the calling thread keeps for the
  /// next call (see Scratch); larger calls allocate their own.
  static constexpr std::size_t kKeptRays = std::size_t(1) << 16;

 private:
  /// One ray of the stream: ReliefTracer::traceWith's locals, kept between the rounds.
  struct RayState {
    Rayf ray;
    std::optional<GridDda<float>> walk;
    int side = 0;  ///< -1 outside, 1 inside, 0 unknown (ReliefTracer::Side)
    float exitField = std::numeric_limits<float>::infinity();
    std::uint32_t steps = 0;
    std::int32_t cell = -1;  ///< the grey cell the ray stands in
  };

  using Accessor = openvdb::Int32Grid::ConstUnsafeAccessor;

  /// A call's working memory: the rays' states and the sort keys of the rays standing in grey
  /// cells. Kept by the thread between calls (start() sets every field a ray's trace reads):
  /// allocated and value-initialized afresh on every call (half a megabyte per block of 4,096
  /// rays) it cost a tenth of the time at N = 1 (Igea, T = 257, 2-32 steps, one thread, best of
  /// three: 5.17 -> 5.73 Mrays/s). Calls of more than kKeptRays rays use memory of their own,
  /// freed on return, so a thread keeps at most about 8 MB.
  struct Scratch {
    std::vector<RayState> states;
    std::vector<std::uint64_t> pending, next;
  };
  /// Sized for `rays`, with no sort keys.
  static void prepare(Scratch& s, std::size_t rays) {
    if (s.states.size() < rays) s.states.resize(rays);
    s.pending.clear();
    s.next.clear();
    s.pending.reserve(rays);
    s.next.reserve(rays);
  }

  /// Walks on to the next grey cell, from the walk's current cell (white and black cells hold no
  /// surface: they keep the side, and no field was read at their faces). False: none is left.
  static bool toGreyCell(RayState& s, Accessor& acc) {
    for (;;) {
      const Vec3i& c = s.walk->cell();
      s.cell = acc.getValue(openvdb::Coord(c.x, c.y, c.z));
      if (s.cell >= 0) return true;
      s.exitField = std::numeric_limits<float>::infinity();
      if (!s.walk->next()) return false;
    }
  }

  /// The ray set up as traceWith sets it up; false when it meets no grey cell (hit stays a miss).
  bool start(const Rayf& input, RayState& s, Accessor& acc) const {
    s.ray = input;
    s.exitField = std::numeric_limits<float>::infinity();
    s.steps = 0;
    const std::optional<RayInterval<float>> span = mReference.prepareRay(s.ray);
    if (!span) return false;
    const relief::ReliefModel& m = model();
    s.walk.emplace(s.ray, Vec3f(m.originWS), float(m.cellSizeWS), m.gridSize, span->t0, span->t1);
    s.side = span->t0 > s.ray.tmin ? -1 : 0;
    return toGreyCell(s, acc);
  }

  /// A cell's values in a lane (PacketRays), computed once per tracer.
  struct LaneCell {
    int type = 0;       ///< projection::ProjectionType
    Vec3f originWS{0};  ///< its minimum corner, as ReliefTracer::cellFrame computes it
    float axis = 0, cellFace = 0, centreFace = 0;
    float point[3] = {0, 0, 0};
    float layerOfFace[6] = {-1, -1, -1, -1, -1, -1};
    float interior = 0, centreInside = 0, openCell = 0;
  };

  LaneCell laneCell(const relief::CellRecord& r) const {
    const relief::ReliefModel& m = model();
    LaneCell c;
    c.type = r.projectionType;
    const float cellSize = float(m.cellSizeWS);
    c.originWS = Vec3f(m.originWS) + Vec3f(r.ijk()) * cellSize;
    const bool parallel = r.projectionType == std::uint8_t(projection::ProjectionType::Parallel);
    c.axis = float(parallel ? r.faceOrAxis / 2 : r.faceOrAxis);
    c.cellFace = float(r.faceOrAxis);
    c.centreFace = float(projection::firstFace(cells::domainFacesOf(r.configuration)));
    for (int a = 0; a < 3; ++a) c.point[a] = r.point[a];
    for (int f = 0; f < cells::kFaceCount; ++f) c.layerOfFace[f] = float(r.layerOf(f));
    c.interior = r.configuration == 0 ? 1.0f : 0.0f;
    c.centreInside = r.centreInside() ? 1.0f : 0.0f;
    c.openCell = r.openSurface() ? 1.0f : 0.0f;
    return c;
  }

  template <class Codes>
  PacketMaps packetMaps(const Codes& codes) const {
    const relief::ReliefModel& m = model();
    PacketMaps maps;
    maps.codes = codes.data;
    maps.codeBits = int(sizeof(*codes.data) * 8);
    maps.gather16 = mGather16 && maps.codeBits == 16;
    maps.texels = m.texels;
    maps.distanceScale = float(m.distanceCodec.scale());
    maps.emptyCode = float(m.distanceCodec.emptyCode());
    maps.zeroCode = float(m.distanceCodec.zeroCode);
    return maps;
  }

  /// Sort key of a ray standing in a grey cell: projection type, cell, ray. A packet is a run of
  /// one type: rays of one cell where they are many (coherent rays), of several where not.
  static std::uint64_t sortKey(int type, std::int32_t cell, std::uint32_t ray) {
    return (std::uint64_t(type) << 62) | (std::uint64_t(cell) << 32) | ray;
  }
  static std::uint32_t rayOf(std::uint64_t key) { return std::uint32_t(key); }
  /// 30 bits of cell: CellRecord packs i, j, k in 10 bits each, so a model has at most 2^30 cells.
  static std::int32_t cellOf(std::uint64_t key) { return std::int32_t((key >> 32) & 0x3fffffffu); }

  template <class Codes>
  void traceStream(const Codes& codes, std::span<const Rayf> rays, std::span<Hit> hits,
                   bool shade) const {
    auto acc = mReference.cellGrid().getConstUnsafeAccessor();
    const PacketMaps maps = packetMaps(codes);
    const std::size_t vector = std::size_t(packetVectorLanes());
    thread_local Scratch kept;
    std::optional<Scratch> own;
    Scratch& scratch = rays.size() <= kKeptRays ? kept : own.emplace();
    prepare(scratch, rays.size());
    const std::span<RayState> states(scratch.states.data(), rays.size());
    std::vector<std::uint64_t>& pending = scratch.pending;
    std::vector<std::uint64_t>& next = scratch.next;
    auto stand = [&](std::vector<std::uint64_t>& into, std::uint32_t i) {
      into.push_back(sortKey(mCells[states[i].cell].type, states[i].cell, i));
    };
    for (std::size_t i = 0; i < rays.size(); ++i) {
      hits[i] = Hit{};
      if (start(rays[i], states[i], acc)) stand(pending, std::uint32_t(i));
    }
    while (!pending.empty()) {
      std::sort(pending.begin(), pending.end());
      for (std::size_t b = 0; b < pending.size();) {
        const int type = mCells[cellOf(pending[b])].type;
        std::size_t e = b + 1;
        while (e < pending.size() && e - b < std::size_t(kPacketLanes) &&
               mCells[cellOf(pending[e])].type == type)
          ++e;
        searchPacket(maps, type, std::span(pending).subspan(b, e - b), vector, states, hits, shade,
                     acc, [&](std::uint32_t i) { stand(next, i); });
        b = e;
      }
      std::swap(pending, next);
      next.clear();
    }
  }

  /// Searches rays standing in grey cells of one projection type (ReliefTracer::searchCell, lane
  /// by lane); rays without a hit walk on to their next grey cell and are handed to `walkOn`.
  template <class WalkOn>
  void searchPacket(const PacketMaps& maps, int type, std::span<const std::uint64_t> lanes,
                    std::size_t vector, std::span<RayState> states, std::span<Hit> hits,
                    bool shade, Accessor& acc, WalkOn&& walkOn) const {
    const relief::ReliefModel& m = model();
    const float cellSize = float(m.cellSizeWS);
    PacketRays packet;
    packet.count = int(lanes.size());
    packet.projectionType = type;
    // Lanes past the count, up to a whole vector, repeat the first ray: computed and dropped.
    const std::size_t filled =
        std::min(std::size_t(kPacketLanes), (lanes.size() + vector - 1) / vector * vector);
    for (std::size_t l = 0; l < filled; ++l) {
      const std::uint64_t key = lanes[l < lanes.size() ? l : 0];
      const RayState& s = states[rayOf(key)];
      const LaneCell& c = mCells[cellOf(key)];
      packet.axis[l] = c.axis;
      packet.cellFace[l] = c.cellFace;
      packet.centreFace[l] = c.centreFace;
      packet.px[l] = c.point[0], packet.py[l] = c.point[1], packet.pz[l] = c.point[2];
      for (int f = 0; f < cells::kFaceCount; ++f) packet.layerOfFace[f][l] = c.layerOfFace[f];
      packet.interior[l] = c.interior;
      packet.centreInside[l] = c.centreInside;
      packet.openCell[l] = c.openCell;
      // ReliefTracer::cellFrame.
      const Vec3f o = (s.ray.origin - c.originWS) / cellSize, d = s.ray.direction / cellSize;
      packet.ox[l] = o.x, packet.oy[l] = o.y, packet.oz[l] = o.z;
      packet.dx[l] = d.x, packet.dy[l] = d.y, packet.dz[l] = d.z;
      const float t0 = s.walk->tEntry(), t1 = s.walk->tExit();
      float from = t0, to = t1;
      const bool reached = mReference.clipToReach(cellOf(key), o, d, from, to);
      packet.t0[l] = t0, packet.t1[l] = t1;
      packet.from[l] = reached ? from : t0, packet.to[l] = reached ? to : t1;
      packet.reached[l] = reached ? 1 : 0;
      packet.linear[l] = 0;
    }
    packetEnterCell(maps, packet);
    // A crossing at the face where the ray enters (searchCell).
    for (std::size_t l = 0; l < lanes.size(); ++l) {
      RayState& s = states[rayOf(lanes[l])];
      if (!mOpenModel && s.side != 0 &&
          mReference.crossesAtFace(packet.fStart[l], s.side > 0, s.exitField)) {
        hits[rayOf(lanes[l])] = finish(cellOf(lanes[l]), s, packet.t0[l], packet.faceStart[l],
                                       packet.uStart[l], packet.vStart[l], 1, shade);
        s.walk.reset();
        continue;
      }
      // The fewest steps where the segment cannot meet a change of side (linearBinarySearch).
      packet.linear[l] = float(packet.reached[l] > 0
                                   ? Search::linearSteps(mReference.options(),
                                                         double(packet.footprint[l] * float(m.texels - 1)))
                                   : constants::kLinearStepsOutsideReach);
    }
    packetSearchCell(maps, mReference.options().binarySteps, packet);
    for (std::size_t l = 0; l < lanes.size(); ++l) {
      const std::uint32_t ray = rayOf(lanes[l]);
      RayState& s = states[ray];
      if (!s.walk) continue;  // hit at the face
      const std::uint32_t steps = std::uint32_t(packet.steps[l]);
      if (packet.found[l] > 0) {
        hits[ray] = finish(cellOf(lanes[l]), s, packet.tHit[l], packet.face[l], packet.u[l],
                           packet.v[l], steps, shade);
        continue;
      }
      s.steps += steps;
      s.side = mOpenModel ? 0 : packet.fEnd[l] > 0 ? 1 : -1;
      s.exitField = std::abs(packet.fEnd[l]);
      if (s.walk->next() && toGreyCell(s, acc))
        walkOn(ray);
      else
        hits[ray].steps = s.steps;  // a miss reports its steps
    }
  }

  Hit finish(std::int32_t index, const RayState& s, float t, float face, float u, float v,
             std::uint32_t steps, bool shade) const {
    projection::FacePoint<float> fp;
    fp.face = int(face);
    fp.uv = Vec2f(u, v);
    return mReference.finishHit(index, s.ray, t, fp, s.steps + steps, shade);
  }

  ReliefTracer<float, Search> mReference;
  bool mOpenModel = false;       ///< ReliefModel::openSurface(): no side carried across cell faces
  bool mGather16 = false;        ///< PacketMaps::gather16
  std::vector<LaneCell> mCells;  ///< per cell of the model
};

}  // namespace cellrelief::trace
