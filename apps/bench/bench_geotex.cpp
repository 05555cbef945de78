// SPDX-License-Identifier: MIT
/// @file bench_geotex.cpp
/// Geometry textures against their peers, measured in one run:
///  1. VSA: ours (geotex::partitionVsa) against CGAL's Surface_mesh_approximation at equal proxy
///     counts and iterations, both partitions scored by the same L2,1 error.
///  2. The representation: conversion time, bytes, and accuracy against Embree on the mesh (depth
///     error and hit/miss disagreement over primary rays), beside the cell complex (relief) at
///     about equal bytes; rays per second of the CPU tracer against Embree's rtcIntersect1 on the
///     same rays and threads.
/// Writes geotex_vsa.csv and geotex_representation.csv.
#include <cstdio>
#include <memory>

#include <cellrelief/cgal/reference_vsa.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/embree/embree_scene.h>
#include <cellrelief/geotex/convert.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/metrics/ray_comparison.h>
#include <cellrelief/relief/convert.h>

#include "bench_common.h"

namespace cellrelief::bench {
namespace {

struct MeshEntry {
  const char* name;
  const char* path;
};

constexpr MeshEntry kMeshes[] = {{"bunny", "meshes/medium/stanford-bunny__common-3d-test-models.obj"},
                                 {"armadillo", "meshes/medium/armadillo__libigl-tutorial-data.obj"},
                                 {"fertility_9k", "meshes/small/fertility_9k__libigl-tutorial-data.off"},
                                 {"igea", "meshes/large/igea__common-3d-test-models.ply"}};

void compareVsa(const std::string& name, const TriangleMesh& mesh, int proxies, int iterations, CsvWriter& csv) {
  geotex::VsaOptions o;
  o.proxies = proxies;
  o.maxIterations = iterations;
  geotex::VsaPartition ours;
  const double oursSeconds = medianSeconds(1, [&] { ours = geotex::partitionVsa(mesh, o); });
  const cgal::CgalVsa theirs = cgal::cgalVsa(mesh, proxies, iterations);
  const double oursError = geotex::partitionError(mesh, ours.regionOfFace, geotex::VsaMetric::L21);
  const double theirError = geotex::partitionError(mesh, theirs.regionOfFace, geotex::VsaMetric::L21);
  const double area = surfaceArea(mesh);
  std::printf("%-13s %8zu %5d | %8.3f %10.3e | %8.3f %10.3e | %6.2fx %6.3f\n", name.c_str(), mesh.triangleCount(),
              proxies, oursSeconds, oursError / area, theirs.seconds, theirError / area, theirs.seconds / oursSeconds,
              oursError / theirError);
  csv.row(name, mesh.triangleCount(), proxies, iterations, oursSeconds, oursError / area, theirs.proxies, theirs.seconds,
          theirError / area);
}

struct Accuracy {
  metrics::RayComparison rays;
  double seconds = 0;  ///< the CPU backend's depth-and-mask frame
};

/// The CPU backend's frame of `scene` against Embree's reference frame of the mesh.
Accuracy measure(const render::Scene& scene, const render::Camera& camera, const render::Frame& reference, int size,
                 int repeats) {
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  render::RenderOptions options;
  options.width = options.height = size;
  options.channels = render::kDepth | render::kMask | render::kNormal;
  render::Frame frame;
  Accuracy a;
  a.seconds = medianSeconds(repeats, [&] { frame = cpu.renderFrame(camera, options); });
  a.rays = metrics::compareRays(reference.depth, reference.mask, reference.normal, frame.depth, frame.mask, frame.normal);
  return a;
}

void compareRepresentations(const std::string& name, const TriangleMesh& mesh, int size, int repeats, CsvWriter& csv) {
  const embree::EmbreeScene embree(mesh);
  const Aabbf b = mesh.surfaceBounds();
  const double diagonal = b.diagonal();
  const render::Camera camera = render::Camera::framing(Vec3d(b.center()), 0.5 * diagonal);
  render::Frame reference;
  const double embreeSeconds = medianSeconds(repeats, [&] { reference = embree.renderReference(camera, size, size); });

  // The cell complex at its defaults, then geometry textures at the map size of about its bytes.
  std::shared_ptr<relief::ReliefModel> cells;
  const double cellsConvert = medianSeconds(1, [&] { cells = std::make_shared<relief::ReliefModel>(relief::convert(mesh)); });
  const Accuracy cellsAccuracy = measure(render::Scene::of(cells), camera, reference, size, repeats);
  std::shared_ptr<geotex::GeoTexModel> charts;
  double chartsConvert = 0;
  for (const int texels : {32, 64, 128, 256, 512}) {
    geotex::GeoTexOptions o;
    o.vsa.proxies = 200;
    o.maxTexels = texels;
    auto candidate = std::make_shared<geotex::GeoTexModel>();
    const double seconds = medianSeconds(1, [&] { *candidate = geotex::convertMesh(mesh, o).model; });
    const bool closer = !charts || std::abs(std::log(double(candidate->byteSize()) / double(cells->byteSize()))) <
                                       std::abs(std::log(double(charts->byteSize()) / double(cells->byteSize())));
    if (closer) {
      charts = candidate;
      chartsConvert = seconds;
    }
  }
  render::Scene chartScene;
  chartScene.geotexModels.push_back(charts);
  const Accuracy chartsAccuracy = measure(chartScene, camera, reference, size, repeats);

  const double rays = double(size) * size;
  auto row = [&](const char* what, double convertSeconds, std::size_t bytes, const Accuracy& a) {
    const double mrays = rays / a.seconds * 1e-6, embreeMrays = rays / embreeSeconds * 1e-6;
    std::printf("%-13s %-14s %7.2f s %9.2f MiB | depth median %.4f%% p99 %.4f%% | %6.0f /M disagree | %6.2f Mrays/s "
                "(%.3fx Embree)\n",
                name.c_str(), what, convertSeconds, double(bytes) / (1 << 20), 100 * a.rays.depthError.median / diagonal,
                100 * a.rays.depthError.p99 / diagonal, 1e6 * a.rays.disagreementRate(), mrays, mrays / embreeMrays);
    csv.row(name, what, convertSeconds, bytes, a.rays.depthError.median / diagonal, a.rays.depthError.p99 / diagonal,
            a.rays.disagreementRate(), mrays, embreeMrays);
  };
  row("cell complex", cellsConvert, cells->byteSize(), cellsAccuracy);
  row("geotex", chartsConvert, charts->byteSize(), chartsAccuracy);
  std::printf("%-13s %-14s %9s %9.2f MiB | the reference                          | %6.2f Mrays/s\n", name.c_str(),
              "Embree", "", double(embree.byteSize()) / (1 << 20), rays / embreeSeconds * 1e-6);
}

}  // namespace
}  // namespace cellrelief::bench

int main(int argc, char** argv) {
  using namespace cellrelief;
  CLI::App app{"bench_geotex: geometry textures against CGAL's VSA, the cell complex and Embree"};
  bench::BenchOptions o;
  o.addTo(app);
  CLI11_PARSE(app, argc, argv);
  const ThreadLimit threads(std::size_t(o.threads));
  bench::CsvWriter vsaCsv(std::filesystem::path(o.out) / "geotex_vsa.csv",
                          "mesh,triangles,proxies,iterations,ours_seconds,ours_l21_per_area,cgal_proxies,cgal_seconds,"
                          "cgal_l21_per_area");
  bench::CsvWriter reprCsv(std::filesystem::path(o.out) / "geotex_representation.csv",
                           "mesh,representation,convert_seconds,bytes,depth_median_diag,depth_p99_diag,disagreement,"
                           "mrays_per_s,embree_mrays_per_s");
  std::printf("VSA, L2,1 error per unit area (both partitions scored alike), 20 iterations after seeding\n");
  std::printf("%-13s %8s %5s | %8s %10s | %8s %10s | %7s %6s\n", "mesh", "faces", "K", "ours s", "L21/area", "CGAL s",
              "L21/area", "speedup", "error");
  const int size = o.quick ? 128 : 512, repeats = o.quick ? 1 : 3;
  for (const bench::MeshEntry& m : bench::kMeshes) {
    if (o.quick && std::string(m.name) != "fertility_9k") continue;
    const TriangleMesh mesh = io::readMesh(std::filesystem::path(o.data) / m.path);
    for (const int k : o.quick ? std::vector<int>{50} : std::vector<int>{50, 200}) bench::compareVsa(m.name, mesh, k, 20, vsaCsv);
  }
  std::printf("\nRepresentations at about equal bytes (geotex: 200 charts, the map size nearest the cell complex's "
              "bytes); %d x %d primary rays, CPU backend against Embree\n",
              size, size);
  for (const bench::MeshEntry& m : bench::kMeshes) {
    if (o.quick && std::string(m.name) != "fertility_9k") continue;
    bench::compareRepresentations(m.name, io::readMesh(std::filesystem::path(o.data) / m.path), size, repeats, reprCsv);
  }
  std::printf("\nwrote %s and %s\n", vsaCsv.path().c_str(), reprCsv.path().c_str());
  return 0;
}
