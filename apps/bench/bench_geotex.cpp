// SPDX-License-Identifier: MIT
/// @file bench_geotex.cpp
/// Geometry textures against their peers, measured in one run:
///  1. VSA: ours (geotex::partitionVsa, seeded hierarchically and by farthest points) against
///     CGAL's Surface_mesh_approximation at equal proxy counts and iterations, all partitions scored
///     by the same L2,1 error; and ours run until CGAL's error: the time at equal error.
///  2. The representation: conversion time, bytes, surface error (two-sided RMS and Hausdorff of
///     the reconstructions against the mesh) and accuracy against Embree on the mesh (depth error
///     and hit/miss disagreement over primary rays), beside the cell complex (relief) at
///     about equal bytes; rays per second of the CPU tracer against Embree's rtcIntersect1 on the
///     same rays and threads.
///  3. The VSA columns of the paper's Tables 2 and 3 on the bunny, as we measure them: for K from 25
///     to 400 charts, the partition's error, folds, empty texels, bytes, accuracy and speed.
///  4. The paper's Fig. 7: frame time of the geometry textures ray cast by the OpenGL backend from
///     their rasterized boxes (and, beside it, from a compute pass over every pixel, and by the
///     Vulkan backend from the boxes) against the full mesh rasterized by OpenGL
///     (gl::MeshRasterizer), as the image grows, and the largest image at which ray casting is the
///     faster (the crossover). `--sections figure7` runs this section alone (for a GPU machine),
///     `--figure7-sizes` sets the sizes, `--figure7-loop` adds the Igea after a Loop step.
/// Writes geotex_vsa.csv, geotex_representation.csv, geotex_chart_counts.csv and geotex_fig7.csv
/// (plot: geotex_fig7.png).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

#include <cellrelief/cgal/reference_vsa.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/embree/embree_scene.h>
#include <cellrelief/geotex/convert.h>
#include <cellrelief/geotex/reconstruct.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/metrics/geometric_error.h>
#include <cellrelief/metrics/ray_comparison.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/reconstruct.h>
#ifdef CELLRELIEF_HAS_OPENGL
#include <cellrelief/gl/gl_backend.h>
#include <cellrelief/gl/mesh_rasterizer.h>
#endif
#ifdef CELLRELIEF_HAS_VULKAN
#include <cellrelief/vulkan/vulkan_backend.h>
#endif

#include "bench_common.h"
#include "bench_programs.h"
#include "../common/plot_script.h"

namespace cellrelief::bench::geotex_program {
namespace {

struct MeshEntry {
  const char* name;
  const char* path;
};

constexpr MeshEntry kMeshes[] = {{"bunny", "meshes/medium/stanford-bunny__common-3d-test-models.obj"},
                                 {"armadillo", "meshes/medium/armadillo__libigl-tutorial-data.obj"},
                                 {"fertility_9k", "meshes/small/fertility_9k__libigl-tutorial-data.off"},
                                 {"igea", "meshes/large/igea__common-3d-test-models.ply"}};

/// Ours with each seeding (hierarchical, as CGAL's; farthest-point, cheaper) against CGAL's: at
/// equal iterations, and run until CGAL's error is reached (at most `kIterationsToTarget`
/// iterations, with region teleports where they settle): the time at equal error, the goal's
/// measure.
constexpr int kIterationsToTarget = 100;
void compareVsa(const std::string& name, const TriangleMesh& mesh, int proxies, int iterations, CsvWriter& csv) {
  const double area = surfaceArea(mesh);
  const cgal::CgalVsa theirs = cgal::cgalVsa(mesh, proxies, iterations);
  const double theirError = geotex::partitionError(mesh, theirs.regionOfFace, geotex::VsaMetric::L21) / area;
  struct Run {
    double seconds = 0, l21 = 0;
    bool reached = false;
  };
  const auto ours = [&](geotex::VsaSeeding seeding, bool toTheirError) {
    geotex::VsaOptions o;
    o.proxies = proxies;
    o.maxIterations = toTheirError ? kIterationsToTarget : iterations;
    o.seeding = seeding;
    if (toTheirError) {
      o.tolerance = 0;
      o.targetError = theirError * area;
      o.teleports = proxies;  // where the iterations settle, up to one per proxy
    }
    geotex::VsaPartition partition;
    Run r;
    r.seconds = medianSeconds(1, [&] { partition = geotex::partitionVsa(mesh, o); });
    r.l21 = geotex::partitionError(mesh, partition.regionOfFace, geotex::VsaMetric::L21) / area;
    r.reached = r.l21 <= theirError;
    return r;
  };
  const Run hierarchical = ours(geotex::VsaSeeding::Hierarchical, false);
  const Run farthest = ours(geotex::VsaSeeding::FarthestPoint, false);
  const Run hierarchicalToTheirs = ours(geotex::VsaSeeding::Hierarchical, true);
  const Run farthestToTheirs = ours(geotex::VsaSeeding::FarthestPoint, true);
  const auto toTheirs = [&](const Run& r) {
    char text[48];
    if (r.reached)
      std::snprintf(text, sizeof text, "%7.3f s %5.2fx", r.seconds, theirs.seconds / r.seconds);
    else
      std::snprintf(text, sizeof text, "not reached (%.3f)", r.l21 / theirError);
    return std::string(text);
  };
  std::printf("%-13s %8zu %5d | %7.3f %9.3e %5.2fx %6.3f | %7.3f %9.3e %5.2fx %6.3f | %7.3f %9.3e | %-19s %-19s\n",
              name.c_str(), mesh.triangleCount(), proxies, hierarchical.seconds, hierarchical.l21,
              theirs.seconds / hierarchical.seconds, hierarchical.l21 / theirError, farthest.seconds, farthest.l21,
              theirs.seconds / farthest.seconds, farthest.l21 / theirError, theirs.seconds, theirError,
              toTheirs(hierarchicalToTheirs).c_str(), toTheirs(farthestToTheirs).c_str());
  csv.row(name, mesh.triangleCount(), proxies, iterations, hierarchical.seconds, hierarchical.l21, farthest.seconds,
          farthest.l21, theirs.proxies, theirs.seconds, theirError, hierarchicalToTheirs.seconds, hierarchicalToTheirs.l21,
          farthestToTheirs.seconds, farthestToTheirs.l21);
}

struct Accuracy {
  metrics::RayComparison rays;
  double seconds = 0;          ///< the CPU backend's depth-and-mask frame
  double stepsPerHitRay = 0;   ///< the traversal's work (samples, skip steps) per ray that hits, on average
};

/// The CPU backend's frame of `scene` against Embree's reference frame of the mesh.
/// `skip`: the tracers' skipping (geometry textures' pyramids), or the paper's search alone.
Accuracy measure(const render::Scene& scene, const render::Camera& camera, const render::Frame& reference, int size,
                 int repeats, bool skip = true) {
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  render::RenderOptions options;
  options.trace.skipEmptySpace = skip;
  options.width = options.height = size;
  options.channels = render::kDepth | render::kMask | render::kNormal | render::kSteps;
  render::Frame frame;
  Accuracy a;
  a.seconds = medianSeconds(repeats, [&] { frame = cpu.renderFrame(camera, options); });
  a.rays = metrics::compareRays(reference.depth, reference.mask, reference.normal, frame.depth, frame.mask, frame.normal);
  double steps = 0, hits = 0;
  for (int y = 0; y < frame.mask.height(); ++y)
    for (int x = 0; x < frame.mask.width(); ++x)
      if (frame.mask.at(x, y, 0) != 0) {
        steps += frame.steps.at(x, y, 0);
        ++hits;
      }
  a.stepsPerHitRay = hits > 0 ? steps / hits : 0;
  return a;
}

/// The camera both sections look through: the mesh's bounding sphere from the default direction.
render::Camera cameraFor(const TriangleMesh& mesh) {
  const Aabbf b = mesh.surfaceBounds();
  return render::Camera::framing(Vec3d(b.center()), 0.5 * double(b.diagonal()));
}

/// Returns the geometry textures it measured (for Fig. 7).
std::shared_ptr<const geotex::GeoTexModel> compareRepresentations(const std::string& name, const TriangleMesh& mesh,
                                                                  int size, int repeats, CsvWriter& csv) {
  const embree::EmbreeScene embree(mesh);
  const double diagonal = mesh.surfaceBounds().diagonal();
  const render::Camera camera = cameraFor(mesh);
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
  const Accuracy unskippedAccuracy = measure(chartScene, camera, reference, size, repeats, false);

  // Surface error, two-sided against the mesh: the cell complex's default reconstruction, and the
  // charts' union (geotex::reconstruct: texel centres at their heights).
  const metrics::DistanceField field(mesh);
  const metrics::SurfaceError cellsSurface = metrics::surfaceError(mesh, field, relief::reconstruct(*cells, {}));
  const metrics::SurfaceError chartsSurface = metrics::surfaceError(mesh, field, geotex::reconstruct(*charts));

  const double rays = double(size) * size;
  auto row = [&](const char* what, double convertSeconds, std::size_t bytes, const metrics::SurfaceError& surface,
                 const Accuracy& a) {
    const double mrays = rays / a.seconds * 1e-6, embreeMrays = rays / embreeSeconds * 1e-6;
    std::printf("%-13s %-14s %7.2f s %9.2f MiB | RMS %.4f%% Hausdorff %.3f%% | depth median %.4f%% p99 %.4f%% | "
                "%6.0f /M disagree | %5.1f steps/hit | %6.2f Mrays/s (%.3fx Embree)\n",
                name.c_str(), what, convertSeconds, double(bytes) / (1 << 20), 100 * surface.rms() / diagonal,
                100 * surface.hausdorff() / diagonal, 100 * a.rays.depthError.median / diagonal,
                100 * a.rays.depthError.p99 / diagonal, 1e6 * a.rays.disagreementRate(), a.stepsPerHitRay, mrays,
                mrays / embreeMrays);
    csv.row(name, what, convertSeconds, bytes, surface.rms() / diagonal, surface.hausdorff() / diagonal,
            a.rays.depthError.median / diagonal, a.rays.depthError.p99 / diagonal, a.rays.disagreementRate(),
            a.stepsPerHitRay, mrays, embreeMrays);
  };
  row("cell complex", cellsConvert, cells->byteSize(), cellsSurface, cellsAccuracy);
  row("geotex", chartsConvert, charts->byteSize(), chartsSurface, chartsAccuracy);
  row("geotex no skip", chartsConvert, charts->byteSize(), chartsSurface, unskippedAccuracy);
  std::printf("%-13s %-14s %9s %9.2f MiB | the reference                          | %6.2f Mrays/s\n", name.c_str(),
              "Embree", "", double(embree.byteSize()) / (1 << 20), rays / embreeSeconds * 1e-6);
  return charts;
}

/// Geometry textures at 200 charts and the default maps (up to 128 texels), with the conversion's
/// time: Fig. 7's charts where the representation section (which picks the map size by the cell
/// complex's bytes) does not run.
std::shared_ptr<const geotex::GeoTexModel> defaultCharts(const std::string& name, const TriangleMesh& mesh) {
  geotex::GeoTexOptions o;
  o.vsa.proxies = 200;
  auto charts = std::make_shared<geotex::GeoTexModel>();
  const double seconds = medianSeconds(1, [&] { *charts = geotex::convertMesh(mesh, o).model; });
  std::printf("%-13s %9zu triangles -> %zu charts, %.2f MiB, in %.2f s\n", name.c_str(), mesh.triangleCount(),
              charts->charts.size(), double(charts->byteSize()) / (1 << 20), seconds);
  return charts;
}

/// The VSA columns of the paper's Tables 2 and 3 on one mesh, as we measure them: the mesh as
/// geometry textures of K charts (maps up to 128 texels, the default) for each K, with the
/// partition's L2,1 error, the charts' folds (faces inverted along the box's z) and empty texels,
/// the bytes, the surface error of the charts against the mesh, and the accuracy and speed of the
/// CPU tracer against Embree on primary rays.
void chartCountTable(const std::string& name, const TriangleMesh& mesh, const std::vector<int>& counts, int size,
                     int repeats, CsvWriter& csv) {
  const embree::EmbreeScene embree(mesh);
  const double diagonal = mesh.surfaceBounds().diagonal(), area = surfaceArea(mesh);
  const render::Camera camera = cameraFor(mesh);
  const render::Frame reference = embree.renderReference(camera, size, size);
  const metrics::DistanceField field(mesh);
  for (const int k : counts) {
    geotex::GeoTexOptions o;
    o.vsa.proxies = k;
    geotex::GeoTexConversion conversion;
    const double seconds = medianSeconds(1, [&] { conversion = geotex::convertMesh(mesh, o); });
    const double l21 = geotex::partitionError(mesh, conversion.partition.regionOfFace, geotex::VsaMetric::L21) / area;
    std::size_t foldedCharts = 0;
    for (const geotex::ChartReport& c : conversion.charts) foldedCharts += c.foldedFaces > 0;
    const auto model = std::make_shared<geotex::GeoTexModel>(std::move(conversion.model));
    const metrics::SurfaceError surface = metrics::surfaceError(mesh, field, geotex::reconstruct(*model));
    const double emptyShare = double(conversion.emptyTexels()) / double(std::max<std::uint64_t>(1, model->texelCount()));
    render::Scene scene;
    scene.geotexModels.push_back(model);
    const Accuracy a = measure(scene, camera, reference, size, repeats);
    const double mrays = double(size) * size / a.seconds * 1e-6;
    std::printf("%-13s %5d %6zu | %7.2f s %10.3e | %6zu %7zu %6.1f%% | %8.2f MiB | %.4f%% %.3f%% | %.4f%% %.4f%% %6.0f /M "
                "| %6.2f Mrays/s\n",
                name.c_str(), k, model->charts.size(), seconds, l21, foldedCharts, conversion.foldedFaces(),
                100 * emptyShare, double(model->byteSize()) / (1 << 20), 100 * surface.rms() / diagonal,
                100 * surface.hausdorff() / diagonal, 100 * a.rays.depthError.median / diagonal,
                100 * a.rays.depthError.p99 / diagonal, 1e6 * a.rays.disagreementRate(), mrays);
    csv.row(name, mesh.triangleCount(), k, model->charts.size(), seconds, l21, foldedCharts, conversion.foldedFaces(),
            emptyShare, model->byteSize(), surface.rms() / diagonal, surface.hausdorff() / diagonal,
            a.rays.depthError.median / diagonal, a.rays.depthError.p99 / diagonal, a.rays.disagreementRate(), mrays);
  }
}

/// Where ray casting stops being faster than rasterizing as the image grows.
struct Crossover {
  std::optional<std::pair<int, int>> largestFaster;  ///< the last size of the first faster run
  bool slowerOnce = false;
  void add(int width, int height, bool castIsFaster) {
    if (castIsFaster && !slowerOnce) largestFaster = {width, height};
    slowerOnce |= !castIsFaster;
  }
  void print(const std::string& mesh, const char* how, const char* clock) const {
    if (!largestFaster)
      std::printf("%-13s ray casting the charts %s is slower than rasterizing the mesh at every size (%s)\n",
                  mesh.c_str(), how, clock);
    else if (!slowerOnce)
      std::printf("%-13s ray casting the charts %s is faster at every size, up to %d x %d (%s)\n", mesh.c_str(), how,
                  largestFaster->first, largestFaster->second, clock);
    else
      std::printf("%-13s crossover: ray casting the charts %s is faster up to %d x %d (%s)\n", mesh.c_str(), how,
                  largestFaster->first, largestFaster->second, clock);
  }
};

/// Fig. 7 on one mesh: for each image size, the median over `repeats` frames (after one that
/// compiles and uploads) of the OpenGL backend ray casting the charts (colour, no shadows), from
/// their rasterized boxes (the paper's way) and, for comparison, from a compute pass over every
/// pixel; of the Vulkan backend casting from the boxes (the same GLSL, another driver path); and of
/// OpenGL rasterizing the mesh: each frame drawn and its colour read back, by the wall clock, and by
/// the device's timer where the driver has one (llvmpipe's reads 0 for the ray caster and only part
/// of a frame for the rasterizer). The crossover is by the device time where all are timed, else by
/// the wall clock.
void figure7(const std::string& name, const TriangleMesh& mesh, std::shared_ptr<const geotex::GeoTexModel> charts,
             const std::vector<std::pair<int, int>>& sizes, int repeats, CsvWriter& csv) {
#ifdef CELLRELIEF_HAS_OPENGL
  const render::Camera camera = cameraFor(mesh);
  std::unique_ptr<gl::GlBackend> rayCaster;
  std::unique_ptr<gl::MeshRasterizer> rasterizer;
  try {
    rayCaster = std::make_unique<gl::GlBackend>();
    rasterizer = std::make_unique<gl::MeshRasterizer>(mesh);
  } catch (const Error& e) {
    std::printf("%-13s Fig. 7 not measured: %s\n", name.c_str(), e.what());
    return;
  }
  // Vulkan beside it where there is one; the figure stands without it.
  std::unique_ptr<render::Backend> vulkanCaster;
  gpu::TraversalControls* vulkanControls = nullptr;
  static bool devicesSaid = false;
  const bool sayDevices = !std::exchange(devicesSaid, true);
  if (sayDevices) std::printf("%s\n", rayCaster->description().c_str());
#ifdef CELLRELIEF_HAS_VULKAN
  try {
    auto vulkan = std::make_unique<vulkan::VulkanBackend>();
    vulkan->setRayEntry(gpu::RayEntry::Rasterized);
    vulkanControls = vulkan.get();
    vulkanCaster = std::move(vulkan);
    if (sayDevices) std::printf("%s\n", vulkanCaster->description().c_str());
  } catch (const Error& e) {
    if (sayDevices) std::printf("Vulkan not measured: %s\n", e.what());
  }
#else
  if (sayDevices) std::printf("Vulkan not measured: this build has no Vulkan backend\n");
#endif
  if (sayDevices)
    std::printf("%-13s %9s %13s | %12s %12s | %12s %7s | %12s %12s | %12s %12s | %s\n", "mesh", "triangles", "image",
                "GL cast dev", "GL cast wall", "GL compute", "/cast", "Vk cast dev", "Vk cast wall", "raster dev",
                "raster wall", "raster / GL cast, / Vk cast");
  render::Scene scene;
  scene.geotexModels.push_back(std::move(charts));
  rayCaster->upload(scene);
  if (vulkanCaster) vulkanCaster->upload(scene);
  const auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  // The crossover of the paper's way (rays from the rasterized boxes), of the faster OpenGL entry at
  // each size (the backend could pick per frame; llvmpipe's 64 x 64 tiles favour compute on tiny
  // frames), and of Vulkan from the boxes.
  Crossover paper, faster, vulkanPaper;
  bool byDevice = true;
  for (const std::pair<int, int>& size : sizes) {
    const int width = size.first, height = size.second;  // not a structured binding: clang before 16 cannot capture one
    render::RenderOptions options;
    options.width = width;
    options.height = height;
    options.channels = render::kColor;
    options.shadows = false;
    for (const gpu::RayEntry entry : {gpu::RayEntry::Rasterized, gpu::RayEntry::Compute}) {
      rayCaster->setRayEntry(entry);
      rayCaster->renderFrame(camera, options);  // compiles the variant
    }
    if (vulkanCaster) vulkanCaster->renderFrame(camera, options);
    rasterizer->render(camera, width, height);
    std::vector<double> castDevice, castWall, computeDevice, computeWall, vulkanDevice, vulkanWall, rasterDevice, rasterWall;
    for (int r = 0; r < repeats; ++r) {
      rayCaster->setRayEntry(gpu::RayEntry::Rasterized);
      castWall.push_back(medianSeconds(1, [&] { rayCaster->renderFrame(camera, options); }));
      castDevice.push_back(rayCaster->deviceSeconds());
      if (rayCaster->lastRayEntry() != gpu::RayEntry::Rasterized) {
        std::printf("%-13s Fig. 7 not measured: the camera is inside the charts' bounds (compute entry)\n", name.c_str());
        return;
      }
      rayCaster->setRayEntry(gpu::RayEntry::Compute);
      computeWall.push_back(medianSeconds(1, [&] { rayCaster->renderFrame(camera, options); }));
      computeDevice.push_back(rayCaster->deviceSeconds());
      if (vulkanCaster) {
        vulkanWall.push_back(medianSeconds(1, [&] { vulkanCaster->renderFrame(camera, options); }));
        vulkanDevice.push_back(vulkanControls->lastRayEntry() == gpu::RayEntry::Rasterized ? vulkanCaster->deviceSeconds() : 0);
      }
      rasterWall.push_back(medianSeconds(1, [&] { rasterizer->render(camera, width, height); }));
      rasterDevice.push_back(rasterizer->deviceSeconds());
    }
    const double castD = median(castDevice), computeD = median(computeDevice), rasterD = median(rasterDevice);
    const double castW = median(castWall), computeW = median(computeWall), rasterW = median(rasterWall);
    const double vulkanD = median(vulkanDevice), vulkanW = median(vulkanWall);
    byDevice &= castD > 0 && computeD > 0 && rasterD > 0 && (!vulkanCaster || vulkanD > 0);
    const double cast = byDevice ? castD : castW, raster = byDevice ? rasterD : rasterW;
    const double compute = byDevice ? computeD : computeW, vulkanCast = byDevice ? vulkanD : vulkanW;
    std::printf("%-13s %9zu %5d x %-5d | %9.3f ms %9.2f ms | %9.3f ms %6.2fx | %9.3f ms %9.2f ms | %9.3f ms %9.2f ms "
                "| %6.2fx %6.2fx\n",
                name.c_str(), mesh.triangleCount(), width, height, 1e3 * castD, 1e3 * castW, 1e3 * compute,
                compute / cast, 1e3 * vulkanD, 1e3 * vulkanW, 1e3 * rasterD, 1e3 * rasterW, raster / cast,
                vulkanCaster ? raster / vulkanCast : 0.0);
    csv.row(name, mesh.triangleCount(), width, height, castD, castW, computeD, computeW, vulkanD, vulkanW, rasterD,
            rasterW);
    paper.add(width, height, cast < raster);
    faster.add(width, height, std::min(cast, compute) < raster);
    if (vulkanCaster) vulkanPaper.add(width, height, vulkanCast < raster);
  }
  const char* clock = byDevice ? "device time" : "wall clock";
  paper.print(name, "by OpenGL from the rasterized boxes", clock);
  faster.print(name, "by OpenGL's faster entry", clock);
  if (vulkanCaster) vulkanPaper.print(name, "by Vulkan from the rasterized boxes", clock);
#else
  (void)mesh, (void)charts, (void)sizes, (void)repeats, (void)csv;
  std::printf("%-13s Fig. 7 not measured: this build has no OpenGL backend\n", name.c_str());
#endif
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"bench_geotex: geometry textures against CGAL's VSA, the cell complex and Embree"};
  BenchOptions o;
  o.addTo(app);
  bool figure7Loop = false;
  std::string figure7Sizes;
  std::vector<std::string> sections{"vsa", "representations", "tables", "figure7"};
  app.add_option("--sections", sections,
                 "The sections to run: vsa, representations, tables, figure7 (alone: charts at 200 proxies and maps "
                 "up to 128 texels, no CGAL, Embree or cell complex: the run for a GPU machine)")
      ->delimiter(',')
      ->check(CLI::IsMember({"vsa", "representations", "tables", "figure7"}))
      ->capture_default_str();
  app.add_option("--figure7-sizes", figure7Sizes, "Fig. 7's image sizes, e.g. 320x240,1600x1200,4096x3072");
  app.add_flag("--figure7-loop", figure7Loop,
               "Fig. 7 also on the Igea after one Loop subdivision step (1.07M triangles, charts converted from it)");
  CLI11_PARSE(app, argc, argv);
  const auto section = [&](const char* name) { return std::find(sections.begin(), sections.end(), name) != sections.end(); };
  std::vector<std::pair<int, int>> sizes;
  if (const auto parsed = parseFrameSizes(figure7Sizes)) {
    sizes = *parsed;
  } else {
    std::fprintf(stderr, "bench_geotex: --figure7-sizes '%s': expected WxH[,WxH...] with sides from 1 to 16384\n",
                 figure7Sizes.c_str());
    return 1;
  }
  if (sizes.empty())
    // The paper's Fig. 7 sizes, 4:3 as its frames, and one smaller where the crossover may lie on a CPU device.
    sizes = o.quick ? std::vector<std::pair<int, int>>{{160, 120}, {320, 240}}
                    : std::vector<std::pair<int, int>>{{80, 60}, {160, 120}, {320, 240}, {640, 480}, {800, 600}, {1024, 768}, {1600, 1200}};
  const ThreadLimit threads(std::size_t(o.threads));
  const std::filesystem::path out(o.out);
  const int size = o.quick ? 128 : 512, repeats = o.quick ? 1 : 3;
  const auto wanted = [&](const MeshEntry& m) { return !o.quick || std::string(m.name) == "fertility_9k"; };
  std::vector<std::filesystem::path> written;

  if (section("vsa")) {
    CsvWriter vsaCsv(out / "geotex_vsa.csv",
                     "mesh,triangles,proxies,iterations,ours_seconds,ours_l21_per_area,ours_farthest_seconds,"
                     "ours_farthest_l21_per_area,cgal_proxies,cgal_seconds,cgal_l21_per_area,"
                     "ours_to_cgal_seconds,ours_to_cgal_l21_per_area,ours_farthest_to_cgal_seconds,"
                     "ours_farthest_to_cgal_l21_per_area");
    std::printf("VSA, L2,1 error per unit area (all partitions scored alike), at most 20 iterations after seeding; "
                "ours seeded hierarchically (as CGAL) and by farthest points, each with its speed-up over CGAL and its "
                "error over CGAL's; then ours run until CGAL's error (at most %d iterations, teleporting regions where "
                "they settle): time and speed-up at equal error, or the error ratio where not reached\n",
                kIterationsToTarget);
    std::printf("%-13s %8s %5s | %-31s | %-31s | %-17s | %-19s %-19s\n", "mesh", "faces", "K",
                "ours, hierarchical: s L21 x err", "ours, farthest-point: s L21 x err", "CGAL: s L21",
                "to CGAL's: hier.", "farthest");
    for (const MeshEntry& m : kMeshes) {
      if (!wanted(m)) continue;
      const TriangleMesh mesh = io::readMesh(std::filesystem::path(o.data) / m.path);
      for (const int k : o.quick ? std::vector<int>{50} : std::vector<int>{50, 200}) compareVsa(m.name, mesh, k, 20, vsaCsv);
    }
    written.push_back(vsaCsv.path());
  }

  struct Measured {
    std::string name;
    TriangleMesh mesh;
    std::shared_ptr<const geotex::GeoTexModel> charts;
  };
  std::vector<Measured> measured;
  if (section("representations") || section("tables") || section("figure7"))
    for (const MeshEntry& m : kMeshes)
      if (wanted(m)) measured.push_back(Measured{m.name, io::readMesh(std::filesystem::path(o.data) / m.path), {}});
  if (section("representations")) {
    CsvWriter reprCsv(out / "geotex_representation.csv",
                      "mesh,representation,convert_seconds,bytes,rms_diag,hausdorff_diag,depth_median_diag,"
                      "depth_p99_diag,disagreement,steps_per_hit_ray,mrays_per_s,embree_mrays_per_s");
    std::printf("\nRepresentations at about equal bytes (geotex: 200 charts, the map size nearest the cell complex's "
                "bytes); surface error of the reconstructions against the mesh (200,000 points a side, %% of the "
                "diagonal); %d x %d primary rays, CPU backend against Embree\n",
                size, size);
    for (Measured& m : measured) m.charts = compareRepresentations(m.name, m.mesh, size, repeats, reprCsv);
    written.push_back(reprCsv.path());
  }
  if (section("tables")) {
    CsvWriter chartsCsv(out / "geotex_chart_counts.csv",
                        "mesh,triangles,proxies,charts,convert_seconds,l21_per_area,folded_charts,folded_faces,"
                        "empty_texel_share,bytes,rms_diag,hausdorff_diag,depth_median_diag,depth_p99_diag,"
                        "disagreement,mrays_per_s");
    const char* tableMesh = o.quick ? "fertility_9k" : "bunny";
    std::printf("\nThe VSA columns of the paper's Tables 2 and 3, on the %s: K charts (maps up to 128 texels), "
                "%d x %d primary rays on the CPU backend against Embree\n", tableMesh, size, size);
    std::printf("%-13s %5s %6s | %9s %10s | %6s %7s %7s | %12s | %-17s | %-23s | %s\n", "mesh", "K", "charts",
                "convert", "L21/area", "folded", "faces", "empty", "bytes", "RMS, Hausdorff", "depth median, p99, miss",
                "CPU");
    for (const Measured& m : measured)
      if (m.name == tableMesh)
        chartCountTable(m.name, m.mesh, o.quick ? std::vector<int>{25, 50} : std::vector<int>{25, 50, 100, 200, 400},
                        size, repeats, chartsCsv);
    written.push_back(chartsCsv.path());
  }
  if (section("figure7")) {
    // Fig. 7's charts: those of the representation section (the map size by the cell complex's
    // bytes), else 200 charts at the default maps.
    if (!section("representations")) std::printf("\nFig. 7's charts: 200 proxies, maps up to 128 texels\n");
    for (Measured& m : measured)
      if (!m.charts) m.charts = defaultCharts(m.name, m.mesh);
    if (figure7Loop) {
      // The same surface with 4x the triangles: the rasterizer's cost grows, the charts' hardly.
      const auto read = std::find_if(measured.begin(), measured.end(), [](const Measured& m) { return m.name == "igea"; });
      const auto entry = std::find_if(std::begin(kMeshes), std::end(kMeshes),
                                      [](const MeshEntry& m) { return std::string(m.name) == "igea"; });
      TriangleMesh loop1 = read != measured.end() ? loopSubdivide(read->mesh)
                                                  : loopSubdivide(io::readMesh(std::filesystem::path(o.data) / entry->path));
      Measured& subdivided = measured.emplace_back(Measured{"igea_loop1", std::move(loop1), {}});
      subdivided.charts = defaultCharts(subdivided.name, subdivided.mesh);
    }
    CsvWriter figureCsv(out / "geotex_fig7.csv",
                        "mesh,triangles,width,height,raycast_device_s,raycast_wall_s,compute_device_s,"
                        "compute_wall_s,vulkan_raycast_device_s,vulkan_raycast_wall_s,raster_device_s,raster_wall_s");
    std::printf("\nFig. 7: frame time of the charts ray cast by OpenGL (colour, no shadows) from their rasterized boxes, "
                "against the same cast by a compute pass over every pixel, by Vulkan from the boxes, and the full mesh "
                "rasterized by OpenGL; median of %d frames, each read back; device time where the driver times it\n",
                repeats);
    for (const Measured& m : measured) figure7(m.name, m.mesh, m.charts, sizes, repeats, figureCsv);
    app::drawPlot("plot_geotex_fig7", figureCsv.path(), out / "geotex_fig7.png");
    written.push_back(figureCsv.path());
  }
  std::printf("\nwrote");
  for (const std::filesystem::path& p : written) std::printf(" %s", p.c_str());
  std::printf("\n");
  return 0;
}

}  // namespace cellrelief::bench::geotex_program
