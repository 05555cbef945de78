// SPDX-License-Identifier: MIT
/// @file command_cells.cpp
/// `cellrelief cells <mesh> [--grid N|auto]`: the cubic cell complex of a mesh: counts per colour
/// and per base case, the grid size and occlusion ratios, the time; optionally the grey cells as
/// coloured boxes (PLY) and a picture of them.
#include <chrono>
#include <cstdio>
#include <memory>

#include <cellrelief/cells/cell_complex.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/projection/choice.h>
#include <cellrelief/relief/grid_size.h>

#include "commands.h"
#include "preview.h"

namespace cellrelief::app {

namespace {

struct CellsOptions {
  std::string mesh;
  std::string grid = "auto";
  int maxGrid = 128;
  double threshold = 0.01;
  projection::CentreOfProjection centre = projection::CentreOfProjection::CellCentre;
  std::string dump;
  std::string preview;
};

/// One colour per base case, for dumps and pictures.
constexpr Color8 kCaseColours[10] = {
    {120, 120, 120, 255}, {66, 133, 244, 255}, {52, 168, 83, 255},  {251, 188, 5, 255},
    {234, 67, 53, 255},   {171, 71, 188, 255}, {0, 172, 193, 255},  {255, 112, 67, 255},
    {158, 157, 36, 255},  {93, 64, 55, 255}};

/// The grey cells as boxes shrunk to 90%, coloured by base case.
TriangleMesh greyCellBoxes(const cells::CellComplex& complex) {
  TriangleMesh m;
  const double h = complex.cellSizeWS();
  for (const cells::GreyCell& g : complex.greyCells()) {
    const Vec3d lo = complex.cellMinWS(g.ijk) + 0.05 * h;
    const auto base = std::uint32_t(m.positions.size());
    for (int k = 0; k < 8; ++k)
      m.positions.push_back(Vec3f(lo + 0.9 * h * Vec3d(k & 1, (k >> 1) & 1, (k >> 2) & 1)));
    const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
      m.triangles.push_back({base + q[0], base + q[1], base + q[2]});
      m.triangles.push_back({base + q[0], base + q[2], base + q[3]});
    }
    m.colors.insert(m.colors.end(), 8, kCaseColours[static_cast<int>(g.baseCase)]);
  }
  m.sourcePolygons = m.triangles.size();
  return m;
}

int runCells(const CellsOptions& o) {
  const TriangleMesh mesh = io::readMesh(o.mesh);
  std::printf("mesh          %s: %zu triangles\n", o.mesh.c_str(), mesh.triangleCount());
  relief::OcclusionOptions occlusion;
  occlusion.centre = o.centre;

  int n = parseGridSize(o.grid);
  if (n == 0) {
    relief::GridSizeOptions g;
    g.threshold = o.threshold;
    g.maxGridSize = o.maxGrid;
    g.occlusion = occlusion;
    const relief::GridSizeChoice choice = relief::chooseGridSize(mesh, g);
    std::printf("grid search   occlusion ratio per N (threshold %.3g, N_max %d):\n", o.threshold,
                o.maxGrid);
    for (const relief::GridSizeTrial& t : choice.trials) {
      std::printf("  N = %4d    occlusion %.5f   grey cells %8zu   %.3f s", t.gridSize, t.occlusionRatio,
                  t.greyCells, t.seconds);
      if (t.rimBandRatio > 0) std::printf("   rim band %.5f", t.rimBandRatio);
      std::printf("\n");
    }
    n = choice.gridSize;
    std::printf("chosen N      %d%s\n", n,
                choice.metThreshold ? "" : " (N_max, or the finest sampling, reached before the threshold)");
  }

  const cells::CellComplex complex = cells::CellComplex::build(mesh, {.gridSize = n});
  const cells::ComplexStats& s = complex.stats();
  const double total = double(n) * n * n;
  std::printf("grid          N = %d, cell size %g, cube (%g, %g, %g) - (%g, %g, %g)\n", n,
              complex.cellSizeWS(), complex.boundsWS().min.x, complex.boundsWS().min.y,
              complex.boundsWS().min.z, complex.boundsWS().max.x, complex.boundsWS().max.y,
              complex.boundsWS().max.z);
  std::printf("cells         white %zu (%.1f%%), black %zu (%.1f%%), grey %zu (%.1f%%)\n", s.white,
              100 * s.white / total, s.black, 100 * s.black / total, s.grey, 100 * s.grey / total);
  std::printf("grey          border (BG) %zu, interior (IG) %zu; %zu cell-triangle pairs\n",
              s.borderGrey, s.interiorGrey, s.cellTrianglePairs);
  std::printf("base cases    case  cells     projection\n");
  for (int c = 0; c < cells::kBaseCaseCount; ++c) {
    const auto type = projection::chooseProjection<float>(cells::kCanonicalConfiguration[c]).type;
    std::printf("              %-4s  %-8zu  %s\n", cells::kBaseCaseNames[c].data(), s.perCase[c],
                projection::toString(type));
  }
  const relief::OcclusionEstimate est =
      relief::estimateOcclusion(mesh, complex, occlusion, relief::MeshRayQuery(mesh));
  std::printf("occlusion     %.5f of the surface area (%zu samples)\n", est.ratio, est.samples);
  std::printf("storage       OpenVDB grid %s (%zu leaf nodes) vs %s for a dense byte per cell\n",
              formatBytes(double(complex.grid().memUsage())).c_str(),
              std::size_t(complex.grid().tree().leafCount()), formatBytes(total).c_str());
  std::printf("time          %.3f s to build the complex\n", s.seconds);

  if (!o.dump.empty() || !o.preview.empty()) {
    const TriangleMesh boxes = greyCellBoxes(complex);
    if (!o.dump.empty()) {
      io::writeMesh(boxes, o.dump);
      std::printf("wrote         %s (grey cells coloured by base case)\n", o.dump.c_str());
    }
    if (!o.preview.empty()) {
      writePreview(boxes, o.preview);
      std::printf("wrote         %s\n", o.preview.c_str());
    }
  }
  return 0;
}

}  // namespace

Command addCellsCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("cells", "Build the cubic cell complex of a mesh and report on it");
  auto o = std::make_shared<CellsOptions>();
  cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .off .stl)")->required();
  cmd->add_option("--grid", o->grid, "Cells per side N, or 'auto' (occlusion-driven doubling)")
      ->capture_default_str();
  cmd->add_option("--max-grid", o->maxGrid, "N_max for --grid auto")
      ->check(CLI::Range(1, cells::kMaxGridSize))
      ->capture_default_str();
  cmd->add_option("--threshold", o->threshold, "Occlusion ratio that stops --grid auto")
      ->capture_default_str();
  cmd->add_option("--centre", o->centre,
                  "Centre of projection for the occlusion ratio: cell (the paper's, and --grid "
                  "auto's in convert), centroid (of the cell's surface) or fewest-crossings (the "
                  "point from which the fewest projection lines cross the surface twice)")
      ->transform(CLI::CheckedTransformer(centreNames(), CLI::ignore_case))
      ->default_str("cell");
  cmd->add_option("--dump", o->dump, "Write the grey cells as boxes coloured by base case (PLY)");
  cmd->add_option("--preview", o->preview, "Write a picture of the grey cells (PNG)");
  return {cmd, [o]() { return runCells(*o); }};
}

}  // namespace cellrelief::app
