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
// centres within rounding of a silhouette edge, and shades them as Lambert of the interpolated vertex
// normal under the scene's light: ambient + intensity max(0, n.l), at most 1, in grey.
TEST_F(GlBackendTest, TheMeshRasterizerCoversThePixelsWhosePrimaryRayHitsTheMesh) {
  const TriangleMesh torusMesh = makeTorus(1.0f, 0.35f, 96, 48);
  MeshRasterizer raster(torusMesh);
  const TriangleBvh<double> bvh(std::vector<Vec3d>(torusMesh.positions.begin(), torusMesh.positions.end()),
                                torusMesh.triangles);
  const std::vector<Vec3f> normals = torusMesh.normals.empty() ? computeVertexNormals(torusMesh) : torusMesh.normals;
  const render::DirectionalLight light;
  const render::Scene defaults;
  const Vec3d towards = glm::normalize(Vec3d(light.direction));
  for (const render::Camera& camera : {render::Camera::framing(Vec3d(0), 1.4, 30, 35), render::Camera::framing(Vec3d(0), 1.4, -70, 10)}) {
    const int width = 160, height = 120;
    const Image<std::uint8_t> color = raster.render(camera, width, height);
    std::size_t hits = 0, disagreements = 0, grey = 0, shadedOff = 0, shaded = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const bool covered = color.at(x, y, 3) == 255;
        const Hit<double> h = bvh.closestHit(camera.primaryRay(x, y, width, height));
        const bool hit = std::isfinite(h.t);
        hits += hit;
        disagreements += covered != hit;
        if (covered) grey += color.at(x, y, 0) != color.at(x, y, 1) || color.at(x, y, 1) != color.at(x, y, 2);
        if (covered && hit) {
          const Vec3u t = torusMesh.triangles[h.primId];
          const Vec3d n = glm::normalize((1 - h.u - h.v) * Vec3d(normals[t.x]) + h.u * Vec3d(normals[t.y]) +
                                         h.v * Vec3d(normals[t.z]));
          const double expected = 255 * std::min(1.0, double(defaults.ambient.x) +
                                                          double(light.intensity) * std::max(0.0, glm::dot(n, towards)));
          ++shaded;
          shadedOff += std::abs(double(color.at(x, y, 0)) - expected) > 3;
        }
      }
    EXPECT_GT(hits, std::size_t(width * height / 10));
    EXPECT_LE(disagreements, hits / 200) << "of " << hits << " hits";
    EXPECT_EQ(grey, 0u) << "the shading is grey";
    EXPECT_LE(shadedOff, shaded / 100) << "pixels more than 3 levels from Lambert, of " << shaded;
  }
  EXPECT_THROW(MeshRasterizer(TriangleMesh{}), Error);
  EXPECT_THROW(raster.render(render::Camera{}, 0, 10), Error);
}

}  // namespace
}  // namespace cellrelief::gl
