// SPDX-License-Identifier: GPL-3.0-or-later
/// @file bench_indirection.cpp
/// The indirection optimizers on real height maps, each against the paper's springs measured in the
/// same run (time ratio at the distortion reached), and CGAL's LSCM, DCP and ARAP
/// (Surface_mesh_parameterization) on the same height-field grid as reference points. The grid
/// optimizers map the square onto the square (the texture must tile the quad); the CGAL maps have a
/// free (LSCM, ARAP) or circular (DCP) border, so they are what an unconstrained state-of-the-art
/// flattening reaches, not competitors for the same problem. Distortion: L2 stretch per cell (the
/// surface through the grid vertices, the only one the CGAL maps have) and, for the grid
/// optimizers, per texel (measureDistortion with 0, what a texture sees). GPL because of CGAL.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <cellrelief/cgal/reference_parameterization.h>
#include <cellrelief/core/parallel.h>
#include <cellrelief/indirection/distortion.h>
#include <cellrelief/indirection/optimizer_table.h>

namespace cellrelief::bench::indirection_program {
namespace {

using namespace indirection;

/// The grid's vertices lifted onto the relief, two triangles per cell as in grid.h.
TriangleMesh heightFieldMesh(const ReliefMap& relief, int g) {
  TriangleMesh mesh;
  const Grid id(g);
  for (int j = 0; j <= g; ++j)
    for (int i = 0; i <= g; ++i) {
      const Vec2f p = id.vertex(i, j);
      mesh.positions.push_back({p.x, p.y, relief.heightAt(p)});
    }
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i)
      for (const auto& tri : kCellTriangles) {
        Vec3u t;
        for (int c = 0; c < 3; ++c) t[c] = std::uint32_t((j + tri[c][1]) * (g + 1) + i + tri[c][0]);
        mesh.triangles.push_back(t);
      }
  return mesh;
}

/// Sander's L2 stretch of the map parameter -> mesh, the parameter scaled to the mesh's area, and
/// the triangles whose parameter orientation differs from the majority's.
struct MeshStretch {
  double l2 = 0;
  std::size_t flipped = 0;
};

MeshStretch stretchOf(const TriangleMesh& mesh, const std::vector<Vec2d>& corners) {
  double sumParam = 0, sumSurface = 0, sumStretch = 0;
  std::size_t negative = 0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Vec3u& t = mesh.triangles[f];
    const Vec3d p0(mesh.positions[t[0]]), p1(mesh.positions[t[1]]), p2(mesh.positions[t[2]]);
    const Vec2d q0 = corners[3 * f], q1 = corners[3 * f + 1], q2 = corners[3 * f + 2];
    const double area2 = (q1.x - q0.x) * (q2.y - q0.y) - (q1.y - q0.y) * (q2.x - q0.x);
    negative += area2 < 0;
    const double a = std::abs(area2) / 2;
    sumSurface += glm::length(glm::cross(p1 - p0, p2 - p0)) / 2;
    if (!(a > 0)) continue;
    // Jacobian parameter -> surface: dP/ds, dP/dt from the two edges.
    const Vec3d e1 = p1 - p0, e2 = p2 - p0;
    const double s1 = q1.x - q0.x, t1 = q1.y - q0.y, s2 = q2.x - q0.x, t2 = q2.y - q0.y;
    const Vec3d ds = (e1 * t2 - e2 * t1) / area2, dt = (e2 * s1 - e1 * s2) / area2;
    sumStretch += a * (glm::dot(ds, ds) + glm::dot(dt, dt)) / 2;
    sumParam += a;
  }
  MeshStretch out;
  out.l2 = std::sqrt(sumStretch / sumSurface);
  out.flipped = std::min(negative, mesh.triangles.size() - negative);
  return out;
}

struct Row {
  std::string map, method;
  double seconds = 0, l2Cell = 0, l2Texel = NAN;
  std::size_t flipped = 0;
};

}  // namespace

int run(int argc, char** argv) {
  CLI::App app("Indirection optimizers against the paper's springs, with CGAL's LSCM, DCP and "
               "ARAP on the same grid as reference points");
  std::string data = CELLRELIEF_DATA_DIR, out = "out/bench";
  bool quick = false, withCgal = true;
  int g = 256, threads = 2;
  float heightScale = 0.1f;
  app.add_option("--data", data, "Test data folder (../shared/data)")->capture_default_str();
  app.add_option("--out", out, "Where the CSV goes")->capture_default_str();
  app.add_flag("--quick", quick, "Maps at 128^2, g = 32: a smoke run");
  app.add_option("--threads", threads, "Worker threads (0: all cores)")->capture_default_str();
  app.add_option("--grid", g, "Grid cells a side")->capture_default_str();
  app.add_option("--height-scale", heightScale, "Height of H = 1 in tile widths")->capture_default_str();
  app.add_flag("!--no-cgal", withCgal, "Leave the CGAL reference points out");
  CLI11_PARSE(app, argc, argv);
  try {
    const ThreadLimit limit(std::size_t(std::max(0, threads)));
    if (quick) g = std::min(g, 32);
    const std::vector<std::string> maps = {"sponza/lion_bump.png", "sponza/spnza_bricks_a_bump.png",
                                           "pom_dxsdk/rocks_NM_height.tga"};
    std::vector<Row> rows;
    const std::vector<indirection::OptimizerEntry> table = indirection::builtinOptimizers();
    for (const std::string& name : maps) {
      const std::filesystem::path path = std::filesystem::path(data) / "heightmaps" / name;
      indirection::ReliefMap relief = indirection::loadReliefMap(path, {heightScale});
      if (quick) relief = indirection::downsample(relief, 128);
      const std::string stem = path.stem().string();
      std::printf("%s: %dx%d, g = %d\n", stem.c_str(), relief.width(), relief.height(), g);
      {
        const indirection::Grid id(g);
        rows.push_back({stem, "identity", 0.0, indirection::measureDistortion(id, relief).l2Stretch,
                        indirection::measureDistortion(id, relief, 0).l2Stretch, 0});
      }
      for (const auto& entry : table) {
        int iterations = 0;
        const auto t0 = std::chrono::steady_clock::now();
        const indirection::Grid grid = entry.run(relief, {.gridSize = g}, {}, iterations);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const indirection::Distortion cell = indirection::measureDistortion(grid, relief);
        rows.push_back({stem, entry.name, s, cell.l2Stretch,
                        indirection::measureDistortion(grid, relief, 0).l2Stretch, cell.flippedCells});
        std::printf("  %-14s %8.3f s  L2 per cell %.4f, per texel %.4f, flips %zu\n",
                    entry.name.c_str(), s, rows.back().l2Cell, rows.back().l2Texel, cell.flippedCells);
      }
      if (!withCgal) continue;
      const TriangleMesh mesh = heightFieldMesh(relief, g);
      for (cgal::DiskParameterizer which : {cgal::DiskParameterizer::Lscm,
                                            cgal::DiskParameterizer::DiscreteConformal,
                                            cgal::DiskParameterizer::Arap}) {
        cgal::DiskMap map;
        try {
          map = cgal::parameterizeDisk(mesh, which);
        } catch (const std::exception& e) {  // a reference point that fails is reported, not fatal
          std::printf("  %-14s failed: %s\n", cgal::toString(which), e.what());
          rows.push_back({stem, std::string(cgal::toString(which)) + " (failed)", 0.0, NAN, NAN, 0});
          continue;
        }
        const MeshStretch st = stretchOf(mesh, map.corners);
        rows.push_back({stem, cgal::toString(which), map.seconds, st.l2, NAN, st.flipped});
        std::printf("  %-14s %8.3f s  L2 per cell %.4f (own border), flips %zu\n",
                    cgal::toString(which), map.seconds, st.l2, st.flipped);
      }
    }
    std::printf("\n%-22s %-20s %10s %12s %12s %6s %18s\n", "heightmap", "method", "seconds",
                "L2 per cell", "L2 per texel", "flips", "vs springs (time)");
    std::filesystem::create_directories(out);
    std::ofstream csv(std::filesystem::path(out) / "bench_indirection.csv");
    csv << "heightmap,method,seconds,l2_per_cell,l2_per_texel,flipped\n";
    for (const Row& r : rows) {
      double springs = NAN;
      for (const Row& s : rows)
        if (s.map == r.map && s.method == "springs") springs = s.seconds;
      char ratio[32] = "";
      if (r.seconds > 0 && r.method != "springs")
        std::snprintf(ratio, sizeof ratio, "%.1fx faster", springs / r.seconds);
      char texel[32] = "-";  // the CGAL maps have no grid to subdivide
      if (!std::isnan(r.l2Texel)) std::snprintf(texel, sizeof texel, "%.4f", r.l2Texel);
      std::printf("%-22s %-20s %10.3f %12.4f %12s %6zu %18s\n", r.map.c_str(), r.method.c_str(),
                  r.seconds, r.l2Cell, texel, r.flipped, ratio);
      csv << r.map << "," << r.method << "," << r.seconds << "," << r.l2Cell << "," << r.l2Texel
          << "," << r.flipped << "\n";
    }
    std::printf("(times: the whole solve, %d threads; CGAL maps have their own border, so their L2 "
                "is a reference point, not the same problem)\n", threads);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_indirection: %s\n", e.what());
    return 1;
  }
}

}  // namespace cellrelief::bench::indirection_program
