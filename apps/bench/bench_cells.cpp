// SPDX-License-Identifier: MIT
/// @file bench_cells.cpp
/// Benchmark: classification of the cubic cell complex (grey/white/black, configurations, the
/// OpenVDB grid) against OpenVDB's meshToLevelSet at the same voxel size, in the same run, on the
/// same threads. Prints times and the ratio; writes CSV. Not a test: times are machine-dependent,
/// the ratio is what to read.
///
///   bench_cells [--data DIR] [--out out/bench] [--quick] [--threads N]
#include <cstdio>
#include <cstring>
#include <string>

#include <CLI/CLI.hpp>
#include <cellrelief/cells/cell_complex.h>
#include <cellrelief/core/parallel.h>
#include <cellrelief/io/mesh_io.h>

#include "bench_common.h"
#include "bench_programs.h"

namespace cellrelief::bench::cells_program {

int run(int argc, char** argv) {
  CLI::App app{"Cell complex classification versus OpenVDB meshToLevelSet", "bench_cells"};
  bench::BenchOptions options;
  options.addTo(app);
  CLI11_PARSE(app, argc, argv);
  const ThreadLimit limit{std::size_t(options.threads)};
  const std::string& data = options.data;
  const bool quick = options.quick;
  openvdb::initialize();

  struct Case {
    std::string name;
    TriangleMesh mesh;
    std::vector<int> grids;
  };
  std::vector<Case> cases;
  try {
    if (quick) {
      cases.push_back({"bumpy", io::readMesh(data + "/meshes/small/bumpy__libigl-tutorial-data.off"), {16}});
    } else {
      TriangleMesh igea = io::readMesh(data + "/meshes/large/igea__common-3d-test-models.ply");
      std::printf("subdividing Igea once (Loop, OpenMesh)...\n");
      TriangleMesh igea1M = bench::loopSubdivide(igea);
      cases.push_back({"igea", std::move(igea), {64, 128}});
      cases.push_back({"igea-loop1", std::move(igea1M), {64, 128, 256}});
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_cells: %s\n", e.what());
    return 1;
  }
  const int repeats = quick ? 1 : 3;
  bench::CsvWriter csv(std::filesystem::path(options.out) / "cells.csv",
                       "mesh,triangles,N,cells_s,grey,black,white,meshToLevelSet_s,active_voxels,ratio");
  std::printf("\n%-12s %10s %5s %10s %9s %9s %14s %12s %8s\n", "mesh", "triangles", "N",
              "cells [s]", "grey", "black", "meshToLS [s]", "LS voxels", "ratio");
  for (const Case& c : cases)
    for (int n : c.grids) {
      cells::CellComplex complex;
      const double ours = bench::medianSeconds(repeats, [&] {
        complex = cells::CellComplex::build(c.mesh, {.gridSize = n});
      });
      openvdb::FloatGrid::Ptr ls;
      const double peer = bench::medianSeconds(repeats, [&] {
        ls = bench::levelSet(c.mesh, complex.cellSizeWS());
      });
      const auto& s = complex.stats();
      std::printf("%-12s %10zu %5d %10.3f %9zu %9zu %14.3f %12llu %7.1fx\n", c.name.c_str(),
                  c.mesh.triangleCount(), n, ours, s.grey, s.black, peer,
                  static_cast<unsigned long long>(ls->activeVoxelCount()), peer / ours);
      csv.row(c.name, c.mesh.triangleCount(), n, ours, s.grey, s.black, s.white, peer,
              ls->activeVoxelCount(), peer / ours);
    }
  std::printf("\nratio = meshToLevelSet time / cell complex time (same voxel size, same threads)\n");
  std::printf("wrote %s\n", csv.path().c_str());
  return 0;
}

}  // namespace cellrelief::bench::cells_program
