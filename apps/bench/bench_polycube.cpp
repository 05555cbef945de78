// SPDX-License-Identifier: GPL-3.0-or-later
/// @file bench_polycube.cpp
/// Benchmark: the PolyCube-Maps paper's Table 1 with its Fig. 8 comparison and two baselines. Per
/// mesh: the automatic polycube, then the map onto it with extended MIPS (theta = 3), plain MIPS
/// and mean value coordinates, beside CGAL's LSCM and discrete conformal map (DCP) of the same
/// mesh cut into a disk. Columns: area and angle distortion (1 is best), stretch efficiency
/// (Praun & Hoppe, 1 is best), flipped triangles, seconds; the last column is the baseline's area
/// distortion over ours (extended MIPS). Prints the table, writes CSV.
///
///   bench_polycube [--data DIR] [--out out/bench] [--quick] [--threads N] [--mesh NAME ...]
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <cellrelief/cgal/reference_parameterization.h>
#include <cellrelief/core/parallel.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/from_mesh.h>
#include <cellrelief/polycube/parameterization.h>

#include "bench_common.h"
#include "bench_programs.h"

namespace cellrelief::bench::polycube_program {

namespace {

struct Row {
  std::string method;
  std::optional<polycube::Distortion> distortion;  ///< empty when the method failed
  double seconds = 0;
  std::string failure;
};

void printRow(const std::string& mesh, std::size_t triangles, std::size_t cubes, const Row& r, double oursArea,
              bench::CsvWriter& csv) {
  if (!r.distortion) {
    std::printf("%-12s %9zu %6zu %-22s failed: %s\n", mesh.c_str(), triangles, cubes, r.method.c_str(),
                r.failure.c_str());
    csv.row(mesh, triangles, cubes, r.method, "", "", "", "", r.seconds, "");
    return;
  }
  const polycube::Distortion& d = *r.distortion;
  const double ratio = oursArea > 0 ? d.area / oursArea : 0.0;
  std::printf("%-12s %9zu %6zu %-22s %9.4f %9.4f %9.4f %8zu %9.2f %9.2fx\n", mesh.c_str(), triangles, cubes,
              r.method.c_str(), d.area, d.angle, d.stretchEfficiency, d.flipped, r.seconds, ratio);
  csv.row(mesh, triangles, cubes, r.method, d.area, d.angle, d.stretchEfficiency, d.flipped, r.seconds, ratio);
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"PolyCube-Maps distortion (the paper's Table 1) beside CGAL's LSCM and DCP", "bench_polycube"};
  bench::BenchOptions options;
  options.addTo(app);
  std::vector<std::string> only;
  app.add_option("--mesh", only,
                 "Only these meshes (3holes, spot, laurana, bumpy-cube, bunny, fertility_9k, armadillo; default: all)");
  CLI11_PARSE(app, argc, argv);
  const ThreadLimit limit{std::size_t(options.threads)};
  const std::vector<std::pair<std::string, std::string>> meshes =
      options.quick ? std::vector<std::pair<std::string, std::string>>{{"3holes", "meshes/small/3holes__cinolib.obj"}}
                    : std::vector<std::pair<std::string, std::string>>{
                          {"3holes", "meshes/small/3holes__cinolib.obj"},
                          {"spot", "meshes/small/spot__common-3d-test-models.obj"},
                          {"laurana", "meshes/medium/laurana__cinolib.obj"},
                          {"bumpy-cube", "meshes/medium/bumpy-cube__libigl-tutorial-data.obj"},
                          {"bunny", "meshes/medium/stanford-bunny__common-3d-test-models.obj"},
                          {"fertility_9k", "meshes/small/fertility_9k__libigl-tutorial-data.off"},
                          {"armadillo", "meshes/medium/armadillo__libigl-tutorial-data.obj"}};
  bench::CsvWriter csv(std::filesystem::path(options.out) / "polycube.csv",
                       "mesh,triangles,cubes,method,area_distortion,angle_distortion,stretch_efficiency,flipped,"
                       "seconds,area_over_extended_mips");
  std::printf("\n%-12s %9s %6s %-22s %9s %9s %9s %8s %9s %10s\n", "mesh", "triangles", "cubes", "method", "area",
              "angle", "stretch", "flipped", "time [s]", "area/ours");
  for (const auto& [name, relative] : meshes) {
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
    TriangleMesh mesh;
    polycube::PolycubeResult cubes;
    try {
      mesh = io::readMesh(options.data + "/" + relative);
      cubes = polycube::polycubeOfMesh(mesh);
    } catch (const Error& e) {
      std::printf("%-12s polycube failed: %s\n", name.c_str(), e.what());
      continue;
    }
    const polycube::PolycubeSurface surface(cubes.polycube);
    std::vector<Row> rows;
    for (polycube::PolycubeEnergy energy :
         {polycube::PolycubeEnergy::ExtendedMips, polycube::PolycubeEnergy::Mips, polycube::PolycubeEnergy::MeanValue}) {
      polycube::ParameterizationOptions o;
      o.energy = energy;
      const polycube::PolycubeParameterization map = polycube::parameterize(mesh, surface, cubes.frame, o);
      rows.push_back({"polycube " + std::string(toString(energy)), map.final, map.seconds + cubes.seconds, ""});
    }
    for (cgal::DiskParameterizer which : {cgal::DiskParameterizer::Lscm, cgal::DiskParameterizer::DiscreteConformal}) {
      try {
        const cgal::DiskMap map = cgal::parameterizeDisk(mesh, which);
        rows.push_back({cgal::toString(which), polycube::measurePlanarDistortion(mesh, map.corners), map.seconds, ""});
      } catch (const Error& e) {
        rows.push_back({cgal::toString(which), std::nullopt, 0.0, e.what()});
      }
    }
    const double oursArea = rows.front().distortion->area;
    for (const Row& r : rows) printRow(name, mesh.triangleCount(), cubes.polycube.size(), r, oursArea, csv);
  }
  std::printf("\npolycube times include building the polycube; CGAL's include cutting the mesh into a disk.\n"
              "area/ours = the method's area distortion over the polycube map's with extended MIPS.\n"
              "wrote %s\n", csv.path().c_str());
  return 0;
}

}  // namespace cellrelief::bench::polycube_program
