// SPDX-License-Identifier: MIT
/// @file bench_backends.cpp
/// Benchmark: one scene, one camera, the same rays on every renderer that runs here. For each
/// mesh (Igea, armadillo, the 1M-triangle Igea; fertility with --quick) it converts at default
/// settings and renders primary rays (depth and mask) and shaded frames with shadow rays on the
/// CPU reference, on OpenGL and Vulkan (llvmpipe and lavapipe get LP_NUM_THREADS = the CPU
/// backend's threads; each also with its general shader and each entry, except with --quick),
/// and casts
/// the same primary and shadow rays with Embree on the original mesh. Prints Mrays/s, the ratio to
/// the CPU reference, the agreement of every channel with it, and the scene bytes; writes
/// backends.csv and the plot backends.png.
///
///   bench_backends [--data DIR] [--out out/bench] [--quick] [--threads 2] [--size 1024|WxH] [--device NAME]
///                  [--skip opengl,vulkan]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <atomic>
#include <map>
#include <memory>
#include <thread>
#include <string>

#include <CLI/CLI.hpp>
#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/parallel.h>
#include <cellrelief/embree/embree_scene.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/frame_comparison.h>

#include "../common/plot_script.h"
#include "bench_common.h"
#include "bench_programs.h"

namespace cellrelief::bench::backends_program {

namespace {

struct Measured {
  double firstSeconds = 0;  ///< upload and the first frame: tracers built, shader variant compiled (or read from a cache)
  double primarySeconds = 0, shadedSeconds = 0, deviceSeconds = 0;
  std::size_t shadowRays = 0, bytes = 0;
  render::Frame primary;
};

/// Primary rays, then shaded frames with one shadow ray per lit hit, on a backend.
Measured measureBackend(render::Backend& backend, const render::Scene& scene, const render::Camera& camera,
                        int width, int height, int repeats, int threads) {
  Measured m;
  render::RenderOptions options;
  options.width = width;
  options.height = height;
  options.threads = std::size_t(threads);
  options.channels = render::kDepth | render::kMask | render::kNormal | render::kCell | render::kSteps;
  options.shadows = false;
  m.firstSeconds = bench::medianSeconds(1, [&] {
    backend.upload(scene);
    backend.renderFrame(camera, options);  // warm-up: tracers, shader compilation
  });
  m.primarySeconds = bench::medianSeconds(repeats, [&] { m.primary = backend.renderFrame(camera, options); });
  m.deviceSeconds = backend.deviceSeconds();
  options.channels = render::kColor;
  options.shadows = true;
  backend.renderFrame(camera, options);
  m.shadedSeconds = bench::medianSeconds(repeats, [&] { backend.renderFrame(camera, options); });
  m.bytes = backend.sceneBytes();
  return m;
}

/// Embree on the original mesh: the same primary rays, and a shadow ray towards the light from
/// every hit that faces it.
Measured measureEmbree(const embree::EmbreeScene& embree, const render::Camera& camera, int width, int height,
                       int repeats,
                       const Vec3f& light, float offset) {
  Measured m;
  m.primarySeconds = bench::medianSeconds(repeats, [&] { m.primary = embree.renderReference(camera, width, height); });
  std::atomic<std::size_t> shadowRays{0};
  m.shadedSeconds = bench::medianSeconds(repeats, [&] {
    shadowRays = 0;
    parallelFor(0, std::size_t(width) * std::size_t(height), [&](std::size_t i) {
      const int x = int(i % std::size_t(width)), y = int(i / std::size_t(width));
      const Rayd primary = camera.primaryRay(x, y, width, height);
      const Rayf ray(Vec3f(primary.origin), Vec3f(primary.direction));
      const auto hit = embree.intersect(ray);
      if (!hit.valid()) return;
      Vec3f n = embree.normal(hit);
      if (glm::dot(n, ray.direction) > 0) n = -n;
      if (glm::dot(n, light) <= 0) return;
      ++shadowRays;
      (void)embree.occluded(Rayf(ray.at(hit.t) + offset * n, light));
    }, 256);
  });
  m.shadowRays = shadowRays;
  m.bytes = embree.byteSize();
  return m;
}

/// How busy 8 lanes running 8 consecutive pixels stay when each runs its ray's steps: the mean
/// over groups of (mean steps / most steps). llvmpipe runs a compute shader this way (256 bits),
/// so this bounds what it can get from the traversal's divergence.
double laneOccupancy(const render::Frame& f) {
  double sum = 0;
  std::size_t groups = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x0 = 0; x0 + 8 <= f.width; x0 += 8) {
      double total = 0, most = 0;
      for (int x = x0; x < x0 + 8; ++x) total += f.steps.at(x, y, 0), most = std::max(most, double(f.steps.at(x, y, 0)));
      if (most == 0) continue;
      sum += total / (8 * most);
      ++groups;
    }
  return groups ? sum / double(groups) : 1.0;
}

double meanSteps(const render::Frame& f) {
  double sum = 0;
  for (float v : f.steps.levelData()) sum += v;
  return sum / double(std::max<std::size_t>(1, f.steps.levelData().size()));
}

std::size_t countHits(const render::Frame& f) {
  std::size_t hits = 0;
  for (std::uint8_t v : f.mask.levelData()) hits += v;
  return hits;
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"One scene on every backend: Mrays/s, agreement with the CPU reference, scene bytes", "bench_backends"};
  bench::BenchOptions options;
  options.threads = 2;
  std::string sizeText = "1024";
  options.addTo(app);
  app.add_option("--size", sizeText, "Frame size: N (N x N pixels) or WxH, e.g. 1920x1080")->capture_default_str();
  backends::BackendSettings settings;
  app.add_option("--device", settings.vulkanDevice, backends::kDeviceHelp);
  std::vector<std::string> skipped;
  app.add_option("--skip", skipped,
                 "GPU backends not to measure, e.g. opengl (the NVIDIA driver compiles its relief shader for minutes)")
      ->delimiter(',');
  CLI11_PARSE(app, argc, argv);
  std::vector<render::BackendKind> skip;
  try {
    for (const std::string& name : skipped) {
      skip.push_back(render::parseBackendKind(name));
      if (skip.back() == render::BackendKind::Cpu || skip.back() == render::BackendKind::Auto)
        throw Error(ErrorKind::InvalidArgument, "--skip " + name + ": the CPU reference is always measured");
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_backends: %s\n", e.what());
    return 1;
  }
  // llvmpipe and lavapipe read their thread count when the first context or device is made: the
  // same as the CPU's.
  const std::string lpThreads = std::to_string(options.threads > 0 ? options.threads : int(std::thread::hardware_concurrency()));
  setenv("LP_NUM_THREADS", lpThreads.c_str(), 0);
  const ThreadLimit limit{std::size_t(options.threads)};
  const std::optional<std::pair<int, int>> frame = bench::parseFrameSize(sizeText);
  if (!frame) {
    std::fprintf(stderr, "bench_backends: --size '%s': expected N or WxH with sides from 1 to 16384\n", sizeText.c_str());
    return 1;
  }
  int width = frame->first, height = frame->second;
  if (options.quick) width = std::min(width, 128), height = std::min(height, 128);
  const int repeats = options.quick ? 1 : 3;

  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  try {
    if (options.quick) {
      meshes.emplace_back("fertility", io::readMesh(options.data + "/meshes/small/fertility_9k__libigl-tutorial-data.off"));
    } else {
      TriangleMesh igea = io::readMesh(options.data + "/meshes/large/igea__common-3d-test-models.ply");
      TriangleMesh igea1M = bench::loopSubdivide(igea);
      meshes.emplace_back("igea", std::move(igea));
      meshes.emplace_back("armadillo", io::readMesh(options.data + "/meshes/medium/armadillo__libigl-tutorial-data.obj"));
      meshes.emplace_back("igea-loop1", std::move(igea1M));
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_backends: %s\n", e.what());
    return 1;
  }
  bench::CsvWriter csv(std::filesystem::path(options.out) / "backends.csv",
                       "mesh,backend,device,pixels,hits,first_frame_s,primary_mrays,shaded_mpixels,shadow_rays,vs_cpu_primary,"
                       "vs_cpu_shaded,mask_disagreement,median_depth_texels,p95_depth_texels,scene_bytes");
  std::printf("%d threads (LP_NUM_THREADS=%s); %dx%d pixels from a framing camera; median of %d frames\n",
              options.threads, std::getenv("LP_NUM_THREADS"), width, height, repeats);
  for (const auto& [name, mesh] : meshes) {
    const auto model = std::make_shared<relief::ReliefModel>(relief::convert(mesh));
    const render::Scene scene = render::Scene::of(model);
    const Aabbd bounds(Vec3d(mesh.bounds().min), Vec3d(mesh.bounds().max));
    const render::Camera camera = render::Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), 35, 20);
    const double spacing = model->sampleSpacingWS();
    std::printf("\n%s: %zu triangles -> N = %d, T = %d, %zu grey cells\n", name.c_str(), mesh.triangleCount(),
                model->gridSize, model->texels, model->cells.size());
    std::printf("%-8s %10s %10s %8s %10s %8s %10s %9s %9s %12s  %s\n", "backend", "prim Mr/s", "vs cpu",
                "first s", "shaded Mp/s", "vs cpu", "mask", "depth med", "depth p95", "scene bytes", "device");
    struct Row {
      std::string backend, device;
      Measured m;
    };
    std::vector<Row> rows;
    for (const auto& [kind, available] : backends::renderers()) {
      if (std::find(skip.begin(), skip.end(), kind) != skip.end()) {
        std::printf("%-8s skipped: --skip\n", std::string(render::backendName(kind)).c_str());
        continue;
      }
      if (!available) {
        std::printf("%-8s skipped: %s\n", std::string(render::backendName(kind)).c_str(), available.reason.c_str());
        continue;
      }
      auto backend = backends::createBackend(kind, backends::settingsFor(kind, settings));
      rows.push_back({std::string(render::backendName(kind)), backend->description(),
                      measureBackend(*backend, scene, camera, width, height, repeats, options.threads)});
      // What the scene's own shader variant saves (the same frames with the general shader), and
      // the two entries (grey cells rasterized, the paper's way, and a compute pass over every
      // pixel) of which the default takes the faster: the same rows on both GPU backends; the
      // rasterized row only where the default did not take it.
      auto variantRows = [&](auto& gpu, const std::string& prefix) {
        const bool defaultRasterized = gpu.lastRayEntry() == gpu::RayEntry::Rasterized;
        rows.back().device += defaultRasterized ? ", rasterized entry" : ", compute entry";
        gpu.setGeneralShader(true);
        rows.push_back({prefix + "-general", "the one shader with every projection, map and feature",
                        measureBackend(gpu, scene, camera, width, height, repeats, options.threads)});
        gpu.setGeneralShader(false);
        gpu.setRayEntry(gpu::RayEntry::Compute);
        rows.push_back({prefix + "-compute", "the traversal as a compute pass over every pixel",
                        measureBackend(gpu, scene, camera, width, height, repeats, options.threads)});
        if (!defaultRasterized) {
          gpu.setRayEntry(gpu::RayEntry::Rasterized);
          rows.push_back({prefix + "-rasterized", "the grey cells rasterized, a fragment pass on the covered pixels",
                          measureBackend(gpu, scene, camera, width, height, repeats, options.threads)});
        }
        gpu.setRayEntry(gpu::RayEntry::Fastest);
      };
      // --quick (the smoke test) leaves them out: each variant is a shader compiled on the CPU
      // drivers, most of the run, and the backend tests render them all.
      if (options.quick) continue;
#ifdef CELLRELIEF_HAS_OPENGL
      if (auto* gl = dynamic_cast<gl::GlBackend*>(backend.get())) variantRows(*gl, "opengl");
#endif
#ifdef CELLRELIEF_HAS_VULKAN
      if (auto* vk = dynamic_cast<vulkan::VulkanBackend*>(backend.get())) variantRows(*vk, "vulkan");
#endif
    }
    {
      const auto built = std::chrono::steady_clock::now();
      const embree::EmbreeScene embree(mesh);
      const double buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count();
      const Vec3f light = glm::normalize(scene.lights[0].direction);
      rows.push_back({"embree", "Embree 3 rtcIntersect1/rtcOccluded1 on the original mesh, " +
                                    std::to_string(options.threads) + " threads",
                      measureEmbree(embree, camera, width, height, repeats, light, float(2 * spacing))});
      rows.back().m.firstSeconds = buildSeconds;
    }
    const Measured& cpu = rows[0].m;
    const double pixels = double(width) * double(height);
    std::printf("%-8s %.1f field evaluations and skip steps per primary ray; 8-lane occupancy %.0f%%\n", "",
                meanSteps(cpu.primary), 100 * laneOccupancy(cpu.primary));
    for (const Row& r : rows) {
      const render::FrameAgreement a = render::compareFrames(cpu.primary, r.m.primary, spacing);
      const double primary = pixels / r.m.primarySeconds * 1e-6, shaded = pixels / r.m.shadedSeconds * 1e-6;
      std::printf("%-8s %10.2f %9.2fx %8.2f %10.2f %7.2fx %10.2e %9.4f %9.4f %12zu  %s\n", r.backend.c_str(), primary,
                  cpu.primarySeconds / r.m.primarySeconds, r.m.firstSeconds, shaded, cpu.shadedSeconds / r.m.shadedSeconds,
                  a.maskFraction, a.medianTexels, a.p95Texels, r.m.bytes, r.device.c_str());
      if (r.m.deviceSeconds > 0)
        std::printf("%-8s device clock: %.2f Mrays/s\n", "", pixels / r.m.deviceSeconds * 1e-6);
      csv.row(name, r.backend, '"' + r.device + '"', std::size_t(pixels), countHits(r.m.primary), r.m.firstSeconds,
              primary, shaded,
              r.m.shadowRays, cpu.primarySeconds / r.m.primarySeconds, cpu.shadedSeconds / r.m.shadedSeconds,
              a.maskFraction, a.medianTexels, a.p95Texels, r.m.bytes);
    }
  }
  const std::filesystem::path png = std::filesystem::path(options.out) / "backends.png";
  const bool plotted = app::drawPlot("plot_backends", csv.path(), png);
  std::printf("\nvs cpu = the CPU reference's time / this backend's on the same frame; first s = upload and "
              "the first frame (tracers built, the shader variant compiled or read from Mesa's disk cache; "
              "Embree: its BVH build); mask and depth: "
              "agreement of the primary frame with the CPU reference (depth in sample spacings; Embree "
              "is the original mesh, so its figures are the relief model's own error)\nwrote %s%s%s%s\n",
              csv.path().c_str(), plotted ? " (plot: " : "", plotted ? png.c_str() : "", plotted ? ")" : "");
  return 0;
}

}  // namespace cellrelief::bench::backends_program
