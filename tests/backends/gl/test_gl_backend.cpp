// SPDX-License-Identifier: MIT
// What is particular to the OpenGL backend: it compiles its GLSL at run time, so a broken shader
// (CELLRELIEF_SHADER_OVERRIDE) is an error with the driver's log. What both GPU backends share
// is tested in gpu/test_gpu_backends.cpp. Under CI an OpenGL that does not come up fails.
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

}  // namespace
}  // namespace cellrelief::gl
