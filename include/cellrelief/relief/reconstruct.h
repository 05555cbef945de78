// SPDX-License-Identifier: MIT
/// @file reconstruct.h
/// Geometry-based reconstruction (Apaza & Andujar, 3.5.1): a triangle mesh rebuilt from the maps,
/// by one of two methods (ReconstructionMethod):
/// - Closed (closed_reconstruction.h): the zero set of the model's inside/outside field, closed
///   and manifold by construction; the default for models of closed inputs of more than one
///   cell (see reconstruct(model, options) for Auto).
/// - PerFace (the paper's): every 2 x 2 block of neighbouring samples of a face becomes two triangles (one when a corner is
/// empty), each vertex unprojected with its stored distance. Level of detail L uses every 2^L-th
/// sample, the vertex-centred mip level L of the maps, which keeps the face edges.
///
/// Cracks of the per-face method: within a face there are none. Faces of one cell that share an edge sample the same
/// projection lines along it (vertex-centred samples), so their border vertices coincide and are
/// welded. Between cells, where a projection line lies in the shared cell plane (parallel and
/// planar faces, and faces whose centre or axis lies on that plane) both cells put vertices on the
/// same curve where the surface crosses the plane, leaving only slivers between two chords of it;
/// elsewhere a gap of at most one sample spacing can remain. reconstructionGap() in the accuracy
/// figures includes all of them. It is the default for open inputs, whose holes the field would
/// close (white space reaches both sides of an open surface).
#pragma once

#include <cmath>
#include <unordered_map>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/mesh_topology.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/relief/closed_reconstruction.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::relief {

enum class ReconstructionMethod {
  Auto,     ///< Closed for a model of a closed input, PerFace for an open one (details: reconstruct())
  Closed,   ///< the zero set of the inside/outside field (closed_reconstruction.h)
  PerFace,  ///< the paper's: each face's samples joined into triangles
};

struct ReconstructOptions {
  int levelOfDetail = 0;  ///< every 2^L-th sample, 0..maxLevelOfDetail(model)
  ReconstructionMethod method = ReconstructionMethod::Auto;
};

/// The paper's reconstruction: each face's samples joined into triangles (see the file comment).
inline TriangleMesh reconstructPerFace(const ReliefModel& model, int lod = 0) {
  checkLevelOfDetail(model, lod);
  const int step = 1 << lod;
  const int S = (model.texels - 1) / step + 1;  // samples per side at this level
  struct Part {
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::vector<Color8> colors;
    std::vector<Vec3u> triangles;
  };
  std::vector<Part> parts(model.cells.size());
  parallelFor(0, model.cells.size(), [&](std::size_t ci) {
    const CellRecord& r = model.cells[ci];
    const auto proj = r.projection<double>();
    Part& part = parts[ci];
    // Weld within the cell: samples on a shared face edge unproject to the same point.
    std::unordered_map<std::uint64_t, std::uint32_t> welded;
    std::vector<std::int64_t> index(std::size_t(S) * S);
    for (int f = 0; f < cells::kFaceCount; ++f) {
      const int layer = r.layerOf(f);
      if (layer < 0) continue;
      for (int b = 0; b < S; ++b)
        for (int a = 0; a < S; ++a) {
          const std::uint32_t code = model.distanceCode(layer, a * step, b * step);
          std::int64_t& id = index[std::size_t(b) * S + a];
          id = -1;
          if (!model.distanceCodec.hasSurface(code)) continue;
          const float d = model.distanceCodec.decode(code);
          const Vec2d uv(double(a * step) / (model.texels - 1), double(b * step) / (model.texels - 1));
          const Vec3d p = proj.unproject(f, uv, double(d));
          const bool onEdge = a == 0 || b == 0 || a == S - 1 || b == S - 1;
          if (onEdge) {
            // Key: the edge sample's 3D position on the unit cell's surface and its code.
            const Vec3d onFace = projection::facePoint(f, uv);
            const std::uint64_t key =
                (std::uint64_t(std::lround(onFace.x * (model.texels - 1))) << 48) ^
                (std::uint64_t(std::lround(onFace.y * (model.texels - 1))) << 32) ^
                (std::uint64_t(std::lround(onFace.z * (model.texels - 1))) << 16) ^
                std::uint64_t(code);
            const auto [it, inserted] = welded.try_emplace(key, std::uint32_t(part.positions.size()));
            if (!inserted) {
              id = it->second;
              continue;
            }
          }
          id = std::int64_t(part.positions.size());
          part.positions.push_back(Vec3f(model.toWorld(r.ijk(), p)));
          if (model.normalFormat != NormalFormat::None)
            part.normals.push_back(model.normal(layer, a * step, b * step));
          if (model.colorFormat == ColorFormat::Rgba8) {
            Color8 c;
            for (int k = 0; k < 4; ++k) c[k] = model.colors.at(a * step, b * step, layer, k);
            part.colors.push_back(c);
          }
        }
      // Two triangles per 2 x 2 block, one when a corner is empty. The winding follows the face's
      // (u, v) frame, flipped on negative faces, so triangles face out of the cell.
      const bool flip = cells::faceSign(f) < 0;
      // Neighbouring samples that hit different sheets of surface (at an occlusion boundary) are
      // not joined: an edge longer than kMaxEdgeSpacings sample spacings is a depth jump, not a
      // slanted surface (that allows slopes up to about 75 degrees).
      constexpr float kMaxEdgeSpacings = 4.0f;
      const float maxEdge2 = std::pow(kMaxEdgeSpacings * float(step) * float(model.cellSizeWS) /
                                          float(model.texels - 1), 2.0f);
      auto emit = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
        if (x == y || y == z || x == z) return;
        const Vec3f &px = part.positions[x], &py = part.positions[y], &pz = part.positions[z];
        if (glm::dot(px - py, px - py) > maxEdge2 || glm::dot(py - pz, py - pz) > maxEdge2 ||
            glm::dot(pz - px, pz - px) > maxEdge2)
          return;
        part.triangles.push_back(flip ? Vec3u(std::uint32_t(x), std::uint32_t(z), std::uint32_t(y))
                                      : Vec3u(std::uint32_t(x), std::uint32_t(y), std::uint32_t(z)));
      };
      for (int b = 0; b + 1 < S; ++b)
        for (int a = 0; a + 1 < S; ++a) {
          const std::int64_t i00 = index[std::size_t(b) * S + a], i10 = index[std::size_t(b) * S + a + 1],
                             i01 = index[std::size_t(b + 1) * S + a],
                             i11 = index[std::size_t(b + 1) * S + a + 1];
          const int present = (i00 >= 0) + (i10 >= 0) + (i01 >= 0) + (i11 >= 0);
          if (present == 4) {
            emit(i00, i10, i11);
            emit(i00, i11, i01);
          } else if (present == 3) {
            if (i00 < 0) emit(i10, i11, i01);
            else if (i10 < 0) emit(i00, i11, i01);
            else if (i01 < 0) emit(i00, i10, i11);
            else emit(i00, i10, i01);
          }
        }
    }
  }, 16);
  TriangleMesh mesh;
  std::size_t vertices = 0, triangles = 0;
  for (const Part& p : parts) {
    vertices += p.positions.size();
    triangles += p.triangles.size();
  }
  mesh.positions.reserve(vertices);
  mesh.triangles.reserve(triangles);
  for (const Part& p : parts) {
    const auto base = std::uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), p.positions.begin(), p.positions.end());
    mesh.normals.insert(mesh.normals.end(), p.normals.begin(), p.normals.end());
    mesh.colors.insert(mesh.colors.end(), p.colors.begin(), p.colors.end());
    for (const Vec3u& t : p.triangles) mesh.triangles.push_back(t + Vec3u(base));
  }
  mesh.sourcePolygons = mesh.triangles.size();
  return mesh;
}

/// Bounds of the closed mesh's area over the per-face mesh's that Auto accepts: the per-face
/// mesh lacks its cracks (1.05 to 1.23 on the closed meshes of the test data); outside them,
/// surface thinner than a lattice spacing was lost between the lattice points or doubled across
/// it (a flat input's slab measured 2.1), and the samples still hold it.
inline constexpr double kMinClosedAreaRatio = 0.9;
inline constexpr double kMaxClosedAreaRatio = 1.5;

/// Auto: the per-face method for an open input; for a closed one, the per-face mesh where it is
/// already closed and manifold (a single grey cell, whose faces weld along their shared edges:
/// its vertices are the samples themselves, the most accurate), else the closed method, unless
/// its area falls outside kMinClosedAreaRatio..kMaxClosedAreaRatio of the per-face mesh's, its
/// lattice is too large (checkLatticeSize) or it is not closed after all (a defect: the per-face
/// mesh is then the safer answer).
inline TriangleMesh reconstruct(const ReliefModel& model, const ReconstructOptions& options) {
  checkLevelOfDetail(model, options.levelOfDetail);
  const int lod = options.levelOfDetail;
  switch (options.method) {
    case ReconstructionMethod::PerFace: return reconstructPerFace(model, lod);
    case ReconstructionMethod::Closed: return reconstructClosed(model, lod);
    case ReconstructionMethod::Auto: break;
  }
  if (model.openSurface() || model.layerCount() == 0) return reconstructPerFace(model, lod);
  TriangleMesh perFace = reconstructPerFace(model, lod);
  if (model.cells.size() == 1) {
    const MeshTopology topology = analyzeTopology(perFace);
    if (topology.closed() && topology.manifold() && topology.oriented()) return perFace;
  }
  TriangleMesh closed;
  try {
    closed = reconstructClosed(model, lod);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::ResourceLimit) throw;
    return perFace;
  }
  const double ratio = surfaceArea(closed) / surfaceArea(perFace);
  if (!(ratio >= kMinClosedAreaRatio && ratio <= kMaxClosedAreaRatio)) return perFace;
  if (countBoundaryEdges(closed) != 0) return perFace;
  return closed;
}

/// The reconstruction by the method that suits the model (ReconstructionMethod::Auto).
inline TriangleMesh reconstruct(const ReliefModel& model, int lod = 0) {
  return reconstruct(model, ReconstructOptions{lod, ReconstructionMethod::Auto});
}

}  // namespace cellrelief::relief
