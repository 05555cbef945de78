// SPDX-License-Identifier: MIT
// Numerical stability and bad input of the indirection module: near-vertical steps (the box and
// cube-well reliefs of the paper's figure 10) and noise converge without NaN or flipped cells;
// constant, tiny and missing maps and absurd grid sizes are clear errors, also on the command line,
// which then leaves no output file behind.
#include <cstdlib>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <cellrelief/indirection/distortion.h>
#include <cellrelief/indirection/indirection_map.h>
#include <cellrelief/indirection/springs.h>

#include "indirection/test_support_indirection.h"

namespace cellrelief {
namespace {

using namespace indirection;

void expectStableAndFlipFree(const ReliefMap& relief, int g, const char* what, bool lowers = true) {
  SpringOptions o;
  o.gridSize = g;
  o.maxIterations = 600;
  SpringReport report;
  const Grid grid = relaxSprings(relief, o, {}, &report);
  ASSERT_TRUE(grid.isFinite()) << what;
  const Distortion d = measureDistortion(grid, relief);
  EXPECT_EQ(d.flippedCells, 0u) << what;
  EXPECT_TRUE(std::isfinite(d.l2Stretch) && std::isfinite(d.angleMax)) << what;
  if (lowers) EXPECT_LT(d.l2Stretch, measureDistortion(Grid(g), relief).l2Stretch) << what;
  const Image<float> I = indirectionMap(grid, 128, 128);
  for (float x : I.levelData()) ASSERT_TRUE(std::isfinite(x)) << what;
  std::printf("%-18s g=%d: %d iterations, converged %d, L2 %.4f, angle max %.3f, flips %zu\n", what,
              g, report.iterations, int(report.converged), d.l2Stretch, d.angleMax,
              d.flippedCells);
}

TEST(IndirectionStress, NearVerticalStepsConvergeWithoutNaNOrFlips) {
  // 128 texels and a height of 0.3: the walls rise 0.3 over one texel (slope ~38).
  expectStableAndFlipFree(test::boxRelief(128, 0.3f), 64, "box");
  expectStableAndFlipFree(test::boxRelief(128, 0.3f, true), 64, "cube well");
  // Taller than wide: a height of 2 tile widths.
  expectStableAndFlipFree(test::boxRelief(64, 2.0f), 32, "tall box");
}

TEST(IndirectionStress, NoiseConvergesWithoutNaNOrFlips) {
  // On noise the paper's in-plane forces need not lower distortion (docs/indirection.md); they
  // must stay finite and flip-free.
  expectStableAndFlipFree(test::noiseRelief(64, 0.2f, 20, 7), 32, "fine noise", false);
  expectStableAndFlipFree(test::noiseRelief(64, 1.0f, 63, 9), 64, "texel noise x1", false);
}

TEST(IndirectionStress, RealStepHeightMaps) {
  for (const char* name : {"learnopengl/toy_box_disp.png", "pom_dxsdk/four_NM_height.tga"}) {
    const auto path = test::heightmap(name);
    CELLRELIEF_REQUIRE_FILE(path);
    expectStableAndFlipFree(downsample(loadReliefMap(path, {0.2f}), 64), 32, name);
  }
}

TEST(IndirectionStress, BadParametersAreClearErrors) {
  const ReliefMap relief = test::noiseRelief(16, 0.1f, 3, 1);
  for (int g : {0, 1, -5, 100000}) {
    SpringOptions o;
    o.gridSize = g;
    try {
      relaxSprings(relief, o);
      ADD_FAILURE() << "g = " << g << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("grid size"), std::string::npos) << e.what();
    }
  }
  SpringOptions o;
  o.forceOrder = 0;
  EXPECT_THROW(relaxSprings(relief, o), Error);
  o = {};
  o.maxStepFraction = 2;
  EXPECT_THROW(relaxSprings(relief, o), Error);
  EXPECT_THROW(indirectionMap(Grid(4), 0, 10), Error);
  EXPECT_THROW(ReliefMap(2, 1, {0, 1}, 1.0f), Error);
  EXPECT_THROW(loadReliefMap(test::heightmap("does/not/exist.png")), Error);
}

// ---- the command line ---------------------------------------------------------------------------

using Result = test::CliResult;

Result run(const std::string& args, const test::TempDir&) { return test::runCli(args); }

TEST(IndirectionCli, BadInputExitsOneAndLeavesNoOutput) {
  test::TempDir dir;
  io::writePng(Image<std::uint8_t>(16, 16, 1, 128), dir / "constant.png");
  io::writePng(Image<std::uint8_t>(2, 1, 1, 9), dir / "tiny.png");
  test::writeBytes(dir / "garbage.png", std::string(100, 'x'));
  Image<std::uint8_t> ok(32, 32, 1);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) ok.at(x, y, 0) = std::uint8_t((x * 8) ^ (y * 8));
  io::writePng(ok, dir / "ok.png");
  const std::pair<std::string, std::string> cases[] = {
      {(dir / "absent.png").string(), "no such file"},
      {(dir / "constant.png").string(), "constant"},
      {(dir / "tiny.png").string(), "too small"},
      {(dir / "garbage.png").string(), "not a readable"},
      {(dir / "ok.png").string() + " --grid 1", "grid size"},
      {(dir / "ok.png").string() + " --grid 99999", "grid size"},
      {(dir / "ok.png").string() + " --height-scale -1", "height-scale"}};
  for (const auto& [args, words] : cases) {
    const auto out = dir / "out.png";
    const Result r = run("indirect " + args + " -o " + out.string(), dir);
    EXPECT_EQ(r.status, 1) << args << ": " << r.output;
    EXPECT_TRUE(test::hasWords(r.output, words)) << args << ": " << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << args;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
      EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
  // And the good one works, writing the map and its scale/bias.
  const Result good = run("indirect " + (dir / "ok.png").string() + " --grid 16 -o " +
                          (dir / "out.png").string(), dir);
  EXPECT_EQ(good.status, 0) << good.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out.png.json"));
  // Pre-warp a texture through the same run; a missing texture fails before anything is written.
  const Result warped = run("indirect " + (dir / "ok.png").string() + " --grid 16 -o " +
                                (dir / "o2.png").string() + " --prewarp " + (dir / "ok.png").string() +
                                " --prewarp-out " + (dir / "warped.png").string(), dir);
  EXPECT_EQ(warped.status, 0) << warped.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "warped.png"));
  const Result noTexture = run("indirect " + (dir / "ok.png").string() + " -o " +
                                   (dir / "o3.png").string() + " --prewarp " +
                                   (dir / "absent.png").string() + " --prewarp-out " +
                                   (dir / "w3.png").string(), dir);
  EXPECT_EQ(noTexture.status, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "o3.png"));
}

}  // namespace
}  // namespace cellrelief
