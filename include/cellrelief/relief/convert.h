// SPDX-License-Identifier: MIT
/// @file convert.h
/// Mesh to relief model (Apaza & Andujar, 3.3.2): for every domain face of every grey cell, the
/// distance from each sample point P' of the face to the nearest surface point that projects onto
/// it. Each sample casts its projection line (from P' towards the centre, the axis, or along the
/// inward normal) against the mesh's BVH and keeps the nearest hit, so distances are exact per
/// sample, never interpolated across triangles, and axial projections need no curve subdivision.
/// Normals (interpolated vertex normals) and colors (vertex colors, or a texture through the
/// mesh's UVs) are sampled at the same hits when the mesh has them. Parallel over cells with TBB.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "cellrelief/cells/cell_complex.h"
#include "cellrelief/core/bvh.h"
#include "cellrelief/core/mesh_topology.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/metrics/geometric_error.h"
#include "cellrelief/relief/centre_search.h"
#include "cellrelief/relief/flat_mesh.h"
#include "cellrelief/relief/grid_size.h"
#include "cellrelief/relief/reconstruct.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::relief {

struct ConvertOptions {
  int gridSize = 0;   ///< N; 0 chooses it from the occlusion ratio (grid_size.h)
  /// T: samples per face side (2^k + 1 keeps every mip level on the edges); 0 picks
  /// T = max(512 / N, 8) + 1, the same sample spacing for every N up to 64 (defaultTexels).
  int texels = 0;
  int distanceBits = 16;
  /// Moves each sample to centre the bilinear reading's error on the surface
  /// (centreInterpolationError); false keeps every sample exact on its projection line.
  bool centreSamples = true;
  /// Normal maps only when the mesh has normals (a mesh that lacks them shades from the distance
  /// gradient); set forceNormals to store normals computed from the geometry anyway.
  NormalFormat normals = NormalFormat::Octahedral16;
  bool forceNormals = false;
  bool colors = true;                         ///< when the mesh has colors or a texture is given
  const Image<std::uint8_t>* texture = nullptr;  ///< sampled through the mesh's UVs
  /// FewestCrossings moves a cell's point only where some projection line crosses the surface
  /// twice (cost: one more ray per filled sample, and the search in those cells).
  projection::CentreOfProjection centre = projection::CentreOfProjection::FewestCrossings;
  GridSizeOptions gridSearch = {.threshold = 0.01, .maxGridSize = 64};
  std::size_t memoryLimitBytes = std::size_t(4) << 30;
  /// Called with the fraction done (0..1), about 100 times, from worker threads but never two at
  /// once, with values that never decrease.
  std::function<void(double)> progress = {};
};

struct ConvertReport {
  double gridSeconds = 0, sampleSeconds = 0, totalSeconds = 0;
  std::size_t greyCells = 0, layers = 0, droppedLayers = 0;
  std::size_t filledSamples = 0, emptySamples = 0;
  /// Filled samples whose projection line meets the surface again past the stored hit: the side
  /// past that second crossing is misread (0 is a model that reads every line right).
  std::size_t linesCrossedTwice = 0;
  std::size_t movedCentres = 0;  ///< cells whose point FewestCrossings moved
  double quantizationErrorWS = 0;
  std::vector<GridSizeTrial> gridTrials;
  /// > 0 when the mesh was flat and was modelled as a slab this thick (flat_mesh.h).
  double slabThicknessWS = 0;
};

namespace detail {

/// The signals a conversion samples: only those the mesh has (and the options allow).
struct Signals {
  bool normals = false, colors = false, textured = false;
  std::vector<Vec3f> vertexNormals;  ///< the mesh's, or computed when normals are forced
};

inline Signals signalsOf(const TriangleMesh& mesh, const ConvertOptions& options) {
  Signals s;
  s.normals = options.normals != NormalFormat::None && (mesh.hasNormals() || options.forceNormals);
  s.textured = options.colors && options.texture && mesh.hasUVs();
  s.colors = options.colors && (mesh.hasColors() || s.textured);
  if (s.normals) s.vertexNormals = mesh.hasNormals() ? mesh.normals : computeVertexNormals(mesh);
  return s;
}

/// One grey cell while sampling: its projection and, per domain face (in face order), T x T
/// samples of distance (NaN = empty), normal and color.
struct CellSamples {
  projection::CellProjection<double> proj;
  std::vector<float> distance;
  std::vector<Vec3f> normal;
  std::vector<Color8> color;
  std::uint8_t present = 0;   ///< domain faces with at least one sample
  bool centreInside = false;  ///< interior cells only
  bool centreMoved = false;   ///< FewestCrossings moved the point off the canonical one
  int linesCrossedTwice = 0;  ///< samples whose line meets the surface again past its hit
};

/// Refuses bad options and conversions over the memory limit; returns T.
inline int checkConversion(const cells::CellComplex& complex, const ConvertOptions& options) {
  if (options.texels != 0 && (options.texels < 2 || options.texels > 1025))
    throw Error(ErrorKind::InvalidArgument,
                "texels T = " + std::to_string(options.texels) + " is out of range (2 to 1025)");
  if (!DistanceCodec::supports(options.distanceBits))
    throw Error(ErrorKind::InvalidArgument, "distance bits must be 8 or 16");
  const int n = complex.gridSize();
  const int T = options.texels != 0 ? options.texels : defaultTexels(n);
  std::size_t maxLayers = 0;
  for (const cells::GreyCell& g : complex.greyCells()) maxLayers += std::popcount(unsigned(g.domainFaces()));
  // Per sample while sampling: a float distance, a Vec3f normal, a Color8; then the quantized
  // maps (2 + 4 + 4 bytes at most) exist at the same time.
  const std::size_t sampleBytes = maxLayers * std::size_t(T) * T * (4 + 12 + 4 + 2 + 4 + 4);
  if (sampleBytes > options.memoryLimitBytes)
    throw Error(ErrorKind::ResourceLimit,
                "N = " + std::to_string(n) + ", T = " + std::to_string(T) + " needs about " +
                    std::to_string(sampleBytes >> 20) + " MiB of maps before quantization, over the limit");
  return T;
}

/// The normal and color of the surface at a hit, interpolated from the hit triangle's corners.
inline void sampleSignals(const TriangleMesh& mesh, const Signals& signals, const ConvertOptions& options,
                          const Hitd& hit, Vec3f* normal, Color8* color) {
  const Vec3u& tri = mesh.triangles[hit.primId];
  const double w0 = 1.0 - hit.u - hit.v;
  if (signals.normals) {
    const Vec3f nrm = float(w0) * signals.vertexNormals[tri[0]] + float(hit.u) * signals.vertexNormals[tri[1]] +
                      float(hit.v) * signals.vertexNormals[tri[2]];
    const float len = glm::length(nrm);
    *normal = len > 0 ? nrm / len : Vec3f(glm::normalize(hit.geometricNormal));
  }
  if (!signals.colors) return;
  if (signals.textured) {
    const std::size_t c = 3 * std::size_t(hit.primId);
    const Vec2f uv = float(w0) * mesh.uvs[c] + float(hit.u) * mesh.uvs[c + 1] + float(hit.v) * mesh.uvs[c + 2];
    // OBJ's v runs upwards; image rows run downwards.
    const Vec4f t = options.texture->sample(Vec2f(uv.x, 1.0f - uv.y), {Filter::Bilinear, Wrap::Repeat});
    *color = Color8(glm::round(glm::clamp(t, 0.0f, 1.0f) * 255.0f));
  } else {
    const Vec4f c = float(w0) * Vec4f(mesh.colors[tri[0]]) + float(hit.u) * Vec4f(mesh.colors[tri[1]]) +
                    float(hit.v) * Vec4f(mesh.colors[tri[2]]);
    *color = Color8(glm::round(c));
  }
}

/// How far planar and parallel projection lines look past their end, in sample spacings of
/// depth. A line that just misses the surface before its end would be empty, and the bilinear
/// texel between it and a filled neighbour would read no surface: a gap up to a texel wide where
/// the surface leaves the line's reach. With the hit past the end stored, that texel interpolates
/// a distance that reaches the end where the surface does. The field of such a line is negative
/// (before the surface) over its whole length, as an empty line's is outside, so the side each
/// line reads is unchanged.
/// - Planar lines end at the mid-plane: a sheet that crosses it splits between the two faces
///   (pinholes in a line across laurana's chest at N = 32, against Embree).
/// - Parallel lines end at the opposite face: a surface that leaves the cell through it, into a
///   grey neighbour whose own projection does not see that piece, left pinholes along the face
///   (the bunny's flanks and base at N = 32: 151 -> 59 disagreements per million rays).
/// Central and axial lines end at a point or an axis, and their continuation leads into the
/// opposite face's region, not the neighbouring one: they stop at their end.
inline constexpr double kPastLineEndSamples = 2.0;

/// How far past its end (t = 1) a projection line is searched: kPastLineEndSamples in units of
/// the line's length (a planar line is half a cell long, a parallel one a whole cell).
inline double pastLineEnd(projection::ProjectionType type, int T) {
  switch (type) {
    case projection::ProjectionType::Planar: return 2 * kPastLineEndSamples / (T - 1);
    case projection::ProjectionType::Parallel: return kPastLineEndSamples / (T - 1);
    default: return 0.0;
  }
}

/// Where the distance curves along a face, the bilinear reading between samples lies on one side
/// of the surface only: up to f'' s^2 / 8 at a texel's middle (f'' the second derivative of the
/// distance along the face, s the sample spacing), exact at the samples. Moving every sample by
/// minus a sixteenth of its second differences (kInterpolationCentring) centres that error on
/// the surface, half as large at worst. Without it a convex part read inside the mesh along its
/// whole silhouette (rays that graze it missed) and a concave one outside.
inline constexpr double kInterpolationCentring = 1.0 / 16;
/// A second difference larger than this many sample spacings is a crease or a depth jump (an
/// occlusion boundary), where the reading is not a parabola's: such an axis is left as sampled.
inline constexpr double kMaxCentredCurvature = 1.0;

/// Centres the interpolation error of one face's T x T distances (cell units, NaN = empty):
/// each sample moves by -kInterpolationCentring times its second differences along the face's
/// two axes, each axis only where both neighbours are filled and the difference is a curvature
/// (kMaxCentredCurvature). A sample on a face's edge has a neighbour along the edge only, so it
/// moves by the same amount in every face and cell that samples that line.
inline void centreInterpolationError(float* distance, int T) {
  const std::vector<float> sampled(distance, distance + std::size_t(T) * T);
  const double limit = kMaxCentredCurvature / (T - 1);
  auto secondDifference = [&](int a, int b, int da, int db) -> double {
    const int a0 = a - da, b0 = b - db, a1 = a + da, b1 = b + db;
    if (a0 < 0 || b0 < 0 || a1 >= T || b1 >= T) return 0;
    const float before = sampled[std::size_t(b0) * T + a0], after = sampled[std::size_t(b1) * T + a1];
    if (std::isnan(before) || std::isnan(after)) return 0;
    const double d2 = double(before) - 2.0 * sampled[std::size_t(b) * T + a] + double(after);
    return std::abs(d2) <= limit ? d2 : 0.0;
  };
  for (int b = 0; b < T; ++b)
    for (int a = 0; a < T; ++a) {
      const std::size_t k = std::size_t(b) * T + a;
      if (std::isnan(sampled[k])) continue;
      const double curvature = secondDifference(a, b, 1, 0) + secondDifference(a, b, 0, 1);
      distance[k] = float(std::max(0.0, sampled[k] - kInterpolationCentring * curvature));
    }
}

/// Faces of at least this many samples a side are sampled in parallel rows (sampleFaces).
inline constexpr int kParallelRowsFrom = 129;

/// Casts the projection line of each sample of each domain face of `out.proj` against the mesh
/// and keeps the nearest hit (for planar and parallel projections, one past the line's end as
/// well: kPastLineEndSamples); counts the lines that meet the surface again past it.
inline void sampleFaces(const TriangleMesh& mesh, const TrianglesInBox<double>& surface, const ConvertOptions& options,
                        const Signals& signals, const Vec3d& cellMin, double h, int T, CellSamples& out) {
  const int faces = std::popcount(unsigned(out.proj.domainFaces()));
  out.distance.assign(std::size_t(faces) * T * T, std::numeric_limits<float>::quiet_NaN());
  out.normal.assign(signals.normals ? out.distance.size() : 0, Vec3f(0));
  out.color.assign(signals.colors ? out.distance.size() : 0, Color8(0));
  out.present = 0;
  out.linesCrossedTwice = 0;
  const double pastEnd = pastLineEnd(out.proj.type, T);
  int slot = 0;
  for (int f = 0; f < cells::kFaceCount; ++f) {
    if (!(out.proj.domainFaces() & (1u << f))) continue;
    const std::size_t first = std::size_t(slot) * T * T;
    // Rows in parallel, each writing its own samples and counts: a model of one cell (N = 1) is
    // otherwise one task of the conversion's loop over cells. Small faces stay one task (split,
    // they made N = 16 conversions 5% to 20% slower).
    std::vector<int> withinLine(T, 0), crossedTwice(T, 0);
    const std::size_t rowsPerTask = T >= kParallelRowsFrom ? 8 : std::size_t(T);
    parallelFor(0, std::size_t(T), [&](std::size_t row) {
      const int b = int(row);
      for (int a = 0; a < T; ++a) {
        const Vec3d onFace = projection::facePoint(f, Vec2d(double(a) / (T - 1), double(b) / (T - 1)));
        const Rayd line = projectionLine(out.proj, f, onFace, cellMin, h);
        const FirstAndNextHit<double> crossings = firstHitAndCrossingAgain(surface, line, 1 + pastEnd);
        const Hitd& hit = crossings.first;
        if (!hit.valid()) continue;
        const std::size_t k = first + std::size_t(b) * T + a;
        out.distance[k] = float(hit.t * glm::length(out.proj.lineEnd(f, onFace) - onFace));
        if (hit.t <= 1) {
          withinLine[b] = 1;
          crossedTwice[b] += crossings.next;
        }
        sampleSignals(mesh, signals, options, hit, signals.normals ? &out.normal[k] : nullptr,
                      signals.colors ? &out.color[k] : nullptr);
      }
    }, rowsPerTask);
    const bool anyWithinLine = std::find(withinLine.begin(), withinLine.end(), 1) != withinLine.end();
    for (const int n : crossedTwice) out.linesCrossedTwice += n;
    if (anyWithinLine) {
      if (options.centreSamples) centreInterpolationError(out.distance.data() + first, T);
      out.present |= std::uint8_t(1u << f);
    } else {
      // Only hits past the line's end: the face reads no surface of its own (as if empty).
      std::fill_n(out.distance.begin() + std::ptrdiff_t(first), std::size_t(T) * T,
                  std::numeric_limits<float>::quiet_NaN());
    }
    ++slot;
  }
}

/// How far before its face an interior cell's empty line is continued, in sample spacings
/// (cell units: kBeforeFaceSamples / (T - 1)).
///
/// Why: an empty line of an interior cell (case 0) lies wholly on the centre's side, so the
/// surface crossed the line's continuation before the face, outside the cell. Stored as empty,
/// a texel between it and a filled line could only guess where the surface crosses the face
/// (ReliefTracer::mixedTexel, kept for models without these distances), and a guess off by part
/// of a texel grew or cut the relief along the rim where the surface leaves the cell: the most
/// of the "only ours" silhouette disagreements with Embree on the armadillo. Stored as the
/// negative distance to that crossing (the line cast backwards, outwards from the face), the
/// bilinear reading crosses zero where the surface crosses the face. Two spacings: with exact
/// distances from 0.5 to 2 spacings bench_silhouettes measured armadillo 107, 88, 93, 92
/// disagreements per million rays and fertility 72, 69, 65, 61 (the guess: 120 and 82); a line
/// whose continuation meets nothing that near reads -kBeforeFaceSamples spacings.
inline constexpr double kBeforeFaceSamples = 2.0;

inline double beforeFace(int T) { return kBeforeFaceSamples / (T - 1); }

/// Gives every empty sample of an interior cell's present faces the negative distance at which
/// the line's continuation outwards meets the surface, or -beforeFace(T) when it meets none that
/// near (kBeforeFaceSamples). Only samples next to a filled one (of the 8 around it) are cast:
/// a texel without a filled corner reads the centre's side all over whatever its corners hold,
/// so the others take the limit. Signals are sampled at the hits, as for the lines' own hits.
/// `near`: the triangles that meet the cell's box grown by beforeFace(T) cells.
inline void sampleBeforeFaces(const TriangleMesh& mesh, const TrianglesInBox<double>& near, const ConvertOptions& options,
                              const Signals& signals, const Vec3d& cellMin, double h, int T, CellSamples& out) {
  const double reach = beforeFace(T);
  std::vector<char> nextToFilled(std::size_t(T) * T);
  int slot = 0;
  for (int f = 0; f < cells::kFaceCount; ++f) {
    if (!(out.proj.domainFaces() & (1u << f))) continue;
    const std::size_t first = std::size_t(slot++) * T * T;
    if (!(out.present & (1u << f))) continue;
    std::fill(nextToFilled.begin(), nextToFilled.end(), 0);
    for (int b = 0; b < T; ++b)
      for (int a = 0; a < T; ++a) {
        if (std::isnan(out.distance[first + std::size_t(b) * T + a])) continue;
        for (int y = std::max(0, b - 1); y <= std::min(T - 1, b + 1); ++y)
          for (int x = std::max(0, a - 1); x <= std::min(T - 1, a + 1); ++x) nextToFilled[std::size_t(y) * T + x] = 1;
      }
    for (int b = 0; b < T; ++b)
      for (int a = 0; a < T; ++a) {
        const std::size_t k = first + std::size_t(b) * T + a;
        if (!std::isnan(out.distance[k])) continue;
        if (!nextToFilled[std::size_t(b) * T + a]) {
          out.distance[k] = float(-reach);
          continue;
        }
        const Vec3d onFace = projection::facePoint(f, Vec2d(double(a) / (T - 1), double(b) / (T - 1)));
        const double length = glm::length(out.proj.lineEnd(f, onFace) - onFace);
        const Rayd line = projectionLine(out.proj, f, onFace, cellMin, h);
        const Hitd hit = near.closestHit(Rayd(line.origin, -line.direction, 0.0, reach / length));
        out.distance[k] = float(hit.valid() ? -hit.t * length : -reach);
        if (hit.valid())
          sampleSignals(mesh, signals, options, hit, signals.normals ? &out.normal[k] : nullptr,
                        signals.colors ? &out.color[k] : nullptr);
      }
  }
}

/// Samples one grey cell: chooses its projection, then samples its faces. FewestCrossings samples
/// with the canonical projection first and searches for a better point only when some of its
/// lines cross the surface twice.
inline CellSamples sampleCell(const TriangleMesh& mesh, const cells::CellComplex& complex,
                              const MeshRayQuery& query, const ConvertOptions& options,
                              const Signals& signals, const cells::GreyCell& cell, int T) {
  using projection::CentreOfProjection;
  CellSamples out;
  const double h = complex.cellSizeWS();
  const Vec3d cellMin = complex.cellMinWS(cell.ijk);
  std::optional<Vec3d> centroid;
  if (options.centre == CentreOfProjection::SurfaceCentroid) {
    std::vector<SurfaceSample> surf;
    sampleCellSurface(complex, mesh.triangles, cell, 256.0, 4096, surf);
    centroid = sampleCentroid(surf);
  }
  const CentreOfProjection first =
      options.centre == CentreOfProjection::FewestCrossings ? CentreOfProjection::CellCentre : options.centre;
  out.proj = projection::chooseProjection<double>(cell.configuration, first, centroid);
  // Every projection line lies in the cell, but for the stretch a parallel one searches past
  // the opposite face: only the triangles that meet that box can be hit. Not
  // CellComplex::cellTriangles: the complex found those on snapped positions, which may miss a
  // triangle that touches the cell.
  const Aabbd box = complex.cellBoxWS(cell.ijk);
  const Vec3d reach(h * pastLineEnd(out.proj.type, T));
  const TrianglesInBox<double> surface(query.bvh, Aabbd(box.min - reach, box.max + reach));
  sampleFaces(mesh, surface, options, signals, cellMin, h, T, out);
  if (options.centre == CentreOfProjection::FewestCrossings && out.linesCrossedTwice > 0) {
    const auto better = fewestCrossingsProjection(cell.configuration, surface, cellMin, h);
    if (better.point != out.proj.point) {
      // The search saw 9 x 9 lines per face; keep the canonical samples unless the T x T agree.
      CellSamples moved;
      moved.proj = better;
      moved.centreMoved = true;
      sampleFaces(mesh, surface, options, signals, cellMin, h, T, moved);
      if (moved.linesCrossedTwice < out.linesCrossedTwice) out = std::move(moved);
    }
  }
  if (cell.configuration == 0) {
    out.centreInside = query.contains(cellMin + h * out.proj.point);
    const Vec3d before(h * beforeFace(T));
    sampleBeforeFaces(mesh, TrianglesInBox<double>(query.bvh, Aabbd(box.min - before, box.max + before)), options,
                      signals, cellMin, h, T, out);
  }
  return out;
}

/// The grey cells that hold a boundary edge of the mesh (CellRecord::kOpenSurface): each edge is
/// walked in steps of at most a quarter cell, and every cell within a millionth of a cell of a
/// step's point is marked (an edge in a cell plane marks the cells on both sides).
inline std::vector<char> openCells(const TriangleMesh& mesh, const cells::CellComplex& complex) {
  std::vector<char> open(complex.greyCells().size(), 0);
  const int n = complex.gridSize();
  const auto& tree = complex.grid().tree();
  constexpr double kSlack = 1e-6;
  for (const auto& [a, b] : boundaryEdges(mesh)) {
    const Vec3d pa = complex.worldToIndex(Vec3d(mesh.positions[a]));
    const Vec3d pb = complex.worldToIndex(Vec3d(mesh.positions[b]));
    const int steps = 1 + int(std::ceil(4.0 * glm::length(pb - pa)));
    for (int k = 0; k <= steps; ++k) {
      const Vec3d p = pa + (pb - pa) * (double(k) / steps);
      const Vec3i lo = glm::clamp(Vec3i(glm::floor(p - kSlack)), Vec3i(0), Vec3i(n - 1));
      const Vec3i hi = glm::clamp(Vec3i(glm::floor(p + kSlack)), Vec3i(0), Vec3i(n - 1));
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x)
            if (const std::int32_t index = tree.getValue(openvdb::Coord(x, y, z)); index >= 0) open[index] = 1;
    }
  }
  return open;
}

/// The model's header and look-up table: one record per grey cell, layers for present faces only
/// (in cell and face order), and the largest distance, which sets the quantization step.
/// `open` marks the grey cells that hold a boundary edge of the mesh (openCells).
inline ReliefModel layOutLayers(const cells::CellComplex& complex, const std::vector<CellSamples>& samples,
                                const std::vector<char>& open, const ConvertOptions& options,
                                const Signals& signals, int T, ConvertReport& rep) {
  const auto grey = complex.greyCells();
  ReliefModel model;
  model.gridSize = complex.gridSize();
  model.originWS = complex.boundsWS().min;
  model.cellSizeWS = complex.cellSizeWS();
  model.texels = T;
  model.distanceCodec.bits = options.distanceBits;
  model.normalFormat = signals.normals ? options.normals : NormalFormat::None;
  model.colorFormat = signals.colors ? ColorFormat::Rgba8 : ColorFormat::None;
  std::uint32_t layers = 0;
  float maxDistance = 0, minDistance = 0;
  model.cells.resize(grey.size());
  for (std::size_t ci = 0; ci < grey.size(); ++ci) {
    const cells::GreyCell& g = grey[ci];
    const CellSamples& s = samples[ci];
    CellRecord& r = model.cells[ci];
    r.packedIjk = CellRecord::packIjk(g.ijk) | (s.centreInside ? CellRecord::kCentreInside : 0u) |
                  (open[ci] ? CellRecord::kOpenSurface : 0u);
    r.configuration = g.configuration;
    r.projectionType = std::uint8_t(s.proj.type);
    r.faceOrAxis = std::uint8_t(std::max(0, s.proj.faceOrAxis));
    r.presentFaces = s.present;
    r.firstLayer = layers;
    for (int a = 0; a < 3; ++a) r.point[a] = float(s.proj.point[a]);
    layers += std::popcount(unsigned(r.presentFaces));
    rep.droppedLayers += std::popcount(unsigned(g.domainFaces())) - std::popcount(unsigned(r.presentFaces));
    rep.linesCrossedTwice += std::size_t(s.linesCrossedTwice);
    rep.movedCentres += s.centreMoved ? 1 : 0;
    for (const float d : s.distance)
      if (!std::isnan(d)) {
        maxDistance = std::max(maxDistance, d);
        minDistance = std::min(minDistance, d);
      }
  }
  model.distanceCodec.distanceMax = maxDistance > 0 ? maxDistance : 1.0f;
  model.distanceCodec.zeroCode =
      DistanceCodec::zeroCodeFor(options.distanceBits, model.distanceCodec.distanceMax, -double(minDistance));
  if (layers > 0) {
    model.visitDistances([&](auto& maps) {
      maps = std::decay_t<decltype(maps)>(T, T, int(layers), 1);
    });
    if (model.normalFormat == NormalFormat::Octahedral16)
      model.normals16 = ImageArray<std::uint16_t>(T, T, int(layers), 2);
    if (model.normalFormat == NormalFormat::Rgba8) model.normals8 = ImageArray<std::uint8_t>(T, T, int(layers), 4);
    if (model.colorFormat == ColorFormat::Rgba8) model.colors = ImageArray<std::uint8_t>(T, T, int(layers), 4);
  }
  rep.layers = layers;
  return model;
}

/// Quantizes one cell's samples into its layers of the maps; returns (filled, empty) samples, a
/// sample before its face (sampleBeforeFaces) counted as empty. Signals are kept for filled ones.
inline std::pair<std::size_t, std::size_t> quantizeCell(ReliefModel& model, const CellRecord& r,
                                                        const CellSamples& s) {
  const int T = model.texels;
  const DistanceCodec& codec = model.distanceCodec;
  std::size_t filled = 0, empty = 0;
  int slot = 0;
  for (int f = 0; f < cells::kFaceCount; ++f) {
    if (!(cells::domainFacesOf(r.configuration) & (1u << f))) continue;
    const int layer = r.layerOf(f);
    if (layer >= 0)
      for (int b = 0; b < T; ++b)
        for (int a = 0; a < T; ++a) {
          const std::size_t k = (std::size_t(slot) * T + b) * T + a;
          const float d = s.distance[k];
          const std::uint32_t code = std::isnan(d) ? codec.emptyCode() : codec.encode(d);
          const bool hasSurface = codec.hasSurface(code);
          (hasSurface ? filled : empty)++;
          model.visitDistances([&](auto& maps) {
            maps.at(a, b, layer, 0) = typename std::decay_t<decltype(maps)>::Scalar(code);
          });
          if (!hasSurface) continue;
          if (model.normalFormat == NormalFormat::Octahedral16) {
            const Vec2f e = octahedralEncode(s.normal[k]);
            model.normals16.at(a, b, layer, 0) = quantizeUnorm<std::uint16_t>(e.x);
            model.normals16.at(a, b, layer, 1) = quantizeUnorm<std::uint16_t>(e.y);
          } else if (model.normalFormat == NormalFormat::Rgba8) {
            const Vec3f e = s.normal[k] * 0.5f + 0.5f;
            for (int c = 0; c < 3; ++c) model.normals8.at(a, b, layer, c) = quantizeUnorm<std::uint8_t>(e[c]);
            model.normals8.at(a, b, layer, 3) = 255;
          }
          if (model.colorFormat == ColorFormat::Rgba8)
            for (int c = 0; c < 4; ++c) model.colors.at(a, b, layer, c) = s.color[k][c];
        }
    ++slot;
  }
  return {filled, empty};
}

/// Calls `progress` about 100 times over `total` steps, never twice at once and never backwards.
class ProgressReporter {
 public:
  ProgressReporter(const std::function<void(double)>& progress, std::size_t total)
      : mProgress(progress), mTotal(total), mEvery(std::max<std::size_t>(1, total / 100)) {}
  void step() {
    const std::size_t finished = ++mDone;
    if (!mProgress || finished % mEvery != 0) return;
    std::unique_lock lock(mMutex, std::try_to_lock);
    const double fraction = double(finished) / double(mTotal);
    if (lock.owns_lock() && fraction > mReported) mProgress(mReported = fraction);
  }

 private:
  const std::function<void(double)>& mProgress;
  std::size_t mTotal, mEvery;
  std::atomic<std::size_t> mDone{0};
  std::mutex mMutex;
  double mReported = 0;
};

}  // namespace detail

/// Samples the maps of a relief model on a cell complex of `mesh` and a ray query of it that the
/// caller already has (options.gridSize is ignored: the complex fixes N). Reports the sampling
/// time only; convert() below adds the grid. Steps: check the options and memory, sample every
/// grey cell (in parallel), lay out the layers of the faces that hold surface, quantize the maps.
inline ReliefModel convert(const TriangleMesh& mesh, const cells::CellComplex& complex,
                           const MeshRayQuery& query, const ConvertOptions& options,
                           ConvertReport* report = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  ConvertReport local;
  ConvertReport& rep = report ? *report : local;
  const int T = detail::checkConversion(complex, options);
  const detail::Signals signals = detail::signalsOf(mesh, options);
  const auto grey = complex.greyCells();

  std::vector<detail::CellSamples> samples(grey.size());
  detail::ProgressReporter progress(options.progress, grey.size());
  parallelFor(0, grey.size(), [&](std::size_t ci) {
    samples[ci] = detail::sampleCell(mesh, complex, query, options, signals, grey[ci], T);
    progress.step();
  }, 4);

  ReliefModel model = detail::layOutLayers(complex, samples, detail::openCells(mesh, complex), options, signals, T, rep);
  std::atomic<std::size_t> filled{0}, empty{0};
  parallelFor(0, grey.size(), [&](std::size_t ci) {
    const auto [f, e] = detail::quantizeCell(model, model.cells[ci], samples[ci]);
    filled += f;
    empty += e;
  }, 16);
  if (options.progress) options.progress(1.0);
  // No stored sample means no model: the mesh encloses nothing the grid sees. Refused rather than
  // written as an empty model whose error reads "inf".
  if (filled == 0)
    throw Error(ErrorKind::InvalidInput,
                "the mesh gives no grey cell with a stored sample on the " + std::to_string(complex.gridSize()) +
                    "^3 grid (" + std::to_string(grey.size()) + " grey cells, " + std::to_string(rep.layers) +
                    " face layers), so no relief model: no projection line of its cells meets the surface");

  rep.greyCells = grey.size();
  rep.filledSamples = filled;
  rep.emptySamples = empty;
  rep.quantizationErrorWS = model.quantizationError() * complex.cellSizeWS();
  rep.sampleSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  rep.totalSeconds = rep.gridSeconds + rep.sampleSeconds;
  return model;
}

namespace detail {
/// A flat mesh's slab has no occlusion, so the occlusion ratio stops the grid search at once; but
/// where a projection centre or axis lies near the slab (the cells along its rim), its sides are
/// seen at grazing angles and sampled sparsely, which only smaller cells cure (measured: the
/// Hausdorff distance falls about as 1/N). So its grid is chosen by measured error: N doubles from
/// 2 until the model rebuilt from its maps is within kFlatHausdorff of the input (over the diagonal)
/// or N reaches N_max; the most accurate model is kept.
inline constexpr double kFlatHausdorff = 0.01;

inline ReliefModel convertSlabByError(const TriangleMesh& input, const TriangleMesh& slab,
                                      const MeshRayQuery& query, const ConvertOptions& options,
                                      ConvertReport& rep, std::chrono::steady_clock::time_point start) {
  const double diagonal = double(input.surfaceBounds().diagonal());
  const metrics::DistanceField inputField(input);
  ReliefModel best;
  ConvertReport bestReport;
  double bestError = std::numeric_limits<double>::infinity();
  const int maxN = std::max(1, options.gridSearch.maxGridSize);
  for (int n = std::min(2, maxN);; n = std::min(2 * n, maxN)) {
    const auto trialStart = std::chrono::steady_clock::now();
    ConvertOptions trialOptions = options;
    trialOptions.progress = nullptr;
    ConvertReport trial;
    std::optional<cells::CellComplex> complex;
    ReliefModel model;
    try {
      complex = cells::CellComplex::build(
          slab, {.gridSize = n, .memoryLimitBytes = std::min(options.memoryLimitBytes,
                                                             options.gridSearch.memoryLimitBytes)});
      model = convert(slab, *complex, query, trialOptions, &trial);
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::ResourceLimit || rep.gridTrials.empty()) throw;
      break;  // the finest grid that fits is the answer
    }
    const double error =
        metrics::surfaceError(input, inputField, reconstructPerFace(model), 50000).hausdorff() / diagonal;
    rep.gridTrials.push_back(
        {.gridSize = n, .greyCells = complex->stats().grey,
         .seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - trialStart).count(),
         .hausdorff = error});
    if (error < bestError) {
      bestError = error;
      best = std::move(model);
      bestReport = trial;
    }
    if (error <= kFlatHausdorff || n >= maxN) break;
  }
  bestReport.gridTrials = std::move(rep.gridTrials);
  bestReport.slabThicknessWS = rep.slabThicknessWS;
  bestReport.totalSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bestReport.gridSeconds = bestReport.totalSeconds - bestReport.sampleSeconds;
  rep = std::move(bestReport);
  if (options.progress) options.progress(1.0);
  return best;
}
}  // namespace detail

/// Converts a mesh: a flat mesh becomes a thin slab (flat_mesh.h), then the ray query, the grid
/// (chosen from the occlusion ratio when options.gridSize is 0, reusing the search's complex),
/// then the maps. Throws Error on bad input (see CellComplex::build) or bad options.
inline ReliefModel convert(const TriangleMesh& input, const ConvertOptions& options = {},
                           ConvertReport* report = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  ConvertReport local;
  ConvertReport& rep = report ? *report : local;
  const std::optional<TriangleMesh> slab = slabIfFlat(input, &rep.slabThicknessWS);
  const TriangleMesh& mesh = slab ? *slab : input;
  const MeshRayQuery query(mesh);
  if (slab && options.gridSize == 0) return detail::convertSlabByError(input, mesh, query, options, rep, start);
  std::shared_ptr<const cells::CellComplex> complex;
  if (options.gridSize == 0) {
    GridSizeOptions search = options.gridSearch;
    search.texels = options.texels;
    search.memoryLimitBytes = std::min(search.memoryLimitBytes, options.memoryLimitBytes);
    GridSizeChoice choice = chooseGridSize(mesh, search, &query);
    rep.gridTrials = choice.trials;
    complex = std::move(choice.complex);
  } else {
    complex = std::make_shared<const cells::CellComplex>(cells::CellComplex::build(
        mesh, {.gridSize = options.gridSize, .memoryLimitBytes = options.memoryLimitBytes}));
  }
  rep.gridSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return convert(mesh, *complex, query, options, &rep);
}

}  // namespace cellrelief::relief
