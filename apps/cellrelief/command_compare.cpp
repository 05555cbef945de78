// SPDX-License-Identifier: MIT
/// @file command_compare.cpp
/// `cellrelief compare-backends model.crm|mesh`: the same scene and camera on every backend that
/// runs here; prints backend, device, time, Mrays/s and the agreement of every channel with the
/// CPU reference, and writes a side-by-side picture and one diff picture per GPU backend.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/relief/relief_model.h>
#include <cellrelief/render/frame_comparison.h>

#include "commands.h"

namespace cellrelief::app {
namespace {

struct CompareBackendsCli {
  std::string input, output = "out/compare", size = "512x512", camera, device;
  gpu::RayEntry entry = gpu::RayEntry::Fastest;
  bool shadows = true;
  int repeat = 3;
  SurfaceCli surface;
};

struct Rendered {
  render::BackendKind kind;
  std::string device;
  double seconds = 0, deviceSeconds = 0;
  std::size_t bytes = 0;
  render::Frame frame;
};

/// The frames next to each other, left to right, with a 4-pixel white gap.
Image<std::uint8_t> sideBySide(const std::vector<Rendered>& runs) {
  const int w = runs[0].frame.width, h = runs[0].frame.height, gap = 4;
  const int n = int(runs.size());
  Image<std::uint8_t> out(n * w + (n - 1) * gap, h, 4, 255);
  for (int i = 0; i < n; ++i)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 4; ++c) {
          const std::uint8_t v = runs[std::size_t(i)].frame.color.at(x, y, c);
          // Misses have alpha 0: shown over white.
          out.at(i * (w + gap) + x, y, c) = c == 3 ? 255 : runs[std::size_t(i)].frame.color.at(x, y, 3) ? v : 255;
        }
  return out;
}

int runCompareBackends(const CompareBackendsCli& o) {
  const auto [width, height] = parseImageSize(o.size);
  const render::Scene scene = loadScene(o.input, o.surface);
  const render::Camera camera = parseCamera(o.camera, scene.boundsWS());
  render::RenderOptions options;
  options.width = width;
  options.height = height;
  options.shadows = o.shadows;
  std::vector<Rendered> runs;
  const backends::BackendSettings settings{.vulkanDevice = o.device};
  for (const auto& [kind, available] : backends::renderers()) {
    if (!available) {
      std::printf("%-8s skipped: %s\n", std::string(render::backendName(kind)).c_str(), available.reason.c_str());
      continue;
    }
    auto backend = backends::createBackend(kind, backends::settingsFor(kind, settings));
    setRayEntry(*backend, o.entry);
    withPath(o.input, [&] { backend->upload(scene); });
    Rendered r{kind, backend->description(), 0, 0, backend->sceneBytes(), {}};
    backend->renderFrame(camera, options);  // warm-up: tracers, shader compilation
    double best = 1e30, bestDevice = 0;
    for (int i = 0; i < std::max(1, o.repeat); ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      r.frame = backend->renderFrame(camera, options);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (s < best) best = s, bestDevice = backend->deviceSeconds();
    }
    r.seconds = best;
    r.deviceSeconds = bestDevice;
    if (const std::string entry = lastRayEntry(*backend); !entry.empty()) r.device += ", " + entry;
    r.bytes = backend->sceneBytes();
    runs.push_back(std::move(r));
  }
  // Depth errors in sample spacings of the relief model, or in thousandths of the scene's
  // diagonal for geometry textures and polycube meshes.
  const double spacing = scene.models.empty()
                             ? 1e-3 * scene.boundsWS().diagonal()
                             : scene.models[0]->sampleSpacingWS();
  const double rays = double(width) * double(height);
  std::printf("\n%-8s %9s %9s %9s %11s %10s %10s %9s %9s %9s  %s\n", "backend", "time s", "Mrays/s", "vs cpu",
              "scene", "mask", "depth med", "depth p95", "normal", "color", "device");
  std::filesystem::create_directories(o.output);
  for (const Rendered& r : runs) {
    const render::FrameAgreement a = render::compareFrames(runs[0].frame, r.frame, spacing);
    std::printf("%-8s %9.4f %9.2f %8.2fx %11s %10.2e %10.4f %9.4f %8.3f° %9.3f  %s\n",
                std::string(render::backendName(r.kind)).c_str(), r.seconds, rays / r.seconds * 1e-6,
                runs[0].seconds / r.seconds, formatBytes(double(r.bytes)).c_str(), a.maskFraction, a.medianTexels,
                a.p95Texels, a.p95Degrees, a.meanColor, r.device.c_str());
    if (r.deviceSeconds > 0)
      std::printf("%-8s device clock %.4f s (%.2f Mrays/s)\n", "", r.deviceSeconds, rays / r.deviceSeconds * 1e-6);
    if (r.kind != render::BackendKind::Cpu) {
      const std::filesystem::path diff =
          std::filesystem::path(o.output) / ("diff_cpu_" + std::string(render::backendName(r.kind)) + ".png");
      io::writePng(render::frameDiffImage(runs[0].frame, r.frame, spacing), diff);
      std::printf("wrote %s (red: only cpu hit, blue: only %s, light grey: both, darker with depth error, black at a sample spacing)\n",
                  diff.c_str(), std::string(render::backendName(r.kind)).c_str());
    }
  }
  const std::filesystem::path side = std::filesystem::path(o.output) / "side_by_side.png";
  io::writePng(sideBySide(runs), side);
  std::printf("wrote %s (left to right:", side.c_str());
  for (const Rendered& r : runs) std::printf(" %s", std::string(render::backendName(r.kind)).c_str());
  std::printf(")\n");
  return 0;
}

}  // namespace

Command addCompareBackendsCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("compare-backends",
                                 "Render one scene on every backend that runs here and compare them with the CPU reference");
  auto o = std::make_shared<CompareBackendsCli>();
  cmd->add_option("model", o->input,
                  "Relief model (.crm), geometry textures (.cgt), mesh (.obj .ply .off .stl), a folder "
                  "written by `cellrelief polycube`, or a height map (.png .jpg .tga .bmp) shown by parallax "
                  "occlusion mapping")
      ->required();
  cmd->add_option("-o,--out", o->output, "Folder for side_by_side.png and the diff pictures")->capture_default_str();
  cmd->add_option("--size", o->size, "Image size WxH")->capture_default_str();
  cmd->add_option("--device", o->device, backends::kDeviceHelp);
  cmd->add_option("--entry", o->entry, kRayEntryHelp)
      ->transform(CLI::CheckedTransformer(rayEntryNames(), CLI::ignore_case).description("fastest|rasterized|compute"))
      ->default_str("fastest");
  cmd->add_option("--camera", o->camera,
                  "yaw,pitch[,fov] around the model, or ex,ey,ez,tx,ty,tz[,fov] (default 35,20,40)");
  cmd->add_option("--repeat", o->repeat, "Timed frames per backend (the fastest is reported)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_flag("!--no-shadows", o->shadows, "No shadow rays");
  addSurfaceOptions(cmd, o->surface);
  return {cmd, [o]() { return runCompareBackends(*o); }};
}

}  // namespace cellrelief::app
