// SPDX-License-Identifier: MIT
/// @file mesh_map.h
/// A mesh mapped onto its polycube, the steps `cellrelief polycube` and the Python module share:
/// 1. the domain: a polycube built automatically (from_mesh.h) or given, then checked against the
///    mesh (a closed 2-manifold in one piece, of the mesh's genus); a given one without a frame is
///    fitted over the mesh;
/// 2. the map (parameterization.h), refused while it folds a triangle;
/// 3. T2 baked from a signal: the paper's grid pattern, or the mesh's normals, shading or colours.
/// mapMeshOntoPolycube runs all three and returns a TexturedMesh a scene renders.
#pragma once

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "cellrelief/polycube/from_mesh.h"
#include "cellrelief/polycube/mesh_signal.h"
#include "cellrelief/polycube/parameterization.h"
#include "cellrelief/polycube/polycube_file.h"
#include "cellrelief/polycube/textured_mesh.h"

namespace cellrelief::polycube {

namespace detail {
/// An error about `source` where there is one (a file), else about the request.
inline Error errorAbout(ErrorKind kind, const std::filesystem::path& source, const std::string& problem) {
  return source.empty() ? Error(kind, problem) : Error(kind, source, problem);
}
}  // namespace detail

/// The polycube a mesh is mapped onto, placed in world space.
struct PolycubeDomain {
  Polycube polycube;
  PolycubeFrame frame;
  std::optional<int> meshGenus;          ///< cappedGenus of the mesh; none when not one manifold piece
  std::optional<PolycubeResult> search;  ///< the automatic search (its trials); none for a given polycube
};

/// A given polycube without a frame placed over the mesh: centred on its bounds, scaled uniformly
/// so that its largest extent is the mesh's.
inline PolycubeFrame fitFrame(const Polycube& p, const TriangleMesh& mesh) {
  const Aabbd bounds(Vec3d(mesh.bounds().min), Vec3d(mesh.bounds().max));
  const Vec3d lo(p.minCube()), hi(Vec3d(p.maxCube()) + Vec3d(1));
  const Vec3d meshExtent = bounds.max - bounds.min, cubeExtent = hi - lo;
  const double size = std::max({meshExtent.x, meshExtent.y, meshExtent.z}) /
                      std::max({cubeExtent.x, cubeExtent.y, cubeExtent.z});
  return {bounds.center() - size * 0.5 * (lo + hi), size};
}

/// Throws InvalidInput naming `source` unless `p`'s surface is a 2-manifold in one piece of genus
/// `meshGenus` (when that is known).
inline void checkPolycubeForMesh(const Polycube& p, std::optional<int> meshGenus, const std::filesystem::path& source) {
  if (p.size() == 0) throw detail::errorAbout(ErrorKind::InvalidInput, source, "the polycube has no cubes");
  const std::vector<Vec3i> bad = p.nonManifoldVertices();
  if (!bad.empty())
    throw detail::errorAbout(ErrorKind::InvalidInput, source,
                "the polycube's surface is not a 2-manifold at " + std::to_string(bad.size()) +
                    " lattice vertices, the first (" + std::to_string(bad[0].x) + ", " + std::to_string(bad[0].y) +
                    ", " + std::to_string(bad[0].z) + "): cubes meet only along an edge or at a corner there");
  const SurfaceStats s = p.surfaceStats();
  if (s.components != 1)
    throw detail::errorAbout(ErrorKind::InvalidInput, source,
                "the polycube's surface has " + std::to_string(s.components) + " pieces; it must be one");
  if (meshGenus && s.genus() != meshGenus)
    throw detail::errorAbout(ErrorKind::InvalidInput, source,
                "the polycube has genus " + std::to_string(s.genus().value_or(-1)) + ", the mesh " +
                    std::to_string(*meshGenus));
}

/// Step 1 with a given polycube (`source` names where it came from in errors).
inline PolycubeDomain givenDomain(const TriangleMesh& mesh, PolycubeFile cubes, const std::filesystem::path& source) {
  PolycubeDomain d;
  d.meshGenus = cappedGenus(analyzeTopology(mesh));
  checkPolycubeForMesh(cubes.polycube, d.meshGenus, source);
  d.frame = cubes.hasFrame ? cubes.frame : fitFrame(cubes.polycube, mesh);
  if (!(d.frame.cubeSize > 0) || !std::isfinite(d.frame.cubeSize))
    throw detail::errorAbout(ErrorKind::InvalidInput, source,
                             "the mesh's bounds have no extent: a polycube cannot be fitted over it");
  d.polycube = std::move(cubes.polycube);
  return d;
}

/// Step 1, automatic: the coarsest lattice whose polycube keeps the mesh's genus (or options' N).
inline PolycubeDomain automaticDomain(const TriangleMesh& mesh, const PolycubeOptions& options = {}) {
  PolycubeDomain d;
  d.search = polycubeOfMesh(mesh, options);
  d.polycube = d.search->polycube;
  d.frame = d.search->frame;
  d.meshGenus = d.search->meshGenus;
  return d;
}

/// Step 2's check: throws InvalidInput naming `source` while the map folds a triangle; `remedy`
/// ends the message (a command line names its options there).
inline void requireUnfolded(const PolycubeParameterization& map, const TriangleMesh& mesh,
                            const std::filesystem::path& source,
                            std::string_view remedy = "try another grid, more sweeps or a polycube of your own") {
  if (map.final.flipped == 0) return;
  throw detail::errorAbout(ErrorKind::InvalidInput, source,
              "the map onto the polycube still folds " + std::to_string(map.final.flipped) + " of " +
                  std::to_string(mesh.triangleCount()) + " triangles after " + std::to_string(map.sweeps) +
                  " sweeps: a feature is likely thinner than a cube or the polycube misses it; " + std::string(remedy));
}

/// A signal by name: "grid" (none: the paper's pattern) or a MeshSignalKind's. Throws
/// InvalidArgument, the message starting with `what` (the option's name), for any other name.
inline std::optional<MeshSignalKind> parseSignal(std::string_view name, std::string_view what) {
  if (name == "grid") return std::nullopt;
  for (auto k : {MeshSignalKind::Normal, MeshSignalKind::Shading, MeshSignalKind::Color})
    if (toString(k) == name) return k;
  throw Error(ErrorKind::InvalidArgument,
              std::string(what) + ": '" + std::string(name) + "' is not grid, normals, shading or color");
}

/// Step 3: T2 of `signal` (none: the paper's grid pattern) with S texels per squarelet side.
/// Throws InvalidInput for colours of a mesh without vertex colours.
inline PolycubeTexture bakeSignal(const TriangleMesh& mesh, std::span<const Vec3d> texture,
                                  std::shared_ptr<const PolycubeSurface> surface, std::optional<MeshSignalKind> signal,
                                  int texelsPerSquarelet) {
  if (signal == MeshSignalKind::Color && !mesh.hasColors())
    throw Error(ErrorKind::InvalidInput, "polycube signal color: the mesh has no vertex colours");
  const SurfaceSignal values = signal ? meshSignal(std::make_shared<const InverseMap>(mesh, texture), *signal)
                                      : gridSignalFor(texelsPerSquarelet);
  return PolycubeTexture(std::move(surface), values, {texelsPerSquarelet});
}

/// What T2 of a signal is for: normals shade, everything else is colour.
constexpr TextureUse textureUseOf(std::optional<MeshSignalKind> signal) {
  return signal == MeshSignalKind::Normal ? TextureUse::Normal : TextureUse::Color;
}

struct MeshMapOptions {
  PolycubeOptions polycube;           ///< the automatic search, unless `cubes` is given
  std::optional<PolycubeFile> cubes;  ///< a given polycube; without a frame it is fitted over the mesh
  ParameterizationOptions map;
  std::optional<MeshSignalKind> signal;  ///< none: the paper's grid pattern
  int texelsPerSquarelet = 16;           ///< S, a power of two in 1..256
};

/// All three steps' results.
struct MeshMap {
  PolycubeDomain domain;
  PolycubeParameterization map;
  std::shared_ptr<TexturedMesh> textured;  ///< the mesh, its texture positions and T2: what a scene holds
};

/// Maps `mesh` onto its polycube and bakes T2. Errors name `source` (the mesh's file, if any).
inline MeshMap mapMeshOntoPolycube(const TriangleMesh& mesh, const MeshMapOptions& options,
                                   const std::filesystem::path& source = {}) {
  const int s = options.texelsPerSquarelet;
  if (s < 1 || s > 256 || (s & (s - 1)) != 0)
    throw Error(ErrorKind::InvalidArgument, "polycube: texels per squarelet must be a power of two in 1..256, not " +
                                                std::to_string(s));
  if (options.signal == MeshSignalKind::Color && !mesh.hasColors())
    throw detail::errorAbout(ErrorKind::InvalidInput, source, "polycube signal color: the mesh has no vertex colours");
  mesh.validate(source.empty() ? "polycube" : source.string());
  MeshMap out;
  out.domain = options.cubes ? givenDomain(mesh, *options.cubes, source) : automaticDomain(mesh, options.polycube);
  const auto surface = std::make_shared<const PolycubeSurface>(out.domain.polycube);
  out.map = parameterize(mesh, *surface, out.domain.frame, options.map);
  requireUnfolded(out.map, mesh, source);
  out.textured = std::make_shared<TexturedMesh>();
  out.textured->t2 = std::make_shared<const PolycubeTexture>(
      bakeSignal(mesh, out.map.texture, surface, options.signal, options.texelsPerSquarelet));
  out.textured->use = textureUseOf(options.signal);
  out.textured->mesh = mesh;
  out.textured->texture.assign(out.map.texture.begin(), out.map.texture.end());
  return out;
}

}  // namespace cellrelief::polycube
