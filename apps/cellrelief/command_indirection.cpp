// SPDX-License-Identifier: MIT
/// @file command_indirection.cpp
/// `cellrelief indirect <heightmap> -o indirection.png --optimizer gauss-newton|springs|ceres`: the
/// indirection map of a height map; and `cellrelief compare-optimizers [heightmaps...]`: the
/// optimizers side by side, distortion against time as CSV and a plot, a final table, and parallax
/// pictures before and after.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <cellrelief/core/parallel.h>
#include <cellrelief/indirection/distortion.h>
#include <cellrelief/indirection/optimizer_table.h>
#include <cellrelief/indirection/indirection_map.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/indirection/indirection_file.h>
#include <cellrelief/indirection/relief_surface.h>
#include <cellrelief/indirection/springs.h>
#include <cellrelief/io/atomic_file.h>
#include <cellrelief/io/image_io.h>
#ifdef CELLRELIEF_HAS_CERES
#include <cellrelief/indirection/ceres_optimizer.h>
#endif

#include "commands.h"
#include "../common/plot_script.h"

namespace cellrelief::app {

namespace {

using namespace indirection;

struct IndirectionCli {
  std::string heightmap, output, optimizer = "gauss-newton", wrap = "clamp", springForce = "in-plane";
  std::string prewarpIn, prewarpOut;
  int grid = 256, bits = 8, size = 0, threads = 0;
  float heightScale = 0.1f;
};

/// Every optimizer this build has: the library's table, and Ceres' where it is built.
const std::vector<OptimizerEntry>& optimizerTable() {
  static const std::vector<OptimizerEntry> table = [] {
    std::vector<OptimizerEntry> t = builtinOptimizers();
#ifdef CELLRELIEF_HAS_CERES
    for (OptimizerEntry& e : ceresOptimizers()) t.push_back(std::move(e));
#endif
    return t;
  }();
  return table;
}

/// The optimizer called `name`, with a clear error for Ceres' names in a build without Ceres.
const OptimizerEntry& findOptimizer(const std::string& name) {
#ifndef CELLRELIEF_HAS_CERES
  if (name.rfind("ceres", 0) == 0)
    throw Error(ErrorKind::Unsupported,
                "this build has no Ceres (install libceres-dev and reconfigure): use gauss-newton");
#endif
  return indirection::findOptimizer(optimizerTable(), name);
}

Grid optimize(const std::string& name, const ReliefMap& relief, int g, SpringForce force,
              const ProgressCallback& progress, int& iterations) {
  return findOptimizer(name).run(relief, {.gridSize = g, .springForce = force}, progress, iterations);
}

ReliefMap loadRelief(const std::string& path, float heightScale, Wrap wrap) {
  if (!std::isfinite(heightScale) || heightScale <= 0 || heightScale > 100)
    throw Error(ErrorKind::InvalidArgument,
                "--height-scale must be in (0, 100], not " + std::to_string(heightScale));
  return loadReliefMap(path, {heightScale, wrap});
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  io::writeTextAtomically(path, [&](std::ostream& out) { out << text; });
}

/// The relief as a surface on the CPU backend, from where the paper's figures look (plain POM
/// when `indirection` is null), with a checkerboard to show the stretch.
void writeParallaxPicture(const ReliefMap& relief, const Image<float>* indirection, const std::filesystem::path& png) {
  auto surface = std::make_shared<ReliefSurface>();
  surface->relief = relief;
  if (indirection) surface->indirection = *indirection;
  render::Scene scene;
  scene.reliefSurfaces.push_back(std::move(surface));
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  render::Camera camera;
  camera.eye = Vec3d(0.5, -0.55, 0.75);
  camera.target = Vec3d(0.5, 0.45, 0.0);
  camera.up = Vec3d(0, 0, 1);
  camera.verticalFovDegrees = 45;
  render::RenderOptions options;
  options.width = 640;
  options.height = 480;
  options.channels = render::kColor;
  io::writePng(cpu.renderFrame(camera, options).color, png);
}

int runIndirect(const IndirectionCli& o) {
  if (o.output.empty()) throw Error(ErrorKind::InvalidArgument, "indirect needs -o indirection.png");
  if (o.bits != 8 && o.bits != 16) throw Error(ErrorKind::InvalidArgument, "--bits takes 8 or 16");
  findOptimizer(o.optimizer);
  checkGridSize(o.grid);
  const SpringForce force = o.springForce == "tangent" ? SpringForce::Tangent : SpringForce::InPlane;
  if (o.springForce != "tangent" && o.springForce != "in-plane")
    throw Error(ErrorKind::InvalidArgument, "--spring-force takes in-plane or tangent");
  if (o.prewarpIn.empty() != o.prewarpOut.empty())
    throw Error(ErrorKind::InvalidArgument, "--prewarp and --prewarp-out go together");
  const ThreadLimit limit(std::size_t(std::max(0, o.threads)));
  const ReliefMap relief = loadRelief(o.heightmap, o.heightScale, parseWrap(o.wrap));
  io::ImageFile texture;
  if (!o.prewarpIn.empty()) {  // read before the long solve: a bad texture fails at once
    texture = io::readImage(o.prewarpIn);
    if (texture.bitDepth() != 8)
      throw Error(ErrorKind::Unsupported, o.prewarpIn, "pre-warp takes 8-bit textures");
  }
  std::printf("height map    %s: %dx%d, height scale %g, surface area %.4f\n", o.heightmap.c_str(),
              relief.width(), relief.height(), relief.heightScale(), relief.surfaceArea());
  int iterations = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const Grid grid = optimize(o.optimizer, relief, o.grid, force, {}, iterations);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Measured down to the texels (measureDistortion with 0): what a texture on the relief sees.
  const Distortion before = measureDistortion(Grid(o.grid), relief, 0);
  const Distortion after = measureDistortion(grid, relief, 0);
  std::printf("optimizer     %s, g = %d: %d iterations, %.3f s\n", o.optimizer.c_str(), o.grid,
              iterations, seconds);
  std::printf("distortion    (per texel) L2 stretch %.4f -> %.4f, angle mean %.4f -> %.4f (max "
              "%.2f), area mean %.4f -> %.4f, flipped cells %zu\n",
              before.l2Stretch, after.l2Stretch, before.angleMean, after.angleMean, after.angleMax,
              before.areaMean, after.areaMean, after.flippedCells);
  const int w = o.size > 0 ? o.size : relief.width(), h = o.size > 0 ? o.size : relief.height();
  const Image<float> I = indirectionMap(grid, w, h);
  writeIndirectionMap(I, o.output, o.bits, {.heightmap = o.heightmap, .optimizer = o.optimizer, .grid = o.grid,
                                            .heightScale = o.heightScale});
  if (!o.prewarpIn.empty()) {
    io::writePng(prewarp(std::get<Image<std::uint8_t>>(texture.pixels), grid, parseWrap(o.wrap)),
                 o.prewarpOut);
    std::printf("pre-warped    %s -> %s (fetch it at (u, v) + I(u, v))\n", o.prewarpIn.c_str(),
                o.prewarpOut.c_str());
  }
  std::printf("wrote         %s (%dx%d, %d-bit, R = I_u, G = I_v) and %s.json (scale, bias)\n",
              o.output.c_str(), w, h, o.bits, o.output.c_str());
  return 0;
}

// ---- compare-optimizers -------------------------------------------------------------------------

struct CompareOptimizersCli {
  std::vector<std::string> heightmaps;
  std::string out = "out/indirection", optimizers = "gauss-newton,springs,springs-chord,ceres";
  int grid = 256, threads = 2;
  float heightScale = 0.1f;
  bool quick = false, pictures = true;
};

/// The distortion as the comparison measures it: per texel (each cell subdivided into two sub-cells
/// per texel it spans, at most 8 x 8), what a texture on the relief sees. The per-cell measure on the vertices' heights
/// alone can be gamed by placing vertices on equal heights (relief_metric.h); it is printed beside.
Distortion measureOnTexels(const Grid& grid, const ReliefMap& relief) {
  return measureDistortion(grid, relief, 0);
}

struct Sample {
  double seconds;
  Distortion d;
};

struct Run {
  std::string map, optimizer;
  std::vector<Sample> curve;
  Distortion final, finalCorners;
  double seconds = 0;
  int iterations = 0;
  Grid grid;
};

/// The first time the excess distortion L2 - 1 is within `fraction` of the best's.
double timeToReach(const Run& run, double best, double fraction) {
  for (const Sample& s : run.curve)
    if (s.d.l2Stretch - 1 <= (best - 1) * (1 + fraction)) return s.seconds;
  return NAN;
}

std::string fmtTime(double s) {
  char buf[32];
  if (std::isnan(s)) return "never";
  std::snprintf(buf, sizeof buf, "%.3f s", s);
  return buf;
}

/// Per map: how much sooner each optimizer reaches the paper's springs' final distortion than the
/// springs themselves (the springs' total time over the time to reach their final L2).
void printSpeedupOverSprings(const std::vector<Run>& runs) {
  for (const Run& springs : runs) {
    if (springs.optimizer != "springs") continue;
    for (const Run& r : runs) {
      if (r.map != springs.map || &r == &springs) continue;
      double reached = NAN;
      for (const Sample& s : r.curve)
        if (s.d.l2Stretch <= springs.final.l2Stretch) {
          reached = s.seconds;
          break;
        }
      if (std::isnan(reached))
        std::printf("%s: %s never reaches the springs' L2 %.4f\n", r.map.c_str(),
                    r.optimizer.c_str(), springs.final.l2Stretch);
      else
        std::printf("%s: %s reaches the springs' L2 %.4f after %.3f s: %.1fx faster than the "
                    "springs (%.3f s)\n",
                    r.map.c_str(), r.optimizer.c_str(), springs.final.l2Stretch, reached,
                    springs.seconds / std::max(reached, 1e-9), springs.seconds);
    }
  }
}

int runCompareOptimizers(CompareOptimizersCli o) {
  if (o.heightmaps.empty()) {
    const std::filesystem::path data = std::filesystem::path(CELLRELIEF_DATA_DIR) / "heightmaps";
    o.heightmaps = {(data / "sponza/lion_bump.png").string(),
                    (data / "sponza/spnza_bricks_a_bump.png").string()};
  }
  if (o.quick) o.grid = std::min(o.grid, 32);
  checkGridSize(o.grid);
  std::filesystem::create_directories(o.out);
  const ThreadLimit limit(std::size_t(std::max(0, o.threads)));
  std::vector<std::string> optimizers;
  for (std::size_t start = 0; start <= o.optimizers.size();) {
    std::size_t comma = o.optimizers.find(',', start);
    if (comma == std::string::npos) comma = o.optimizers.size();
    const std::string name = o.optimizers.substr(start, comma - start);
    start = comma + 1;
#ifndef CELLRELIEF_HAS_CERES
    if (name.rfind("ceres", 0) == 0) {
      std::printf("(this build has no Ceres: %s left out)\n", name.c_str());
      continue;
    }
#endif
    findOptimizer(name);
    optimizers.push_back(name);
  }

  std::vector<Run> runs;
  std::ostringstream csv;
  csv << "heightmap,optimizer,seconds,g_level,l2_stretch,angle_mean,area_mean,angle_max,"
         "flipped_cells\n";
  for (const std::string& path : o.heightmaps) {
    ReliefMap relief = loadRelief(path, o.heightScale, Wrap::Clamp);
    if (o.quick) relief = downsample(relief, 128);
    const std::string name = std::filesystem::path(path).stem().string();
    const Distortion identity = measureOnTexels(Grid(o.grid), relief);
    std::printf("%s: %dx%d, height scale %g, g = %d, identity L2 %.4f, angle %.4f, area %.4f\n",
                name.c_str(), relief.width(), relief.height(), relief.heightScale(), o.grid,
                identity.l2Stretch, identity.angleMean, identity.areaMean);
    for (const std::string& opt : optimizers) {
      Run run;
      run.map = name;
      run.optimizer = opt;
      run.curve.push_back({0.0, identity});
      csv << name << "," << opt << ",0," << o.grid << "," << identity.l2Stretch << "," << identity.angleMean << ","
          << identity.areaMean << "," << identity.angleMax << "," << identity.flippedCells << "\n";
      // Distortion of the map as it stands, at the target g (coarse levels refined to it, which is
      // the map one would get by stopping there). Not charged to the optimizer's time.
      auto progress = [&](const Grid& grid, const Progress& p) {
        const Distortion d =
            measureOnTexels(grid.g() == o.grid ? grid : grid.resampled(o.grid), relief);
        run.curve.push_back({p.seconds, d});
        csv << name << "," << opt << "," << p.seconds << "," << p.g << "," << d.l2Stretch << ","
            << d.angleMean << "," << d.areaMean << "," << d.angleMax << "," << d.flippedCells
            << "\n";
      };
      const auto t0 = std::chrono::steady_clock::now();
      run.grid = optimize(opt, relief, o.grid, SpringForce::InPlane, progress, run.iterations);
      run.seconds = run.curve.back().seconds;
      run.final = measureOnTexels(run.grid, relief);
      run.finalCorners = measureDistortion(run.grid, relief);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("  %-13s %6.3f s (%.1f s with measurements), %d iterations, L2 %.4f (corners "
                  "%.4f), angle %.4f, area %.4f, flips %zu\n",
                  opt.c_str(), run.seconds, wall, run.iterations, run.final.l2Stretch,
                  run.finalCorners.l2Stretch, run.final.angleMean, run.final.areaMean,
                  run.final.flippedCells);
      runs.push_back(std::move(run));
    }
    if (o.pictures) {  // parallax pictures before and after, with the lower-distortion result
      const Run* best = nullptr;
      for (const Run& r : runs)
        if (r.map == name && (!best || r.final.l2Stretch < best->final.l2Stretch)) best = &r;
      const Image<float> I = indirectionMap(best->grid, 512, 512);
      const ReliefMap shown = o.quick ? relief : downsample(relief, 1024);
      writeParallaxPicture(shown, nullptr, std::filesystem::path(o.out) / ("indirection_" + name + "_pom_before.png"));
      writeParallaxPicture(shown, &I,
                           std::filesystem::path(o.out) / ("indirection_" + name + "_pom_after_" + best->optimizer + ".png"));
    }
  }
  writeText(std::filesystem::path(o.out) / "indirection_convergence.csv", csv.str());

  // The table: time to within 1% and 5% of the best final excess distortion (L2 - 1) per map.
  std::printf("\n%-22s %-13s %10s %10s %10s %9s %9s %9s %9s %6s\n", "heightmap", "optimizer",
              "to 5%", "to 1%", "total", "L2", "L2 corner", "angle", "area", "flips");
  std::map<std::string, double> best;
  for (const Run& r : runs)
    best[r.map] = best.count(r.map) ? std::min(best[r.map], r.final.l2Stretch) : r.final.l2Stretch;
  for (const Run& r : runs) {
    std::printf("%-22s %-13s %10s %10s %10s %9.4f %9.4f %9.4f %9.4f %6zu\n", r.map.c_str(),
                r.optimizer.c_str(), fmtTime(timeToReach(r, best[r.map], 0.05)).c_str(),
                fmtTime(timeToReach(r, best[r.map], 0.01)).c_str(), fmtTime(r.seconds).c_str(),
                r.final.l2Stretch, r.finalCorners.l2Stretch, r.final.angleMean, r.final.areaMean,
                r.final.flippedCells);
  }
  std::printf("(times exclude the distortion measurements; L2: stretch per texel, which the 'to' "
              "columns use; 'to 1%%': excess L2 stretch - 1 within 1%% of the best final of that "
              "map)\n");
  printSpeedupOverSprings(runs);
  const std::filesystem::path out(o.out);
  drawPlot("plot_convergence", out / "indirection_convergence.csv", out / "indirection_convergence.png");
  std::printf("wrote %s/indirection_convergence.csv%s\n", o.out.c_str(), o.pictures ? " and the parallax pictures" : "");
  return 0;
}

}  // namespace

Command addIndirectCommand(CLI::App& app) {
  auto o = std::make_shared<IndirectionCli>();
  CLI::App* cmd = app.add_subcommand(
      "indirect", "indirection map of a height map (quasi-conformal relief texturing)");
  cmd->add_option("heightmap", o->heightmap, "height map: PNG/JPEG/BMP gray, TGA alpha, 8/16 bit")
      ->required();
  cmd->add_option("-o,--output", o->output, "indirection map PNG (R = I_u, G = I_v; scale and bias "
                                            "in <output>.json)");
  cmd->add_option("--optimizer", o->optimizer,
                  "gauss-newton (the default: the conformal energy by damped Gauss-Newton with "
                  "multigrid, the fastest to within 1% of the lowest distortion in "
                  "compare-optimizers), springs (the paper), springs-chord (lengths between grid "
                  "vertices), ceres (L-BFGS) or ceres-lm (Levenberg-Marquardt)")
      ->capture_default_str();
  cmd->add_option("--grid", o->grid, "grid cells a side, g")->capture_default_str();
  cmd->add_option("--height-scale", o->heightScale, "height of H = 1 in tile widths")
      ->capture_default_str();
  cmd->add_option("--wrap", o->wrap, "height map borders: clamp or repeat")->capture_default_str();
  cmd->add_option("--bits", o->bits, "8 or 16 bits per channel")->capture_default_str();
  cmd->add_option("--size", o->size, "indirection map size (default: the height map's)");
  cmd->add_option("--spring-force", o->springForce,
                  "in-plane (the paper) or tangent (the spring energy's gradient)")
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "worker threads (0: all cores)");
  cmd->add_option("--prewarp", o->prewarpIn, "a structured texture to pre-warp by M (section 5.2)");
  cmd->add_option("--prewarp-out", o->prewarpOut, "where the pre-warped texture goes (PNG)");
  return {cmd, [o] { return runIndirect(*o); }};
}

Command addCompareOptimizersCommand(CLI::App& app) {
  auto o = std::make_shared<CompareOptimizersCli>();
  CLI::App* cmd = app.add_subcommand(
      "compare-optimizers", "the optimizers side by side: distortion against time, CSV, plot, table");
  cmd->add_option("heightmaps", o->heightmaps, "height maps (default: Sponza lion and bricks)");
  cmd->add_option("--grid", o->grid, "grid cells a side, g")->capture_default_str();
  cmd->add_option("--height-scale", o->heightScale, "height of H = 1 in tile widths")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "output folder")->capture_default_str();
  cmd->add_option("--optimizers", o->optimizers,
                  "comma-separated: gauss-newton, springs, springs-chord, ceres (L-BFGS), ceres-lm")
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "worker threads (0: all cores)")->capture_default_str();
  cmd->add_flag("--quick", o->quick, "small run (maps at 128, g <= 32) for smoke tests");
  cmd->add_flag("!--no-pictures", o->pictures, "skip the parallax pictures");
  return {cmd, [o] { return runCompareOptimizers(*o); }};
}

}  // namespace cellrelief::app
