// SPDX-License-Identifier: MIT
/// @file bench_silhouettes.cpp
/// Where and why the relief tracer and Embree disagree on hit or miss (issue 14, item 4). For each
/// mesh at its default conversion it traces primary rays from two framing views with the CPU
/// tracer and with Embree on the original mesh, and for every ray only one of them hits it says
/// how near the ray passes the real surface:
///   - only ours: the distance from our hit point to the mesh, in sample spacings;
///   - only Embree: how deep the ray goes inside the mesh (the largest distance to the surface of
///     its points between entry and exit), in sample spacings, and whether the relief's own field
///     is inside anywhere along it (then the search stepped over the surface) or nowhere (then the
///     relief has no surface there: a sampling error of the representation, not of the search).
/// A disagreement on a ray that grazes the surface within a small fraction of a sample is the
/// sampling's; one that passes a sample or more away is a fault to find. It writes one picture per
/// view (grey: both hit; red: only ours; blue: only Embree).
///
///   bench_silhouettes [--data DIR] [--out out/bench] [--quick] [--threads 2] [--size 512] [--skip all]
///                     [--grid N] [--texels T] [--mesh igea ...]
#include <algorithm>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <cellrelief/core/bvh.h>
#include <cellrelief/core/parallel.h>
#include <cellrelief/embree/embree_scene.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/projection/choice.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/camera.h>
#include <cellrelief/trace/relief_tracer.h>

#include "bench_common.h"
#include "bench_programs.h"

namespace cellrelief::bench::silhouettes_program {

namespace {

/// Upper bounds of the histogram bins, in sample spacings.
constexpr double kBins[] = {0.05, 0.1, 0.25, 0.5, 1.0, 2.0, INFINITY};
constexpr int kBinCount = int(std::size(kBins));
/// Field samples along an "only Embree" ray, from a few samples before its entry to its exit.
constexpr int kFieldSamples = 2000;

int binOf(double texels) {
  int b = 0;
  while (b + 1 < kBinCount && texels > kBins[b]) ++b;
  return b;
}

struct Tally {
  std::size_t rays = 0, onlyOurs = 0, onlyEmbree = 0;
  std::size_t oursBins[kBinCount] = {}, embreeBins[kBinCount] = {};
  std::size_t oursByProjection[4] = {};
  std::size_t oursAtCellFace = 0;   ///< our hit lies on a cell face (the side carried across it)
  std::size_t steppedOver = 0;      ///< only Embree, and the relief's field is inside on the ray

  void add(const Tally& o) {
    rays += o.rays, onlyOurs += o.onlyOurs, onlyEmbree += o.onlyEmbree;
    oursAtCellFace += o.oursAtCellFace, steppedOver += o.steppedOver;
    for (int b = 0; b < kBinCount; ++b) oursBins[b] += o.oursBins[b], embreeBins[b] += o.embreeBins[b];
    for (int p = 0; p < 4; ++p) oursByProjection[p] += o.oursByProjection[p];
  }
};

struct Setup {
  const relief::ReliefModel& model;
  const trace::ReliefTracerf& tracer;
  const embree::EmbreeScene& embree;
  const MeshBvh& bvh;
  double spacing;  ///< world units per sample
};

/// A ray only our tracer hits: how far its hit lies from the mesh, and where.
void tallyOnlyOurs(const Setup& s, const trace::ReliefHit<float>& ours, Tally& tally) {
  ++tally.onlyOurs;
  const Vec3d p(ours.position);
  ++tally.oursBins[binOf(std::sqrt(s.bvh.bvh.closestPoint(p).first) / s.spacing)];
  ++tally.oursByProjection[s.model.cells[ours.cell].projectionType];
  const Vec3d u = (p - s.model.originWS) / s.model.cellSizeWS;
  const Vec3d f = glm::abs(u - glm::round(u));
  tally.oursAtCellFace += std::min({f.x, f.y, f.z}) < 1e-4;
}

/// A ray only Embree hits: how deep it goes inside the mesh, and whether the relief's field is
/// inside anywhere near that stretch (the search stepped over it) or nowhere (no relief there).
void tallyOnlyEmbree(const Setup& s, const Rayf& ray, const Hitf& entry, Tally& tally) {
  ++tally.onlyEmbree;
  Rayf inside = ray;
  inside.tmin = entry.t * (1 + 1e-5f) + 1e-7f;
  const Hitf exit = s.embree.intersect(inside);
  const double t0 = entry.t, t1 = exit.valid() ? exit.t : entry.t;
  const Rayd rd(Vec3d(ray.origin), Vec3d(ray.direction));
  double deepest = 0;
  for (int k = 1; k < 16; ++k) deepest = std::max(deepest, std::sqrt(s.bvh.bvh.closestPoint(rd.at(t0 + (t1 - t0) * k / 16.0)).first));
  ++tally.embreeBins[binOf(deepest / s.spacing)];
  const double margin = 2 * s.spacing / glm::length(rd.direction);
  for (int k = 0; k <= kFieldSamples; ++k) {
    const double t = t0 - margin + (t1 - t0 + 2 * margin) * k / kFieldSamples;
    if (const auto f = s.tracer.fieldAt(Vec3f(rd.at(t))); f && *f > 0) {
      ++tally.steppedOver;
      return;
    }
  }
}

/// One view: traces every pixel with both, tallies the disagreements, writes the picture.
Tally compareView(const Setup& s, const render::Camera& camera, int size, const std::filesystem::path& png) {
  Image<std::uint8_t> picture(size, size, 3, 255);
  std::vector<Tally> rows(size);
  const render::Camera::FloatFrame frame = camera.floatFrame(size, size);
  parallelFor(0, std::size_t(size), [&](std::size_t y) {
    Tally& row = rows[y];
    for (int x = 0; x < size; ++x) {
      const Rayf ray = frame.ray(x, int(y));
      const auto ours = s.tracer.intersect(ray);
      const Hitf truth = s.embree.intersect(ray);
      ++row.rays;
      Vec3f color(1);
      if (ours.valid() && truth.valid()) {
        color = Vec3f(0.35f + 0.5f * std::abs(glm::dot(glm::normalize(s.embree.normal(truth)), ray.direction)));
      } else if (ours.valid()) {
        tallyOnlyOurs(s, ours, row);
        color = Vec3f(1, 0, 0);
      } else if (truth.valid()) {
        tallyOnlyEmbree(s, ray, truth, row);
        color = Vec3f(0, 0, 1);
      }
      for (int k = 0; k < 3; ++k) picture.at(x, int(y), k) = std::uint8_t(255 * color[k]);
    }
  }, 4);
  io::writePng(picture, png);
  Tally tally;
  for (const Tally& r : rows) tally.add(r);
  return tally;
}

void print(const std::string& name, const relief::ReliefModel& model, const Tally& t) {
  auto perMillion = [&](std::size_t n) { return 1e6 * double(n) / double(t.rays); };
  std::printf("\n%s: N = %d, T = %d; %.0f disagreements per million (%.0f only ours, %.0f only Embree)\n",
              name.c_str(), model.gridSize, model.texels, perMillion(t.onlyOurs + t.onlyEmbree),
              perMillion(t.onlyOurs), perMillion(t.onlyEmbree));
  std::printf("  %-12s", "samples");
  for (int b = 0; b < kBinCount; ++b)
    b + 1 < kBinCount ? std::printf(" %6s", ("<=" + std::to_string(kBins[b]).substr(0, 4)).c_str()) : std::printf(" %6s", "more");
  std::printf("\n  %-12s", "only ours");
  for (int b = 0; b < kBinCount; ++b) std::printf(" %6zu", t.oursBins[b]);
  std::printf("   at a cell face %zu; by projection:", t.oursAtCellFace);
  for (int p = 0; p < 4; ++p) std::printf(" %s %zu", projection::kProjectionTypeNames[p], t.oursByProjection[p]);
  std::printf("\n  %-12s", "only Embree");
  for (int b = 0; b < kBinCount; ++b) std::printf(" %6zu", t.embreeBins[b]);
  std::printf("   the relief's field inside on the ray (stepped over) %zu, nowhere (no relief there) %zu\n",
              t.steppedOver, t.onlyEmbree - t.steppedOver);
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app{"Where the relief tracer and Embree disagree on hit or miss, and how near the surface", "bench_silhouettes"};
  bench::BenchOptions options;
  options.threads = 2;
  int size = 512;
  std::string skip = "all";
  relief::ConvertOptions convertOptions;
  options.addTo(app);
  app.add_option("--grid", convertOptions.gridSize, "N (0: each mesh's automatic choice)")->capture_default_str();
  app.add_option("--texels", convertOptions.texels, "T (0: the default for N)")->capture_default_str();
  std::vector<std::string> meshes;
  app.add_option("--mesh", meshes, "Only these meshes (bunny, armadillo, fertility, igea; default: all)");
  app.add_option("--size", size, "Primary rays: size x size pixels per view")->capture_default_str();
  app.add_option("--skip", skip, "Empty-space skipping: all, flat (parallel and planar cells only) or off")
      ->check(CLI::IsMember({"all", "flat", "off"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const ThreadLimit limit{std::size_t(options.threads)};
  if (options.quick) size = std::min(size, 128);
  openvdb::initialize();

  using Case = std::pair<std::string, std::string>;
  const std::vector<Case> cases =
      options.quick ? std::vector<Case>{{"fertility", "meshes/small/fertility_9k__libigl-tutorial-data.off"}}
                    : std::vector<Case>{{"bunny", "meshes/medium/stanford-bunny__common-3d-test-models.obj"},
                                        {"armadillo", "meshes/medium/armadillo__libigl-tutorial-data.obj"},
                                        {"fertility", "meshes/small/fertility_9k__libigl-tutorial-data.off"},
                                        {"igea", "meshes/large/igea__common-3d-test-models.ply"}};
  std::filesystem::create_directories(options.out);
  std::printf("primary rays %dx%d per view, 2 views, skip %s; in sample spacings: only ours = distance of our "
              "hit from the mesh, only Embree = depth of the ray inside the mesh\n", size, size, skip.c_str());
  std::size_t total = 0, totalRays = 0;
  for (const auto& [name, file] : cases) {
    if (!meshes.empty() && std::find(meshes.begin(), meshes.end(), name) == meshes.end()) continue;
    TriangleMesh mesh;
    relief::ReliefModel model;
    try {
      mesh = io::readMesh(options.data + "/" + file);
      model = relief::convert(mesh, convertOptions);
    } catch (const Error& e) {
      std::fprintf(stderr, "bench_silhouettes: %s: %s\n", name.c_str(), e.what());
      return 1;
    }
    const trace::ReliefTracerf tracer(model, {.skipEmptySpace = skip != "off", .skipCentralCells = skip == "all"});
    const embree::EmbreeScene embree(mesh);
    const MeshBvh bvh(mesh);
    const Setup setup{model, tracer, embree, bvh, model.sampleSpacingWS()};
    const Aabbd bounds(Vec3d(mesh.bounds().min), Vec3d(mesh.bounds().max));
    Tally tally;
    for (const auto& [yaw, pitch] : {std::pair{35.0, 20.0}, std::pair{215.0, -25.0}}) {
      const render::Camera camera = render::Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), yaw, pitch);
      tally.add(compareView(setup, camera, size,
                            std::filesystem::path(options.out) / ("silhouettes_" + name + "_" + std::to_string(int(yaw)) + ".png")));
    }
    print(name, model, tally);
    total += tally.onlyOurs + tally.onlyEmbree;
    totalRays += tally.rays;
  }
  std::printf("\nall meshes: %.0f disagreements per million primary rays (goal: below 100)\nwrote the pictures "
              "silhouettes_<mesh>_<yaw>.png to %s\n", 1e6 * double(total) / double(totalRays), options.out.c_str());
  return 0;
}

}  // namespace cellrelief::bench::silhouettes_program
