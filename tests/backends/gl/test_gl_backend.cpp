// SPDX-License-Identifier: MIT
// What is particular to the OpenGL backend: shader variants (the specialized variant and the
// general shader render the same frame), a model with more face layers than the device has array
// layers, the driver's log in a shader error, and misuse refused with a clear error. Under CI an
// OpenGL that does not come up fails these tests instead of skipping them.
#include <gtest/gtest.h>

#include <cstdlib>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/frame_comparison.h>

#include "test_support.h"

namespace cellrelief::gl {
namespace {

class GlBackendTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const render::Availability a = probeAvailability();
    if (!a && test::inCI()) FAIL() << "OpenGL must run under CI: " << a.reason;
    if (!a) GTEST_SKIP() << a.reason;
  }
};

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

TEST_F(GlBackendTest, TheGeneralShaderAndTheScenesVariantRenderTheSameFrame) {
  const render::Scene scene = render::Scene::of(torus(8, 17));
  const render::Camera camera = render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal());
  render::RenderOptions options;
  options.width = options.height = 96;
  options.reflectionBounces = 1;
  GlBackend gl;
  gl.upload(scene);
  const gpu::ShaderVariant variant = gl.variantFor(options);
  EXPECT_NE(variant, gpu::ShaderVariant::general());
  EXPECT_FALSE(variant.colors);  // the torus has no colors
  const render::Frame specialized = gl.renderFrame(camera, options);
  gl.setGeneralShader(true);
  const render::Frame general = gl.renderFrame(camera, options);
  expectSameFrames(specialized, general, 1.0 / 8 / 16, "general vs specialized");
  gl.setGeneralShader(false);
  gl.setGather(false);
  const render::Frame fetched = gl.renderFrame(camera, options);
  expectSameFrames(specialized, fetched, 1.0 / 8 / 16, "gather vs four fetches");
}

TEST_F(GlBackendTest, TheRasterizedEntryRendersTheComputePassesFrame) {
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
  GlBackend gl;
  gl.upload(scene);
  for (const render::Camera& camera :
       {render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal(), 35, 20),
        render::Camera::framing(scene.boundsWS().center(), 0.2 * scene.boundsWS().diagonal(), -70, 50)}) {
    gl.setRayEntry(RayEntry::Compute);
    const render::Frame compute = gl.renderFrame(camera, options);
    gl.setRayEntry(RayEntry::Rasterized);
    const render::Frame raster = gl.renderFrame(camera, options);
    EXPECT_EQ(gl.lastRayEntry(), RayEntry::Rasterized);
    expectSameFrames(compute, raster, 1.0 / 16 / 8, "rasterized vs compute");
    // The stencil must really limit the fragment pass: boxes shrunk to a fifth of a cell drop
    // hits (a pass that ran everywhere would still show them all).
    gl.setCoverDilation(-0.4);
    const render::Frame shrunk = gl.renderFrame(camera, options);
    gl.setCoverDilation(std::nullopt);
    const render::FrameAgreement dropped = render::compareFrames(compute, shrunk, 1.0);
    EXPECT_GT(dropped.maskDiffers, (dropped.bothHit + dropped.maskDiffers) / 4);
  }
  // With the eye inside the grids, every pixel must run: the backend falls back to compute.
  render::Camera inside;
  inside.eye = Vec3d(scene.models[0]->originWS + Vec3d(0.5 * scene.models[0]->cellSizeWS * scene.models[0]->gridSize));
  inside.target = inside.eye + Vec3d(1, 0, 0);
  gl.renderFrame(inside, options);
  EXPECT_EQ(gl.lastRayEntry(), RayEntry::Compute);
}

TEST_F(GlBackendTest, AModelWithMoreFaceLayersThanArrayLayersRendersAsOnTheCpu) {
  const auto model = torus(64, 5);
  GlBackend gl;
  ASSERT_GT(model->layerCount(), gl.limits().maxArrayLayers);
  const render::Scene scene = render::Scene::of(model);
  gl.upload(scene);
  EXPECT_GE(gl.sceneBytes(), model->byteSize());
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  const render::Camera camera = render::Camera::framing(scene.boundsWS().center(), 0.5 * scene.boundsWS().diagonal());
  render::RenderOptions options;
  options.width = options.height = 96;
  const render::FrameAgreement a =
      render::compareFrames(cpu.renderFrame(camera, options), gl.renderFrame(camera, options), 1.0 / 64 / 4);
  EXPECT_GT(a.bothHit, 1000u);
  EXPECT_LE(a.maskFraction, 2.5e-4);
  EXPECT_LE(a.p95Texels, 1e-3);
}

TEST_F(GlBackendTest, AShaderThatDoesNotCompileIsAnErrorWithTheDriversLog) {
  test::TempDir dir;
  test::writeBytes(dir / "broken.comp", "void main() { undefinedFunction(); }\n");
  setenv("CELLRELIEF_SHADER_OVERRIDE", (dir / "broken.comp").c_str(), 1);
  GlBackend gl;
  gl.upload(render::Scene::of(torus(4, 9)));
  try {
    gl.renderFrame(render::Camera{}, {});
    ADD_FAILURE() << "a broken shader compiled";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("does not compile"), std::string::npos) << what;
    EXPECT_NE(what.find("undefinedFunction"), std::string::npos) << what;  // the driver's log
  }
  unsetenv("CELLRELIEF_SHADER_OVERRIDE");
}

TEST_F(GlBackendTest, MisuseIsRefusedWithAClearError) {
  GlBackend gl;
  EXPECT_THROW(gl.renderFrame(render::Camera{}, {}), Error);  // nothing uploaded
  render::Scene scene = render::Scene::of(torus(4, 9));
  scene.lights.resize(9);
  try {
    gl.upload(scene);
    ADD_FAILURE() << "nine lights were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at most 8 lights"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cellrelief::gl
