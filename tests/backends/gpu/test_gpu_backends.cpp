// SPDX-License-Identifier: MIT
// What both GPU backends must do alike, as one typed suite over OpenGL and Vulkan: shader variants
// (the specialized variant, the general shader and the four-fetch read render the same frame),
// the rasterized entry of grey cells and chart boxes (the compute pass's frame, a stencil that
// really limits the fragment pass, compute when the eye is inside), a model with more face layers than the device has array
// layers, and misuse refused with a clear error. Under CI a GPU backend that does not come up
// fails these tests instead of skipping them.
#include <gtest/gtest.h>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/geotex/convert.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/frame_comparison.h>

#include "test_support.h"

namespace cellrelief::gpu {
namespace {

template <class Backend>
struct Availability;
#ifdef CELLRELIEF_HAS_OPENGL
template <>
struct Availability<gl::GlBackend> {
  static render::Availability probe() { return gl::probeAvailability(); }
  static constexpr const char* kName = "OpenGL";
};
#endif
#ifdef CELLRELIEF_HAS_VULKAN
template <>
struct Availability<vulkan::VulkanBackend> {
  static render::Availability probe() { return vulkan::probeAvailability(); }
  static constexpr const char* kName = "Vulkan";
};
#endif

template <class Backend>
class GpuBackendTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const render::Availability a = Availability<Backend>::probe();
    if (!a && test::inCI()) FAIL() << Availability<Backend>::kName << " must run under CI: " << a.reason;
    if (!a) GTEST_SKIP() << a.reason;
  }
};

using GpuBackends = ::testing::Types<
#if defined(CELLRELIEF_HAS_OPENGL) && defined(CELLRELIEF_HAS_VULKAN)
    gl::GlBackend, vulkan::VulkanBackend
#elif defined(CELLRELIEF_HAS_OPENGL)
    gl::GlBackend
#elif defined(CELLRELIEF_HAS_VULKAN)
    vulkan::VulkanBackend
#endif
    >;
struct BackendName {
  template <class T>
  static std::string GetName(int) {
    return Availability<T>::kName;
  }
};
TYPED_TEST_SUITE(GpuBackendTest, GpuBackends, BackendName);

std::shared_ptr<const relief::ReliefModel> torus(int grid, int texels) {
  return std::make_shared<relief::ReliefModel>(
      relief::convert(makeTorus(1.0f, 0.35f, 192, 96), {.gridSize = grid, .texels = texels}));
}

/// Two renderings of one algorithm: equal on llvmpipe (measured), and within the rounding another
/// compiler may choose differently per program (fused multiply-adds) elsewhere.
void expectSameFrames(const render::Frame& a, const render::Frame& b, double spacing, const char* what) {
  const render::FrameAgreement r = render::compareFrames(a, b, spacing);
  EXPECT_GT(r.bothHit, 500u) << what;
  EXPECT_LE(r.maskFraction, 2.5e-4) << what;
  EXPECT_LE(r.maxTexels, 0.05) << what;
  EXPECT_LE(r.p99Color, 1.0) << what;
  EXPECT_LE(r.cellFraction, 2.5e-4) << what;
  EXPECT_LE(r.meanSteps, 0.05) << what;
}

TYPED_TEST(GpuBackendTest, TheGeneralShaderAndTheScenesVariantRenderTheSameFrame) {
  const render::Scene scene = render::Scene::of(torus(8, 17));
  const render::Camera camera = render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal());
  render::RenderOptions options;
  options.width = options.height = 96;
  options.reflectionBounces = 1;
  TypeParam backend;
  backend.upload(scene);
  const ShaderVariant variant = backend.variantFor(options);
  EXPECT_NE(variant, ShaderVariant::general());
  EXPECT_FALSE(variant.colors);  // the torus has no colors
  const render::Frame specialized = backend.renderFrame(camera, options);
  backend.setGeneralShader(true);
  const render::Frame general = backend.renderFrame(camera, options);
  expectSameFrames(specialized, general, 1.0 / 8 / 16, "general vs specialized");
  backend.setGeneralShader(false);
  backend.setGather(false);
  const render::Frame fetched = backend.renderFrame(camera, options);
  expectSameFrames(specialized, fetched, 1.0 / 8 / 16, "gather vs four fetches");
}


TYPED_TEST(GpuBackendTest, TheRasterizedEntryRendersTheComputePassesFrame) {
  // Two models, shadows and a mirror bounce: the paper's way (grey cells into the stencil, the
  // traversal in a fragment pass on covered pixels) must give exactly the compute pass's frame.
  render::Scene scene;
  scene.models = {torus(16, 9), std::make_shared<relief::ReliefModel>(relief::convert(
                                    [] {
                                      TriangleMesh m = makeIcosphere(4, 0.5f);
                                      for (Vec3f& p : m.positions) p += Vec3f(1.6f, 0.2f, 0.0f);
                                      return m;
                                    }(),
                                    {.gridSize = 4, .texels = 17}))};
  render::RenderOptions options;
  options.width = 120;
  options.height = 90;
  options.reflectionBounces = 1;
  TypeParam backend;
  backend.upload(scene);
  for (const render::Camera& camera :
       {render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal(), 35, 20),
        render::Camera::framing(scene.boundsWS().center(), 0.2 * scene.boundsWS().diagonal(), -70, 50)}) {
    backend.setRayEntry(RayEntry::Compute);
    const render::Frame compute = backend.renderFrame(camera, options);
    backend.setRayEntry(RayEntry::Rasterized);
    const render::Frame raster = backend.renderFrame(camera, options);
    EXPECT_EQ(backend.lastRayEntry(), RayEntry::Rasterized);
    expectSameFrames(compute, raster, 1.0 / 16 / 8, "rasterized vs compute");
    // The stencil must really limit the fragment pass: boxes shrunk to a fifth of a cell drop
    // hits (a pass that ran everywhere would still show them all).
    backend.setCoverDilation(-0.4);
    const render::Frame shrunk = backend.renderFrame(camera, options);
    backend.setCoverDilation(std::nullopt);
    const render::FrameAgreement dropped = render::compareFrames(compute, shrunk, 1.0);
    EXPECT_GT(dropped.maskDiffers, (dropped.bothHit + dropped.maskDiffers) / 4);
  }
  // With the eye inside the grids, every pixel must run: the backend falls back to compute.
  render::Camera inside;
  inside.eye = Vec3d(scene.models[0]->originWS + Vec3d(0.5 * scene.models[0]->cellSizeWS * scene.models[0]->gridSize));
  inside.target = inside.eye + Vec3d(1, 0, 0);
  backend.renderFrame(inside, options);
  EXPECT_EQ(backend.lastRayEntry(), RayEntry::Compute);
}

TYPED_TEST(GpuBackendTest, TheRasterizedEntryOfChartBoxesRendersTheComputePassesFrame) {
  // Geometry textures beside a relief model, shadows on: their chart boxes join the grey cells in
  // the stencil (the geometry-textures paper's way), and the frame must stay the compute pass's.
  TriangleMesh sphere = makeIcosphere(4, 0.6f);
  for (Vec3f& p : sphere.positions) p += Vec3f(1.9f, 0.0f, 0.3f);
  geotex::GeoTexOptions charts;
  charts.vsa.proxies = 20;
  charts.maxTexels = 32;
  render::Scene scene;
  scene.models = {torus(8, 9)};
  scene.geotexModels = {std::make_shared<geotex::GeoTexModel>(geotex::convertMesh(sphere, charts).model)};
  render::RenderOptions options;
  options.width = 120;
  options.height = 90;
  TypeParam backend;
  backend.upload(scene);
  for (const render::Camera& camera :
       {render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal(), 35, 20),
        render::Camera::framing(scene.boundsWS().center(), 0.25 * scene.boundsWS().diagonal(), 160, -40)}) {
    backend.setRayEntry(RayEntry::Compute);
    const render::Frame compute = backend.renderFrame(camera, options);
    backend.setRayEntry(RayEntry::Rasterized);
    const render::Frame raster = backend.renderFrame(camera, options);
    EXPECT_EQ(backend.lastRayEntry(), RayEntry::Rasterized);
    expectSameFrames(compute, raster, 1.0 / 8 / 8, "rasterized vs compute, with chart boxes");
  }
  {
    // The chart boxes' cover must really limit the pass: the relief model gone, boxes shrunk by
    // a third of their size on each side lose much of the sphere.
    render::Scene chartsOnly;
    chartsOnly.geotexModels = scene.geotexModels;
    TypeParam alone;
    alone.upload(chartsOnly);
    const Aabbd bounds = chartsOnly.boundsWS();
    const render::Camera camera = render::Camera::framing(bounds.center(), 0.3 * bounds.diagonal(), 20, 30);
    const render::Frame whole = alone.renderFrame(camera, options);
    alone.setCoverDilation(-0.34);
    const render::Frame shrunk = alone.renderFrame(camera, options);
    EXPECT_EQ(alone.lastRayEntry(), RayEntry::Rasterized);
    const render::FrameAgreement dropped = render::compareFrames(whole, shrunk, 1.0);
    EXPECT_GT(dropped.bothHit + dropped.maskDiffers, 1500u);
    EXPECT_GT(dropped.maskDiffers, (dropped.bothHit + dropped.maskDiffers) / 4);
  }
  // The eye inside the scene's bounds (here at a chart box's centre): rays may start inside a box,
  // whose faces the cover would clip, so every pixel runs by the compute pass.
  const geotex::ChartBox& box = scene.geotexModels[0]->charts[0];
  render::Camera inside;
  inside.eye = box.originWS + 0.5 * (box.axisWS[0] * box.sizeWS.x + box.axisWS[1] * box.sizeWS.y + box.axisWS[2] * box.sizeWS.z);
  inside.target = inside.eye + Vec3d(1, 0, 0);
  backend.renderFrame(inside, options);
  EXPECT_EQ(backend.lastRayEntry(), RayEntry::Compute);
}

TYPED_TEST(GpuBackendTest, AModelWithMoreFaceLayersThanArrayLayersRendersAsOnTheCpu) {
  const auto model = torus(64, 5);
  TypeParam backend;
  ASSERT_GT(model->layerCount(), backend.limits().maxArrayLayers);
  const render::Scene scene = render::Scene::of(model);
  backend.upload(scene);
  EXPECT_GE(backend.sceneBytes(), model->byteSize());
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  const render::Camera camera = render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal());
  render::RenderOptions options;
  options.width = options.height = 96;
  const render::FrameAgreement a =
      render::compareFrames(cpu.renderFrame(camera, options), backend.renderFrame(camera, options), 1.0 / 64 / 4);
  EXPECT_GT(a.bothHit, 1000u);
  EXPECT_LE(a.maskFraction, 2.5e-4);
  EXPECT_LE(a.p95Texels, 1e-3);
}


TYPED_TEST(GpuBackendTest, MisuseIsRefusedWithAClearError) {
  TypeParam backend;
  EXPECT_THROW(backend.renderFrame(render::Camera{}, {}), Error);  // nothing uploaded
  render::Scene scene = render::Scene::of(torus(4, 9));
  scene.lights.resize(9);
  try {
    backend.upload(scene);
    ADD_FAILURE() << "nine lights were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at most 8 lights"), std::string::npos) << e.what();
  }
}


}  // namespace
}  // namespace cellrelief::gpu
