// SPDX-License-Identifier: MIT
// Geometry textures on every backend: a coloured sphere of VSA charts beside a DEM chart. The CPU
// backend's depth is the tracer's, ray by ray; OpenGL and Vulkan are compared with it per pixel
// (mask, depth, normal, colour), shadows included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/geotex/convert.h>
#include <cellrelief/render/frame_comparison.h>

#include "backends/failure_images.h"
#include "test_support.h"

namespace cellrelief::render::geotex_rendering {
namespace {

// Bounds of the GPU comparison. Measured on llvmpipe and lavapipe (two views, 9,676 and 4,609
// pixels hit): no mask disagreement, depth p95 under 2e-4 and at most 2e-3 of 1e-3 diagonals (float
// rounding in another order), normals within 1e-4 degrees, colour mean 0.000 and p99 0. The
// bounds leave room for another driver's rounding on a silhouette or a shadow's edge while
// catching a wrong texel, chart or offset, which moves hundreds of pixels by tens of levels.
constexpr double kMaskBound = 1e-3, kDepthBound = 1e-2, kNormalBound = 0.05;
constexpr double kMeanColourBound = 0.1, kP99ColourBound = 2;

/// A coloured sphere as geometry textures, and a DEM of ripples beside it.
Scene sphereAndTerrain() {
  TriangleMesh sphere = makeIcosphere(4);
  sphere.colors.resize(sphere.positions.size());
  for (std::size_t v = 0; v < sphere.positions.size(); ++v)
    sphere.colors[v] = Color8(Vec3f(127.5f) * (sphere.positions[v] + 1.0f), 255);
  geotex::GeoTexOptions o;
  o.vsa.proxies = 24;
  o.maxTexels = 32;
  Image<std::uint16_t> dem(48, 48, 1);
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 48; ++i)
      dem.at(i, j, 0) = quantizeUnorm<std::uint16_t>(0.5 + 0.4 * std::sin(0.4 * i) * std::cos(0.3 * j));
  geotex::GeoTexModel terrain = geotex::heightMapModel(dem, {.width = 2.5, .depth = 2.5, .height = 0.4});
  for (geotex::ChartBox& c : terrain.charts) c.originWS = Vec3d(1.3, -1.25, -1.0);
  Scene scene;
  scene.geotexModels = {std::make_shared<geotex::GeoTexModel>(geotex::convertMesh(sphere, o).model),
                        std::make_shared<geotex::GeoTexModel>(terrain)};
  return scene;
}

/// The CPU backend with the scene uploaded, and the small framing view its tests render.
struct CpuView {
  explicit CpuView(const Scene& scene)
      : camera(Camera::framing(scene.boundsWS().center(), 0.3 * scene.boundsWS().diagonal(), 30, 35)) {
    cpu.upload(scene);
    options.width = 96;
    options.height = 64;
  }
  cpu::CpuBackend cpu;
  RenderOptions options;
  Camera camera;
};

TEST(GeoTexRendering, TheCpuBackendShowsWhatTheTracerHits) {
  const Scene scene = sphereAndTerrain();
  CpuView view(scene);
  const RenderOptions& options = view.options;
  const Camera& camera = view.camera;
  const Frame frame = view.cpu.renderFrame(camera, options);
  const trace::GeoTexTracer<float> sphere(*scene.geotexModels[0]), terrain(*scene.geotexModels[1]);
  const Camera::FloatFrame rays = camera.floatFrame(options.width, options.height);
  std::size_t hits = 0, coloured = 0;
  for (int y = 0; y < options.height; ++y)
    for (int x = 0; x < options.width; ++x) {
      const Rayf ray = rays.ray(x, y);
      const Hitf a = sphere.intersect(ray), b = terrain.intersect(ray);
      const float t = std::min(a.valid() ? a.t : INFINITY, b.valid() ? b.t : INFINITY);
      ASSERT_EQ(frame.mask.at(x, y, 0) != 0, std::isfinite(t)) << "pixel " << x << ", " << y;
      if (!std::isfinite(t)) continue;
      ++hits;
      EXPECT_EQ(frame.depth.at(x, y, 0), t);
      // The sphere's colour map shows; the terrain has none and is grey.
      const bool grey = frame.color.at(x, y, 0) == frame.color.at(x, y, 1) && frame.color.at(x, y, 1) == frame.color.at(x, y, 2);
      coloured += a.valid() && a.t == t && !grey;
    }
  EXPECT_GT(hits, std::size_t(options.width * options.height / 4));
  EXPECT_GT(coloured, hits / 8);
}

// --no-skip (TraceOptions::skipEmptySpace) changes the search of the tracers built at upload, in
// place: the same pixels at the same depths, other steps, and back again.
TEST(GeoTexRendering, TheCpuBackendSkipsOrNotOnTheSameTracers) {
  const Scene scene = sphereAndTerrain();
  CpuView view(scene);
  view.options.channels = kAllChannels;
  auto renderWithSkipping = [&](bool skip) {
    view.options.trace.skipEmptySpace = skip;
    return view.cpu.renderFrame(view.camera, view.options);
  };
  auto totalSteps = [](const Frame& f) {
    double sum = 0;
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) sum += f.steps.at(x, y, 0);
    return sum;
  };
  const Frame skipping = renderWithSkipping(true), plain = renderWithSkipping(false), again = renderWithSkipping(true);
  auto same = [](const auto& a, const auto& b) { return std::ranges::equal(a.levelData(), b.levelData()); };
  for (const Frame* f : {&plain, &again}) {
    EXPECT_TRUE(same(f->mask, skipping.mask));
    EXPECT_TRUE(same(f->depth, skipping.depth));
  }
  // The search changed (on these maps of 32 texels the pyramid walk's node tests outnumber the
  // samples it saves: 49,734 steps against 40,871 measured; the tracer's own test shows the gain on
  // larger maps) and came back.
  EXPECT_NE(totalSteps(plain), totalSteps(skipping));
  EXPECT_EQ(totalSteps(again), totalSteps(skipping));
}

TEST(GeoTexRendering, GpuBackendsAgreeWithTheCpuReferencePerPixel) {
  const Scene scene = sphereAndTerrain();
  RenderOptions options;
  options.width = 200;
  options.height = 140;
  const Aabbd bounds = scene.boundsWS();
  const Camera cameras[2] = {Camera::framing(bounds.center(), 0.3 * bounds.diagonal(), 25, 30),
                             Camera::framing(bounds.center(), 0.3 * bounds.diagonal(), 200, 15)};
  const test::AgreementBounds agreement{.minHits = 4000, .mask = kMaskBound, .depthP95 = kDepthBound,
                                        .normalP95 = kNormalBound, .meanColour = kMeanColourBound,
                                        .p99Colour = kP99ColourBound, .meanSteps = 0.05};  // steps: measured 0.000
  if (test::expectGpuBackendsAgree(scene, cameras, options, 1e-3 * bounds.diagonal(), agreement, "geotex") == 0 &&
      !test::inCI())
    GTEST_SKIP() << "no GPU backend runs here";
}

}  // namespace
}  // namespace cellrelief::render::geotex_rendering
