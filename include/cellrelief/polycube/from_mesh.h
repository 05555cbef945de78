// SPDX-License-Identifier: MIT
/// @file from_mesh.h
/// A polycube built automatically from a mesh: the paper builds its polycubes by hand; here they
/// come from a coarse cubic cell complex of the mesh (cells/cell_complex.h).
///
/// For a lattice of N cubes along the mesh's bounding cube:
/// 1. voxelize: the black cells of the complex, and the grey cells whose centre is inside (the
///    generalized winding number there above 1/2, which also holds for meshes with holes);
/// 2. keep the largest 6-connected piece and fill its cavities (one closed shell);
/// 3. make it manifold: at each lattice vertex where cubes meet only along an edge or at a corner,
///    add the fewest cubes, preferring cells the surface passes through (makeManifold);
/// 4. only with removeCase6b: remove the vertices of case 6b (removeVerticesOfCase: toggling one
///    cube, or a pair; their projection stretches about four times more than the other cases'),
///    keeping the surface manifold and its genus;
/// 5. accept it when its genus is the mesh's.
/// With N = 0 (automatic) the coarsest N of `autoSizes` that passes is taken: few cubes per large
/// feature, as the paper's polycubes have. Where no size passes, an Error says why (the genera
/// each size gave), and nothing is returned.
#pragma once

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cellrelief/cells/cell_complex.h"
#include "cellrelief/cells/winding_number.h"
#include "cellrelief/core/mesh_topology.h"
#include "cellrelief/polycube/polycube.h"

namespace cellrelief::polycube {

struct PolycubeOptions {
  int cubesPerSide = 0;  ///< N; 0: the coarsest of autoSizes that keeps the genus
  std::vector<int> autoSizes = {6, 8, 10, 12, 16, 20, 24, 32};
  /// Accept only a polycube of the mesh's genus (with its holes capped). A mesh whose genus is
  /// unknown (non-manifold, or in pieces) takes the first closed manifold polycube.
  bool matchGenus = true;
  /// Step 4: toggle cubes to remove the vertices of case 6b, whose P stretches the most. Off by
  /// default: the toggled cubes cost more than the stretch (fertility's map keeps 16 flipped
  /// triangles on the polycube without them, 1 on the one with its 12 case-6b vertices).
  bool removeCase6b = false;
};

/// Genus of a connected manifold mesh with its holes capped: (2 - chi - boundary loops) / 2.
inline std::optional<int> cappedGenus(const MeshTopology& topology) {
  if (topology.components != 1 || !topology.manifold()) return std::nullopt;
  const long long twice = 2 - topology.eulerCharacteristic - (long long)topology.boundaryLoops;
  if (twice < 0 || twice % 2 != 0) return std::nullopt;
  return int(twice / 2);
}

/// What one lattice size gave.
struct PolycubeTrial {
  int cubesPerSide = 0;
  std::size_t cubes = 0, addedForManifold = 0;
  std::size_t case6bToggled = 0, case6bLeft = 0;  ///< cubes toggled to remove 6b vertices, and those left
  std::optional<int> genus;
};

struct PolycubeResult {
  Polycube polycube;
  PolycubeFrame frame;  ///< lattice to world: the cell complex's grid
  int cubesPerSide = 0;
  std::optional<int> meshGenus;  ///< cappedGenus of the mesh
  std::vector<PolycubeTrial> trials;
  double seconds = 0;
};

namespace detail {

/// Steps 1-4 at one lattice size.
inline Polycube manifoldPolycubeAt(const TriangleMesh& mesh, std::span<const Vec3d> positions, int n,
                                   bool removeCase6b, PolycubeFrame& frame, PolycubeTrial& trial) {
  const cells::CellComplex complex =
      cells::CellComplex::build(mesh, {.gridSize = n, .offProjectionPlanes = false});
  frame = {complex.boundsWS().min, complex.cellSizeWS()};
  std::vector<Vec3i> cubes;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (complex.color({i, j, k}) == cells::CellColor::Black) cubes.push_back({i, j, k});
  const auto grey = complex.greyCells();
  std::vector<std::uint8_t> inside(grey.size(), 0);
  // One winding number per grey cell; each one is parallel over the triangles.
  for (std::size_t g = 0; g < grey.size(); ++g) {
    const Vec3d centre = complex.cellMinWS(grey[g].ijk) + Vec3d(0.5 * complex.cellSizeWS());
    inside[g] = std::abs(cells::windingNumber(positions, mesh.triangles, centre)) > 0.5;
  }
  for (std::size_t g = 0; g < grey.size(); ++g)
    if (inside[g]) cubes.push_back(grey[g].ijk);
  // Cells the surface passes through, or inside: where cubes are best added.
  auto onOrInside = [&](const Vec3i& c) {
    const bool inGrid = glm::all(glm::greaterThanEqual(c, Vec3i(0))) && glm::all(glm::lessThan(c, Vec3i(n)));
    return inGrid && complex.color(c) != cells::CellColor::White ? 1.0 : 0.0;
  };
  Polycube polycube = keepLargestAndFill(Polycube(std::move(cubes)));
  trial.addedForManifold = makeManifold(polycube, onOrInside);
  // Filling may have closed a cavity's mouth: fill again, then check once more.
  polycube = keepLargestAndFill(polycube);
  trial.addedForManifold += makeManifold(polycube);
  if (polycube.nonManifoldVertices().empty() && polycube.surfaceStats().genus()) {
    if (removeCase6b) trial.case6bToggled = removeVerticesOfCase(polycube, VertexCase::k6b, onOrInside);
    trial.case6bLeft = verticesOfCase(polycube, VertexCase::k6b).size();
  }
  return polycube;
}

}  // namespace detail

inline PolycubeResult polycubeOfMesh(const TriangleMesh& mesh, const PolycubeOptions& options = {}) {
  const auto start = std::chrono::steady_clock::now();
  if (mesh.triangles.empty()) throw Error(ErrorKind::InvalidArgument, "polycube: the mesh has no triangles");
  PolycubeResult result;
  result.meshGenus = cappedGenus(analyzeTopology(mesh));
  std::vector<Vec3d> positions(mesh.positions.begin(), mesh.positions.end());
  const std::vector<int> sizes =
      options.cubesPerSide > 0 ? std::vector<int>{options.cubesPerSide} : options.autoSizes;
  for (int n : sizes)
    if (n < 2 || n > 256)
      throw Error(ErrorKind::InvalidArgument, "polycube: cubes per side " + std::to_string(n) + " is out of range 2..256");
  for (int n : sizes) {
    PolycubeFrame frame;
    PolycubeTrial trial;
    trial.cubesPerSide = n;
    Polycube polycube = detail::manifoldPolycubeAt(mesh, positions, n, options.removeCase6b, frame, trial);
    const std::optional<int> genus = polycube.surfaceStats().genus();
    trial.cubes = polycube.size();
    trial.genus = genus;
    result.trials.push_back(trial);
    if (genus && (!options.matchGenus || !result.meshGenus || genus == result.meshGenus)) {
      result.polycube = std::move(polycube);
      result.frame = frame;
      result.cubesPerSide = n;
      result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return result;
    }
  }
  std::string tried;
  for (const PolycubeTrial& t : result.trials)
    tried += (tried.empty() ? "" : ", ") + std::string("N = ") + std::to_string(t.cubesPerSide) + ": " +
             (t.genus ? "genus " + std::to_string(*t.genus) : std::string("not a closed manifold"));
  throw Error(ErrorKind::InvalidArgument,
              "polycube: no lattice size gives a polycube of the mesh's genus " +
                  (result.meshGenus ? std::to_string(*result.meshGenus) : std::string("(unknown)")) + " (" + tried + ")");
}

}  // namespace cellrelief::polycube
