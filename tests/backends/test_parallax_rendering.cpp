// SPDX-License-Identifier: MIT
// Parallax occlusion mapping with indirection maps on every backend: the Sponza lion with its
// colour map and a Gauss-Newton indirection map, the same relief with a checkerboard, and the
// DirectX SDK rocks (normal map in the TGA's RGB, tiling colour map), side by side. The CPU
// backend's frame is the tracer's, ray by ray; OpenGL and Vulkan are compared with it per pixel.
// Spot (a mesh with UVs) carries the rocks as a base mesh: its silhouette is the mesh's, every
// hit lies below it, and the GPU backends match the CPU there too.
#include <gtest/gtest.h>

#include <cmath>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/indirection/gauss_newton.h>
#include <cellrelief/indirection/indirection_map.h>
#include <cellrelief/render/frame_comparison.h>

#include "backends/failure_images.h"
#include "test_support.h"

namespace cellrelief::render::parallax_rendering {
namespace {

using indirection::ReliefSurface;

std::filesystem::path heightmap(const char* name) { return test::dataDir() / "heightmaps" / name; }

/// The relief's indirection map from Gauss-Newton at a small grid (a second on 2 threads).
Image<float> indirectionFor(const indirection::ReliefMap& relief) {
  indirection::GaussNewtonOptions o;
  o.gridSize = 32;
  return indirection::indirectionMap(indirection::optimizeGaussNewton(relief, o), 128, 128);
}

/// Three tiles in a row along x: the lion in colour, the lion's checkerboard, the rocks.
Scene threeTiles() {
  Scene scene;
  ReliefSurface lion;
  lion.relief = indirection::downsample(indirection::loadReliefMap(heightmap("sponza/lion_bump.png"), {0.1f}), 128);
  lion.indirection = indirectionFor(lion.relief);
  lion.colors = indirection::detail::rgb8(io::readImage(heightmap("sponza/lion.png")));
  ReliefSurface checker = lion;
  checker.colors = {};
  checker.originWS = Vec3f(1.1f, 0, 0);
  indirection::ReliefSurfaceFiles rocksFiles;
  rocksFiles.heightmap = heightmap("pom_dxsdk/rocks_NM_height.tga");
  rocksFiles.colors = heightmap("pom_dxsdk/rocks.jpg");
  rocksFiles.wrap = Wrap::Repeat;
  ReliefSurface rocks = indirection::loadReliefSurface(rocksFiles);
  rocks.originWS = Vec3f(2.2f, 0, 0);
  scene.reliefSurfaces = {std::make_shared<ReliefSurface>(std::move(lion)), std::make_shared<ReliefSurface>(std::move(checker)),
                          std::make_shared<ReliefSurface>(std::move(rocks))};
  return scene;
}

constexpr const char* kFiles[] = {"sponza/lion_bump.png", "sponza/lion.png", "pom_dxsdk/rocks_NM_height.tga",
                                   "pom_dxsdk/rocks.jpg"};

#define REQUIRE_PARALLAX_DATA() \
  for (const char* name : kFiles) CELLRELIEF_REQUIRE_FILE(heightmap(name))

/// A view of the three tiles (the xy plane, relief towards +z; the camera's up is +y).
Camera viewFrom(double yaw, double pitch, double radius = 0.75) {
  return Camera::framing(Vec3d(1.6, 0.5, 0.05), radius, yaw, pitch, 40.0);
}

TEST(ParallaxRendering, TheCpuBackendShowsWhatTheTracerHits) {
  REQUIRE_PARALLAX_DATA();
  const Scene scene = threeTiles();
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  RenderOptions options;
  options.width = 120;
  options.height = 60;
  const Camera camera = viewFrom(15, 25);
  const Frame frame = cpu.renderFrame(camera, options);
  const Camera::FloatFrame rays = camera.floatFrame(options.width, options.height);
  std::vector<trace::ParallaxTracer> tracers;
  for (const auto& s : scene.reliefSurfaces) tracers.emplace_back(*s);
  std::size_t hits[3] = {0, 0, 0};
  for (int y = 0; y < options.height; ++y)
    for (int x = 0; x < options.width; ++x) {
      const Rayf ray = rays.ray(x, y);
      float t = INFINITY;
      int nearest = -1;
      for (int i = 0; i < 3; ++i) {
        const trace::ParallaxHit h = tracers[std::size_t(i)].intersect(ray);
        if (h.valid() && h.t < t) t = h.t, nearest = i;
      }
      ASSERT_EQ(frame.mask.at(x, y, 0) != 0, nearest >= 0) << "pixel " << x << ", " << y;
      if (nearest < 0) continue;
      ++hits[nearest];
      EXPECT_EQ(frame.depth.at(x, y, 0), t);
    }
  for (int i = 0; i < 3; ++i) EXPECT_GT(hits[i], std::size_t(options.width * options.height / 12)) << "tile " << i;
}

TEST(ParallaxRendering, TheIndirectionMapChangesWhatTheTextureShows) {
  REQUIRE_PARALLAX_DATA();
  Scene scene = threeTiles();
  Scene plain = scene;
  auto checker = std::make_shared<ReliefSurface>(*scene.reliefSurfaces[1]);
  checker->indirection = {};
  plain.reliefSurfaces[1] = checker;
  cpu::CpuBackend cpu;
  RenderOptions options;
  options.width = options.height = 96;
  const Camera camera = Camera::framing(Vec3d(1.6, 0.5, 0.05), 0.5, 10, 20, 40.0);
  cpu.upload(scene);
  const Frame with = cpu.renderFrame(camera, options);
  cpu.upload(plain);
  const Frame without = cpu.renderFrame(camera, options);
  // Same geometry, different colours where the map moves the checkerboard's squares.
  std::size_t differ = 0, hits = 0;
  for (int y = 0; y < options.height; ++y)
    for (int x = 0; x < options.width; ++x) {
      ASSERT_EQ(with.mask.at(x, y, 0), without.mask.at(x, y, 0));
      if (!with.mask.at(x, y, 0)) continue;
      EXPECT_EQ(with.depth.at(x, y, 0), without.depth.at(x, y, 0));
      ++hits;
      differ += with.color.at(x, y, 0) != without.color.at(x, y, 0);
    }
  EXPECT_GT(hits, std::size_t(options.width * options.height / 2));
  EXPECT_GT(differ, hits / 20);
}

// Bounds of the GPU comparison. Measured on llvmpipe and lavapipe (two views, 13,685 and 11,150
// pixels hit, shadows on): no mask disagreement, depth p95 under 4e-5 texels, normals within 1e-3
// degrees, colour mean at most 0.002, median and p99 0. The goal is a median below one
// level; the other bounds leave room for another driver's rounding (a linear sample or a checker
// square's edge falling the other way) while catching a wrong map, offset or frame, which moves
// hundreds of pixels by tens of levels.
constexpr double kMaskBound = 1e-3, kDepthBound = 1e-2, kNormalBound = 0.05;
constexpr double kMeanColourBound = 0.1, kMedianColourBound = 1.0, kP99ColourBound = 2;

std::filesystem::path spotPath() { return test::dataDir() / "meshes" / "small" / "spot__common-3d-test-models.obj"; }

/// Spot with the rocks carved into it, the maps repeated 6 times over its UV atlas.
Scene spotWithRocks() {
  indirection::ReliefSurfaceFiles files;
  files.heightmap = heightmap("pom_dxsdk/rocks_NM_height.tga");
  files.colors = heightmap("pom_dxsdk/rocks.jpg");
  files.wrap = Wrap::Repeat;
  files.heightScale = 0.04f;
  files.baseMesh = spotPath();
  files.uvScale = 6.0f;
  Scene scene;
  scene.reliefSurfaces.push_back(std::make_shared<ReliefSurface>(indirection::loadReliefSurface(files)));
  return scene;
}

Camera spotView(double yaw, double pitch) { return Camera::framing(Vec3d(0.0, 0.3, 0.0), 1.1, yaw, pitch, 40.0); }

TEST(ParallaxRendering, OnAMeshTheSilhouetteIsTheMeshsAndTheReliefLiesBelowIt) {
  REQUIRE_PARALLAX_DATA();
  CELLRELIEF_REQUIRE_FILE(spotPath());
  const Scene scene = spotWithRocks();
  const ReliefSurface& surface = *scene.reliefSurfaces[0];
  const TriangleBvh<float> bvh(surface.baseMesh->positions, surface.baseMesh->triangles);
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  RenderOptions options;
  options.width = options.height = 96;
  const Camera camera = spotView(30, 15);
  const Frame frame = cpu.renderFrame(camera, options);
  const Camera::FloatFrame rays = camera.floatFrame(options.width, options.height);
  std::size_t hits = 0, carved = 0;
  for (int y = 0; y < options.height; ++y)
    for (int x = 0; x < options.width; ++x) {
      const Rayf ray = rays.ray(x, y);
      const Hitf base = bvh.closestHit(ray, kInvalidId, Faces::Front);
      ASSERT_EQ(frame.mask.at(x, y, 0) != 0, base.valid()) << "pixel " << x << ", " << y;
      if (!base.valid()) continue;
      ++hits;
      const float depth = frame.depth.at(x, y, 0);
      EXPECT_GE(depth, base.t);
      carved += depth > base.t * (1 + 1e-5f);
    }
  EXPECT_GT(hits, std::size_t(options.width * options.height / 5));
  EXPECT_GT(carved, hits / 2);
}

TEST(ParallaxRendering, OnAMeshGpuBackendsAgreeWithTheCpuReference) {
  REQUIRE_PARALLAX_DATA();
  CELLRELIEF_REQUIRE_FILE(spotPath());
  const Scene scene = spotWithRocks();
  RenderOptions options;
  options.width = options.height = 160;
  const Camera cameras[2] = {spotView(30, 15), spotView(200, 35)};
  const test::AgreementBounds agreement{.minHits = 3000, .mask = kMaskBound, .depthP95 = kDepthBound,
                                        .normalP95 = kNormalBound, .meanColour = kMeanColourBound,
                                        .p99Colour = kP99ColourBound, .medianColour = kMedianColourBound};
  if (test::expectGpuBackendsAgree(scene, cameras, options, 1.0 / 128, agreement, "parallax_mesh") == 0 && !test::inCI())
    GTEST_SKIP() << "no GPU backend runs here";
}

TEST(ParallaxRendering, GpuBackendsAgreeWithTheCpuReferencePerPixel) {
  REQUIRE_PARALLAX_DATA();
  const Scene scene = threeTiles();
  RenderOptions options;
  options.width = 240;
  options.height = 120;
  const Camera cameras[2] = {viewFrom(15, 25), viewFrom(55, -20, 0.8)};
  const test::AgreementBounds agreement{.minHits = 8000, .mask = kMaskBound, .depthP95 = kDepthBound,
                                        .normalP95 = kNormalBound, .meanColour = kMeanColourBound,
                                        .p99Colour = kP99ColourBound, .medianColour = kMedianColourBound};
  if (test::expectGpuBackendsAgree(scene, cameras, options, 1.0 / 128, agreement, "parallax") == 0 && !test::inCI())
    GTEST_SKIP() << "no GPU backend runs here";
}

}  // namespace
}  // namespace cellrelief::render::parallax_rendering
