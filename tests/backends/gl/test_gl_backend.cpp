// SPDX-License-Identifier: MIT
// What is particular to the OpenGL backend: it compiles its GLSL at run time, so a broken shader
// (CELLRELIEF_SHADER_OVERRIDE) is an error with the driver's log. What both GPU backends share
// is tested in gpu/test_gpu_backends.cpp. Under CI an OpenGL that does not come up fails.
#include <gtest/gtest.h>

#include <cstdlib>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/bvh.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/gl/mesh_rasterizer.h>
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

// The conventional peer of geometry textures (Fig. 7): the rasterized mesh covers exactly the pixels
// whose primary ray (Camera::primaryRay) hits a triangle, by the BVH's exact ray cast, up to pixel
// centres within rounding of a silhouette edge; lit pixels are shaded within ambient..ambient + light.
TEST_F(GlBackendTest, TheMeshRasterizerCoversThePixelsWhosePrimaryRayHitsTheMesh) {
  const TriangleMesh torusMesh = makeTorus(1.0f, 0.35f, 96, 48);
  MeshRasterizer raster(torusMesh);
  const TriangleBvh<double> bvh(std::vector<Vec3d>(torusMesh.positions.begin(), torusMesh.positions.end()),
                                torusMesh.triangles);
  for (const render::Camera& camera : {render::Camera::framing(Vec3d(0), 1.4, 30, 35), render::Camera::framing(Vec3d(0), 1.4, -70, 10)}) {
    const int width = 160, height = 120;
    const Image<std::uint8_t> color = raster.render(camera, width, height);
    std::size_t hits = 0, disagreements = 0, grey = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const bool covered = color.at(x, y, 3) == 255;
        const bool hit = std::isfinite(bvh.closestHit(camera.primaryRay(x, y, width, height)).t);
        hits += hit;
        disagreements += covered != hit;
        if (covered) {
          EXPECT_GE(color.at(x, y, 0), std::uint8_t(0.18 * 255 - 1)) << x << ", " << y;
          grey += color.at(x, y, 0) != color.at(x, y, 1) || color.at(x, y, 1) != color.at(x, y, 2);
        }
      }
    EXPECT_GT(hits, std::size_t(width * height / 10));
    EXPECT_LE(disagreements, hits / 200) << "of " << hits << " hits";
    EXPECT_EQ(grey, 0u) << "the shading is grey";
  }
  EXPECT_THROW(MeshRasterizer(TriangleMesh{}), Error);
  EXPECT_THROW(raster.render(render::Camera{}, 0, 10), Error);
}

}  // namespace
}  // namespace cellrelief::gl
