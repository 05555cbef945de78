// SPDX-License-Identifier: MIT
// The `cellrelief` program as a user runs it: exit codes, messages on bad input, help, version.
#include <array>
#include <cmath>
#include <cstdio>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <cellrelief/core/procedural.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/polycube.h>

#include "test_support.h"

namespace cellrelief {
namespace {

using Result = test::CliResult;

Result run(const std::string& args, const std::string& prefix = "") { return test::runCli(args, prefix); }

TEST(Cli, VersionAndHelpAtEveryLevel) {
  const Result version = run("--version");
  EXPECT_EQ(version.status, 0);
  EXPECT_TRUE(test::hasWords(version.output, "cellrelief 0.")) << version.output;
  for (const char* level : {"", "info ", "demo "}) {
    const Result help = run(std::string(level) + "--help");
    EXPECT_EQ(help.status, 0) << level;
    EXPECT_TRUE(test::hasWords(help.output, "Usage")) << help.output;
  }
  EXPECT_NE(run("").status, 0);  // a subcommand is required
  const Result unknown = run("frobnicate");
  EXPECT_NE(unknown.status, 0);
}

TEST(Cli, BadInputGivesAClearErrorAndNonZeroExit) {
  test::TempDir dir;
  test::writeBytes(dir / "empty.ply", "");
  test::writeBytes(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  test::writeBytes(dir / "oor.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n");
  test::writeBytes(dir / "points.obj", "v 0 0 0\nv 1 0 0\n");
  test::writeBytes(dir / "garbage.png", std::string(300, '?'));
  const std::pair<std::string, std::string> cases[] = {
      {"absent.obj", "no such file"},      {"empty.ply", "file is empty"},
      {"nan.obj", "not a finite number"},  {"oor.off", "refers to vertex 5"},
      {"points.obj", "no faces"},          {"garbage.png", "not a readable"}};
  for (const auto& [file, words] : cases) {
    const Result r = run("info " + (dir / file).string());
    EXPECT_EQ(r.status, 1) << file << ": " << r.output;
    EXPECT_TRUE(test::hasWords(r.output, (dir / file).string())) << r.output;
    EXPECT_TRUE(test::hasWords(r.output, words)) << r.output;
  }
}

TEST(Cli, InfoReportsTopology) {
  const auto bunny = test::dataDir() / "meshes/medium/stanford-bunny__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(bunny);
  const Result r = run("info " + bunny.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(test::hasWords(r.output, "5 loops")) << r.output;  // the bunny's five holes
  EXPECT_TRUE(test::hasWords(r.output, "1113 unreferenced")) << r.output;
  const auto image = test::dataDir() / "heightmaps/sponza/lion_bump.png";
  CELLRELIEF_REQUIRE_FILE(image);
  const Result i = run("info " + image.string());
  ASSERT_EQ(i.status, 0) << i.output;
  EXPECT_TRUE(test::hasWords(i.output, "1024 x 1024")) << i.output;
  EXPECT_TRUE(test::hasWords(i.output, "bit depth  8")) << i.output;
}

TEST(Cli, DemoWritesTheBuiltInModel) {
  test::TempDir dir;
  const Result r = run("demo --tube-segments 40 -o " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* file : {"displaced_torus.ply", "displaced_torus.png", "displaced_torus.crm",
                           "displaced_torus_relief.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / file)) << file;
  EXPECT_TRUE(test::hasWords(r.output, "5120 (from")) << r.output;  // 64 x 40 x 2
  EXPECT_TRUE(test::hasWords(r.output, "genus                 1")) << r.output;
  EXPECT_TRUE(test::hasWords(r.output, "RMS error")) << r.output;
  const Result own = run("demo " + (dir / "out/displaced_torus.ply").string() + " -o " +
                         (dir / "own").string());
  EXPECT_EQ(own.status, 0) << own.output;
  const Result bad = run("demo " + (dir / "absent.ply").string() + " -o " + (dir / "x").string());
  EXPECT_EQ(bad.status, 1);
  EXPECT_TRUE(test::hasWords(bad.output, "no such file")) << bad.output;
}

TEST(Cli, CellsReportsCountsCasesAndOcclusion) {
  const auto mesh = test::dataDir() / "meshes/small/fertility_9k__libigl-tutorial-data.off";
  CELLRELIEF_REQUIRE_FILE(mesh);
  test::TempDir dir;
  const Result r = run("cells " + mesh.string() + " --grid 16 --dump " + (dir / "cells.ply").string() +
                       " --preview " + (dir / "cells.png").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* words : {"N = 16", "grey 531", "base cases", "3b", "axial", "occlusion", "time"})
    EXPECT_TRUE(test::hasWords(r.output, words)) << words << " not in " << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "cells.ply"));
  EXPECT_TRUE(std::filesystem::exists(dir / "cells.png"));
  const Result automatic = run("cells " + mesh.string() + " --max-grid 32");
  ASSERT_EQ(automatic.status, 0) << automatic.output;
  EXPECT_TRUE(test::hasWords(automatic.output, "N =    1")) << automatic.output;
  EXPECT_TRUE(test::hasWords(automatic.output, "chosen N")) << automatic.output;
  for (const std::string bad : {"--grid 0", "--grid 5000", "--grid many"}) {
    const Result e = run("cells " + mesh.string() + " " + bad);
    EXPECT_NE(e.status, 0) << bad;
    EXPECT_TRUE(test::hasWords(e.output, "error")) << e.output;
  }
}

// `polycube`: automatic, or from a cube file; a bad cube file or a polycube of the wrong genus is
// refused, naming the file, and writes nothing.
TEST(Cli, PolycubeWritesTheDomainAndRefusesBadPolycubes) {
  const auto mesh = test::dataDir() / "meshes/small/3holes__cinolib.obj";
  CELLRELIEF_REQUIRE_FILE(mesh);
  test::TempDir dir;
  const Result r = run("polycube " + mesh.string() + " -o " + (dir / "auto").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* words : {"chosen N = 10", "genus 3 (mesh: 3)", "vertex cases", "5:", "optimized", "extended-mips"})
    EXPECT_TRUE(test::hasWords(r.output, words)) << words << " not in " << r.output;
  for (const char* file :
       {"polycube.txt", "polycube_surface.ply", "polycube_cases.png", "mesh_texture.obj", "distortion.csv", "polycube_map.png",
        "polycube_texture.png", "polycube_render.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / "auto" / file)) << file;
  EXPECT_FALSE(std::filesystem::exists(dir / "auto" / "polycube_render_lod.png")) << "only the normals signal has one";
  // The map: one texture position per vertex, and the table's rows with no flipped triangle left.
  const std::string obj = test::readBytes(dir / "auto" / "mesh_texture.obj");
  std::size_t vertices = 0, textures = 0;
  for (std::size_t at = 0; (at = obj.find('\n', at)) != std::string::npos; ++at) {
    vertices += obj.compare(at + 1, 2, "v ") == 0;
    textures += obj.compare(at + 1, 3, "vt ") == 0;
  }
  EXPECT_GT(vertices, 1000u);
  EXPECT_EQ(textures, vertices);
  const std::string table = test::readBytes(dir / "auto" / "distortion.csv");
  EXPECT_TRUE(test::hasWords(table, "area_distortion,angle_distortion,stretch_efficiency,flipped")) << table;
  EXPECT_TRUE(test::hasWords(table, ",optimized,")) << table;
  EXPECT_NE(table.find(",0,", table.find("optimized")), std::string::npos) << table;
  const Result badEnergy = run("polycube " + mesh.string() + " --energy tutte -o " + (dir / "tutte").string());
  EXPECT_NE(badEnergy.status, 0);
  EXPECT_TRUE(test::hasWords(badEnergy.output, "tutte")) << badEnergy.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "tutte"));
  const Result badCoarse = run("polycube " + mesh.string() + " --coarse -5 -o " + (dir / "coarse").string());
  EXPECT_NE(badCoarse.status, 0);
  EXPECT_TRUE(test::hasWords(badCoarse.output, "--coarse")) << badCoarse.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "coarse"));
  for (const auto& [signal, words] : {std::pair{"bumps", "not grid, normals"}, std::pair{"color", "no vertex colours"}}) {
    const Result badSignal =
        run("polycube " + mesh.string() + " --signal " + signal + " -o " + (dir / "signal").string());
    EXPECT_EQ(badSignal.status, 1) << badSignal.output;
    EXPECT_TRUE(test::hasWords(badSignal.output, words)) << badSignal.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "signal"));
  }
  // The written cube file is accepted back; the normals signal renders a level of detail too.
  const Result again = run("polycube " + mesh.string() + " --cubes " + (dir / "auto" / "polycube.txt").string() +
                           " --signal normals --texels 8 -o " + (dir / "again").string());
  EXPECT_EQ(again.status, 0) << again.output;
  EXPECT_TRUE(test::hasWords(again.output, "8 texels per squarelet")) << again.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "again" / "polycube_render_lod.png"));
  // `render` takes the folder: the mesh textured through its map, on the CPU and on a GPU backend.
  for (const char* backend : {"cpu", "vulkan"}) {
    const auto png = dir / (std::string("render_") + backend + ".png");
    const Result rendered =
        run("render " + (dir / "again").string() + " --backend " + backend + " --size 96x96 -o " + png.string());
    if (backend != std::string("cpu") && !test::inCI() && rendered.status != 0) continue;  // no Vulkan here
    EXPECT_EQ(rendered.status, 0) << rendered.output;
    EXPECT_TRUE(test::hasWords(rendered.output, "polycube map")) << rendered.output;
    EXPECT_TRUE(test::hasWords(rendered.output, "(normals)")) << rendered.output;
    EXPECT_TRUE(std::filesystem::exists(png));
  }
  // A T2 that is not this polycube's is refused, naming the file.
  std::filesystem::copy_file(dir / "auto" / "polycube_cases.png", dir / "again" / "polycube_texture.png",
                             std::filesystem::copy_options::overwrite_existing);
  const Result wrongT2 = run("render " + (dir / "again").string() + " -o " + (dir / "wrong.png").string());
  EXPECT_EQ(wrongT2.status, 1) << wrongT2.output;
  EXPECT_TRUE(test::hasWords(wrongT2.output, "polycube_texture.png")) << wrongT2.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "wrong.png"));
  test::writeBytes(dir / "box.txt", "0 0 0\n1 0 0\n");
  test::writeBytes(dir / "edge.txt", "0 0 0\n1 1 0\n");
  test::writeBytes(dir / "bad.txt", "0 0 0\n1 zero 0\n");
  const std::pair<std::string, std::string> cases[] = {
      {"box.txt", "genus 0, the mesh 3"}, {"edge.txt", "not a 2-manifold"}, {"bad.txt", "line 2"}};
  for (const auto& [file, words] : cases) {
    const Result e = run("polycube " + mesh.string() + " --cubes " + (dir / file).string() + " -o " +
                         (dir / ("out_" + file)).string());
    EXPECT_EQ(e.status, 1) << file << ": " << e.output;
    EXPECT_TRUE(test::hasWords(e.output, (dir / file).string())) << e.output;
    EXPECT_TRUE(test::hasWords(e.output, words)) << e.output;
    EXPECT_FALSE(std::filesystem::exists(dir / ("out_" + file))) << file;
  }
}

// A cube file may hold a case-6b vertex: four cubes in a skew path, whose vertex (1, 1, 1) is
// one, under a mesh that is their surface refined and warped. The command maps it without a fold,
// writes everything, and `render` draws the folder.
/// Four cubes in a skew path (a saddle vertex of case 6b), their surface refined and warped.
void writeWarpedSkewPath(const std::filesystem::path& file) {
  TriangleMesh mesh =
      polycube::Polycube(std::vector<Vec3i>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}}).surfaceMesh();
  splitTrianglesInFour(mesh, 2, [](const Vec3f& a, const Vec3f& b) { return 0.5f * (a + b); });
  for (Vec3f& x : mesh.positions)
    x += 0.08f * Vec3f(std::sin(2.3f * x.y + 0.4f), std::sin(1.9f * x.z + 1.1f), std::sin(2.7f * x.x + 2.0f));
  io::writeMesh(mesh, file);
}

TEST(Cli, PolycubeTakesACubeFileWithACase6bVertex) {
  test::TempDir dir;
  writeWarpedSkewPath(dir / "skew.obj");
  test::writeBytes(dir / "skew.txt", "frame 0 0 0 1\n0 0 0\n1 0 0\n1 1 0\n1 1 1\n");
  const Result r = run("polycube " + (dir / "skew.obj").string() + " --cubes " + (dir / "skew.txt").string() +
                       " --texels 8 -o " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(test::hasWords(r.output, "6b: 1")) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "polycube_render.png"));
  const Result rendered = run("render " + (dir / "out").string() + " --backend vulkan --size 64x64 -o " +
                              (dir / "render.png").string());
  if (rendered.status != 0 && !test::inCI()) return;  // no Vulkan here
  EXPECT_EQ(rendered.status, 0) << rendered.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "render.png"));
}

// The automatic polycube of the skew path keeps its 6b vertex; --remove-case-6b toggles a cube
// to remove it, and is refused with a cube file (which it would not change).
TEST(Cli, PolycubeRemovesCase6bVerticesWhenAsked) {
  test::TempDir dir;
  writeWarpedSkewPath(dir / "skew.obj");
  const std::string common = "polycube " + (dir / "skew.obj").string() + " --texels 8 --sweeps 50";
  const Result kept = run(common + " -o " + (dir / "kept").string());
  ASSERT_EQ(kept.status, 0) << kept.output;
  EXPECT_TRUE(test::hasWords(kept.output, "0 toggled for case 6b), 1 case-6b vertices")) << kept.output;
  EXPECT_TRUE(test::hasWords(kept.output, "6b: 1")) << kept.output;
  const Result removed = run(common + " --remove-case-6b -o " + (dir / "removed").string());
  ASSERT_EQ(removed.status, 0) << removed.output;
  EXPECT_TRUE(test::hasWords(removed.output, "1 toggled for case 6b), 0 case-6b vertices")) << removed.output;
  EXPECT_TRUE(test::hasWords(removed.output, "6b: 0")) << removed.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "removed" / "polycube.txt"));
  const Result refused = run(common + " --remove-case-6b --cubes " + (dir / "kept" / "polycube.txt").string() +
                             " -o " + (dir / "refused").string());
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_TRUE(test::hasWords(refused.output, "--remove-case-6b changes an automatic polycube only")) << refused.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "refused"));
}

// Flat meshes convert (as a thin closed slab), and so do surfaces lying in planes of the grid
// (three crossing coordinate planes): a model whose error is measured and finite. A "mesh" whose
// triangles have no area at all is refused: a clear error naming the file, exit 1 and no model,
// never an empty model reported with "rms inf%".
// Under AddressSanitizer, runs that load the GPU drivers do not check for leaks: Mesa's llvmpipe
// and lavapipe leak 112 bytes in a module they unload at exit, which LeakSanitizer can neither name
// nor suppress. Every other check of the sanitizers stays on.
#if defined(__SANITIZE_ADDRESS__)
const std::string kDrivers = "ASAN_OPTIONS=detect_leaks=0 ";
#else
const std::string kDrivers;
#endif

TEST(Cli, GeotexConvertsMeshesAndHeightMapsAndRendersThem) {
  const auto spot = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  const auto dem = test::dataDir() / "heightmaps/pom_dxsdk/rocks_NM_height.tga";
  CELLRELIEF_REQUIRE_FILE(spot);
  CELLRELIEF_REQUIRE_FILE(dem);
  test::TempDir dir;
  const Result mesh = run("geotex " + spot.string() + " -o " + (dir / "spot.cgt").string() +
                          " --charts 40 --texels 32 --picture " + (dir / "charts.png").string());
  ASSERT_EQ(mesh.status, 0) << mesh.output;
  for (const char* words : {"charts 40 (asked 40, 1 components)", "accuracy", "per million rays", "wrote"})
    EXPECT_TRUE(test::hasWords(mesh.output, words)) << words << " not in " << mesh.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "charts.png"));
  const Result image = run("geotex " + dem.string() + " -o " + (dir / "rocks.cgt").string() + " --extent 2,2,0.1");
  ASSERT_EQ(image.status, 0) << image.output;
  EXPECT_TRUE(test::hasWords(image.output, "one chart of 2 x 2 x 0.1")) << image.output;
  for (const char* model : {"spot.cgt", "rocks.cgt"}) {
    const Result r = run("render " + (dir / model).string() + " -o " + (dir / "r.png").string() +
                         " --size 64x48 --backend cpu");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(test::hasWords(r.output, "geotex model")) << r.output;
    const auto picture = std::get<Image<std::uint8_t>>(io::readImage(dir / "r.png").pixels);
    int covered = 0;  // pixels that are not the white background
    for (int y = 0; y < picture.height(); ++y)
      for (int x = 0; x < picture.width(); ++x) covered += picture.at(x, y, 0) != 255 || picture.at(x, y, 1) != 255;
    EXPECT_GT(covered, 64 * 48 / 20) << model;
  }
  // Every backend that runs here on the charts, against the CPU reference.
  const Result compare = run("compare-backends " + (dir / "spot.cgt").string() + " --size 48x32 -o " +
                             (dir / "compare").string(), kDrivers);
  ASSERT_EQ(compare.status, 0) << compare.output;
  EXPECT_TRUE(test::hasWords(compare.output, "side_by_side.png")) << compare.output;
  test::writeBytes(dir / "line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  const std::pair<std::string, std::string> cases[] = {
      {"geotex " + spot.string() + " -o " + (dir / "x.crm").string(), "must end in .cgt"},
      {"geotex " + (dir / "line.obj").string() + " -o " + (dir / "x.cgt").string(), "zero area"},
      {"geotex " + spot.string() + " -o " + (dir / "x.cgt").string() + " --texels 100", "power of two"},
      {"geotex " + spot.string() + " -o " + (dir / "x.cgt").string() + " --metric l3", "not l21 or l2"},
      {"geotex " + dem.string() + " -o " + (dir / "x.cgt").string() + " --extent 1,2", "--extent '1,2'"},
      {"render " + (dir / "line.obj").string() + ".cgt -o " + (dir / "x.png").string(), "no such file"}};
  for (const auto& [args, words] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.output;
    EXPECT_TRUE(test::hasWords(r.output, words)) << args << ": " << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "x.cgt"));
  EXPECT_FALSE(std::filesystem::exists(dir / "x.crm"));
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

TEST(Cli, FlatMeshesAndSurfacesInGridPlanesConvert) {
  test::TempDir dir;
  for (const char* name : {"degtri_four__cgal.off", "degtri_nullface__cgal.off", "degtri_sliding__cgal.off",
                           "degenerated__libigl-tests-data.obj"}) {
    const auto mesh = test::dataDir() / "meshes/robustness" / name;
    CELLRELIEF_REQUIRE_FILE(mesh);
    const auto out = dir / (std::string(name) + ".crm");
    const Result r = run("convert " + mesh.string() + " -o " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_FALSE(test::hasWords(r.output, "inf")) << r.output;
    EXPECT_FALSE(test::hasWords(r.output, "nan")) << r.output;
    const bool flat = std::string(name).starts_with("degtri");
    EXPECT_EQ(test::hasWords(r.output, "flat mesh modelled as a closed slab"), flat) << r.output;
    // The reconstruction is within 1% of the diagonal of the input (RMS), and the file reads back.
    const std::string words = test::squeezeSpaces(r.output);
    const std::size_t at = words.find("error rms ");
    ASSERT_NE(at, std::string::npos) << r.output;
    EXPECT_LT(std::stod(words.substr(at + 10)), 1.0) << r.output;
    EXPECT_EQ(run("render " + out.string() + " -o " + (dir / (std::string(name) + ".png")).string() +
                  " --backend cpu --size 64x64").status, 0);
  }
  // Collinear triangles: no area, no surface.
  const auto line = dir / "line.obj";
  test::writeBytes(line, "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n");
  const auto out = dir / "line.crm";
  const Result r = run("convert " + line.string() + " -o " + out.string());
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(test::hasWords(r.output, line.string())) << r.output;
  EXPECT_FALSE(test::hasWords(r.output, "inf%")) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, ConvertAndReconstruct) {
  const auto mesh = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  const auto texture = test::dataDir() / "meshes/small/spot_texture__cinolib.png";
  CELLRELIEF_REQUIRE_FILE(mesh);
  CELLRELIEF_REQUIRE_FILE(texture);
  test::TempDir dir;
  const Result r = run("convert " + mesh.string() + " -o " + (dir / "spot.crm").string() +
                       " --grid 8 --texels 17 --texture " + texture.string() + " --atlas " +
                       (dir / "atlas").string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* words : {"N = 8", "layers of 17 x 17", "colors", "bytes", "time", "error         rms",
                            "centre fewest-crossings"})
    EXPECT_TRUE(test::hasWords(r.output, words)) << words << " not in " << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "atlas/color.png"));
  // The paper's centres, by name: no cell is moved.
  const Result paper = run("convert " + mesh.string() + " -o " + (dir / "paper.crm").string() +
                           " --grid 8 --texels 17 --centre cell --no-error");
  ASSERT_EQ(paper.status, 0) << paper.output;
  EXPECT_TRUE(test::hasWords(paper.output, "centre cell: 0 cells moved")) << paper.output;
  const Result back = run("reconstruct " + (dir / "spot.crm").string() + " -o " +
                          (dir / "spot.ply").string() + " --lod 1");
  ASSERT_EQ(back.status, 0) << back.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "spot.ply"));
  // A closed input gives a closed reconstruction by default; the paper's per-face one has cracks.
  EXPECT_TRUE(test::hasWords(back.output, "closed, 0 boundary edges")) << back.output;
  const Result perFace = run("reconstruct " + (dir / "spot.crm").string() + " -o " +
                             (dir / "spot_faces.ply").string() + " --method per-face");
  ASSERT_EQ(perFace.status, 0) << perFace.output;
  EXPECT_TRUE(test::hasWords(perFace.output, "open,")) << perFace.output;
  const Result badMethod = run("reconstruct " + (dir / "spot.crm").string() + " -o " +
                               (dir / "spot_bad.ply").string() + " --method marching");
  EXPECT_NE(badMethod.status, 0);
  EXPECT_TRUE(test::hasWords(badMethod.output, "per-face")) << badMethod.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "spot_bad.ply"));
  const Result bounded = run("convert " + mesh.string() + " -o " + (dir / "b.crm").string() +
                             " --max-error 0.002 --no-error");
  ASSERT_EQ(bounded.status, 0) << bounded.output;
  EXPECT_TRUE(test::hasWords(bounded.output, "meets the bound")) << bounded.output;
  // Bad input: a clear error, non-zero exit, no output file.
  test::writeBytes(dir / "broken.crm", test::readBytes(dir / "spot.crm").substr(0, 100));
  const std::pair<std::string, std::string> cases[] = {
      {"reconstruct " + (dir / "broken.crm").string() + " -o " + (dir / "x.ply").string(), "truncated"},
      {"reconstruct " + (dir / "spot.crm").string() + " -o " + (dir / "y.ply").string() + " --lod 9", "out of range"},
      {"convert " + mesh.string() + " -o " + (dir / "z.crm").string() + " --grid 0", "--grid"},
      {"convert " + mesh.string() + " -o " + (dir / "v.crm").string() + " --centre middle", "fewest-crossings"},
      {"convert " + (dir / "absent.obj").string() + " -o " + (dir / "w.crm").string(), "no such file"}};
  for (const auto& [args, words] : cases) {
    const Result e = run(args);
    EXPECT_NE(e.status, 0) << args;
    EXPECT_TRUE(test::hasWords(e.output, words)) << e.output;
  }
  for (const char* name : {"x.ply", "y.ply", "z.crm", "v.crm", "w.crm"}) EXPECT_FALSE(std::filesystem::exists(dir / name)) << name;
}

TEST(Cli, RenderWritesTheImageAndItsBuffersAndRefusesBadInput) {
  const auto spot = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(spot);
  test::TempDir dir;
  const Result ok = run("render " + spot.string() + " -o " + (dir / "c.png").string() + " --size 96x64 --depth " +
                        (dir / "d.png").string() + " --normals " + (dir / "n.png").string() +
                        " --camera 200,-10,35 --backend cpu");
  ASSERT_EQ(ok.status, 0) << ok.output;
  EXPECT_TRUE(test::hasWords(ok.output, "rendered      96x64")) << ok.output;
  for (const char* name : {"c.png", "d.png", "n.png"}) EXPECT_TRUE(std::filesystem::exists(dir / name)) << name;
  const std::pair<std::string, std::string> cases[] = {
      {"render absent.crm -o x.png", "no such file"},
      {"render " + spot.string() + " -o x.png --size 12by3", "--size '12by3'"},
      {"render " + spot.string() + " -o x.png --size 0x10", "expected WxH"},
      {"render " + spot.string() + " -o x.png --camera 1,2,3,4", "--camera '1,2,3,4'"},
      {"render " + spot.string() + " -o x.png --camera 1,x", "'x' is not a number"},
      {"render " + spot.string() + " -o x.png --camera 35,20,0", "field of view"},
      {"render " + spot.string() + " -o x.png --backend metal", "valid: auto, cpu, opengl, vulkan"},
      {"render " + spot.string() + " -o x.png --backend vulkan --device no-such-gpu-42", "no-such-gpu-42"},
      {"render " + spot.string() + " -o x.png --backend cpu --device llvmpipe", "is not Vulkan"},
      {"bench nosuch", "no such benchmark"},
      {"bench nosuch", "built here:"}};
  for (const auto& [args, words] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.output;
    EXPECT_TRUE(test::hasWords(r.output, words)) << args << ": " << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists("x.png"));
}

/// Pixels whose RGB differs between two PNGs of one size (alpha is ignored: a window has none).
int differingPixels(const std::filesystem::path& a, const std::filesystem::path& b) {
  const auto ia = std::get<Image<std::uint8_t>>(io::readImage(a).pixels);
  const auto ib = std::get<Image<std::uint8_t>>(io::readImage(b).pixels);
  if (ia.width() != ib.width() || ia.height() != ib.height()) return -1;
  int count = 0;
  for (int y = 0; y < ia.height(); ++y)
    for (int x = 0; x < ia.width(); ++x) {
      bool same = true;
      for (int c = 0; c < 3; ++c) same &= ia.at(x, y, c) == ib.at(x, y, c);
      count += !same;
    }
  return count;
}


TEST(Cli, RenderAndCompareBackendsOnTheGpuBackends) {
  const auto spot = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(spot);
  test::TempDir dir;
  const Result cpu = run("render " + spot.string() + " -o " + (dir / "cpu.png").string() + " --size 96x64 --backend cpu");
  ASSERT_EQ(cpu.status, 0) << cpu.output;
  // The mesh converted once with convert's defaults: render's own conversion of the mesh gives the
  // same model, so every render below of the file equals the CPU's render of the mesh.
  const std::string model = (dir / "spot.crm").string();
  const Result converted = run("convert " + spot.string() + " -o " + model);
  ASSERT_EQ(converted.status, 0) << converted.output;
  for (const auto& [backend, described] : {std::pair{"opengl", "on OpenGL"}, std::pair{"vulkan", "on Vulkan"}}) {
    const std::string png = (dir / (std::string(backend) + ".png")).string();
    const Result r = run("render " + model + " -o " + png + " --size 96x64 --backend " + backend, kDrivers);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(test::hasWords(r.output, described)) << r.output;
    EXPECT_EQ(differingPixels(png, dir / "cpu.png"), 0) << backend;
  }
  // The entry as asked, and the same picture by either; the default on these CPU devices rasterizes.
  for (const auto& [entry, said] : {std::pair{"compute", "compute entry"}, std::pair{"rasterized", "rasterized entry"},
                                    std::pair{"fastest", "rasterized entry"}}) {
    const std::string png = (dir / (std::string("vulkan_") + entry + ".png")).string();
    const Result r =
        run("render " + model + " -o " + png + " --size 96x64 --backend vulkan --entry " + entry, kDrivers);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(test::hasWords(r.output, said)) << r.output;
    EXPECT_EQ(differingPixels(png, dir / "cpu.png"), 0) << entry;
  }
  const Result badEntry = run("render " + model + " -o " + (dir / "x.png").string() + " --entry fragment");
  EXPECT_NE(badEntry.status, 0) << badEntry.output;
  EXPECT_TRUE(test::hasWords(badEntry.output, "--entry")) << badEntry.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
  const Result cmp = run("compare-backends " + model + " --size 80x60 --repeat 1 --entry compute -o " +
                             (dir / "cmp").string(),
                         kDrivers);
  ASSERT_EQ(cmp.status, 0) << cmp.output;
  for (const char* words : {"cpu ", "opengl ", "vulkan ", "Mrays/s", "mask", "compute entry"})
    EXPECT_TRUE(test::hasWords(cmp.output, words)) << words;
  EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / "side_by_side.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / "diff_cpu_opengl.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "cmp" / "diff_cpu_vulkan.png"));
  const Result bad = run("compare-backends absent.crm -o " + (dir / "bad").string());
  EXPECT_EQ(bad.status, 1) << bad.output;
  EXPECT_TRUE(test::hasWords(bad.output, "absent.crm")) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
}

// A height map shown by parallax occlusion mapping with the indirection map `indirect` wrote: the
// same picture on every backend, a different one without the map, and clear errors for maps that
// do not belong together.
TEST(Cli, RenderShowsAHeightMapWithItsIndirectionMapOnEveryBackend) {
  test::TempDir dir;
  Image<std::uint8_t> bumps(64, 64, 1);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      bumps.at(x, y, 0) = std::uint8_t(127.5 + 127 * std::sin(0.3 * x) * std::cos(0.25 * y));
  const std::string hm = (dir / "bumps.png").string(), map = (dir / "I.png").string();
  io::writePng(bumps, hm);
  const Result made = run("indirect " + hm + " --grid 16 --height-scale 0.15 -o " + map);
  ASSERT_EQ(made.status, 0) << made.output;
  const std::string common = " --size 96x64 --camera 20,35";
  const Result cpu = run("render " + hm + " --indirection " + map + " -o " + (dir / "cpu.png").string() + common +
                         " --backend cpu");
  ASSERT_EQ(cpu.status, 0) << cpu.output;
  EXPECT_TRUE(test::hasWords(cpu.output, "height scale 0.15, indirection")) << cpu.output;
  for (const char* backend : {"opengl", "vulkan"}) {
    const std::string png = (dir / (std::string(backend) + ".png")).string();
    const Result r = run("render " + hm + " --indirection " + map + " -o " + png + common + " --backend " + backend, kDrivers);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_LE(differingPixels(png, dir / "cpu.png"), 96 * 64 / 200) << backend;
  }
  const Result plain =
      run("render " + hm + " --height-scale 0.15 -o " + (dir / "plain.png").string() + common + " --backend cpu");
  ASSERT_EQ(plain.status, 0) << plain.output;
  EXPECT_GT(differingPixels(dir / "plain.png", dir / "cpu.png"), 96 * 64 / 60);  // measured 185
  const Result cmp = run("compare-backends " + hm + " --indirection " + map + " --size 64x48 --repeat 1 -o " +
                             (dir / "cmp").string(), kDrivers);
  ASSERT_EQ(cmp.status, 0) << cmp.output;
  EXPECT_TRUE(test::hasWords(cmp.output, "vulkan ")) << cmp.output;
  // Maps that do not belong together, and options that do not apply.
  std::filesystem::copy_file(map, dir / "lone.png");
  const auto spot = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  const std::string out = " -o " + (dir / "x.png").string() + " --backend cpu --size 8x8";
  const std::pair<std::string, std::string> cases[] = {
      {"render " + hm + " --indirection " + (dir / "absent.png").string() + out, "no such file"},
      {"render " + hm + " --indirection " + (dir / "lone.png").string() + out, "sidecar"},
      {"render " + hm + " --indirection " + map + " --height-scale 0.3" + out, "computed for height scale"},
      {"render " + hm + " --wrap sideways" + out, "--wrap takes clamp or repeat"},
      {"render " + spot.string() + " --indirection " + map + out, "apply to a height map"}};
  for (const auto& [args, words] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.output;
    EXPECT_TRUE(test::hasWords(r.output, words)) << args << ": " << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

// A height map carved into a mesh with UVs (--base-mesh): the mesh's silhouette on every backend,
// relief inside it that a plain texture lacks, and clear errors for a mesh that cannot carry it.
TEST(Cli, RenderCarvesAHeightMapIntoAMeshWithUVs) {
  const auto spot = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  const auto rocks = test::dataDir() / "heightmaps/pom_dxsdk/rocks_NM_height.tga";
  CELLRELIEF_REQUIRE_FILE(spot);
  CELLRELIEF_REQUIRE_FILE(rocks);
  test::TempDir dir;
  const std::string common = " --base-mesh " + spot.string() + " --wrap repeat --uv-scale 6 --size 96x96 --camera 30,15";
  const Result cpu = run("render " + rocks.string() + " --height-scale 0.04" + common + " -o " + (dir / "cpu.png").string() +
                         " --backend cpu");
  ASSERT_EQ(cpu.status, 0) << cpu.output;
  EXPECT_TRUE(test::hasWords(cpu.output, "carved into")) << cpu.output;
  EXPECT_TRUE(test::hasWords(cpu.output, "5856 triangles, UVs times 6")) << cpu.output;
  for (const char* backend : {"opengl", "vulkan"}) {
    const std::string png = (dir / (std::string(backend) + ".png")).string();
    const Result r = run("render " + rocks.string() + " --height-scale 0.04" + common + " -o " + png + " --backend " + backend,
                         kDrivers);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_LE(differingPixels(png, dir / "cpu.png"), 96 * 96 / 200) << backend;
  }
  // A shallower relief moves the shading and the parallax: many pixels change.
  const Result shallow = run("render " + rocks.string() + " --height-scale 0.005" + common + " -o " +
                             (dir / "shallow.png").string() + " --backend cpu");
  ASSERT_EQ(shallow.status, 0) << shallow.output;
  EXPECT_GT(differingPixels(dir / "shallow.png", dir / "cpu.png"), 96 * 96 / 20);
  // A mesh without UVs, and --base-mesh where there is no height map.
  io::writeMesh(io::readMesh(spot, {.uvs = false}), dir / "no_uvs.obj");
  const std::string out = " -o " + (dir / "x.png").string() + " --backend cpu --size 8x8";
  const std::pair<std::string, std::string> cases[] = {
      {"render " + rocks.string() + " --base-mesh " + (dir / "no_uvs.obj").string() + out, "no_uvs.obj"},
      {"render " + rocks.string() + " --base-mesh " + (dir / "absent.obj").string() + out, "absent.obj"},
      {"render " + spot.string() + " --base-mesh " + spot.string() + out, "apply to a height map"}};
  for (const auto& [args, words] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.status, 1) << args << ": " << r.output;
    EXPECT_TRUE(test::hasWords(r.output, words)) << args << ": " << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

// The viewer in a real window (Xvfb) for a few frames: its screenshot is the headless render of
// the same camera, pixel for pixel, on the CPU, OpenGL and Vulkan backends.
TEST(Cli, ViewerUnderXvfbShowsTheHeadlessRender) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    if (test::inCI()) FAIL() << "xvfb-run is missing (Debian package xvfb)";
    GTEST_SKIP() << "xvfb-run is not installed";
  }
  const auto spot = test::dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(spot);
  test::TempDir dir;
  const Result model = run("convert " + spot.string() + " -o " + (dir / "spot.crm").string());
  ASSERT_EQ(model.status, 0) << model.output;
  for (const char* backend : {"cpu", "opengl", "vulkan"}) {
    const std::string shot = (dir / (std::string(backend) + "_window.png")).string();
    const std::string headless = (dir / (std::string(backend) + "_headless.png")).string();
    const std::string common = " --size 160x120 --camera 150,15 --backend " + std::string(backend);
    const Result view = run("view " + (dir / "spot.crm").string() + common + " --frames 3 --screenshot " + shot,
                            kDrivers + "xvfb-run -a ");
    ASSERT_EQ(view.status, 0) << view.output;
    EXPECT_TRUE(test::hasWords(view.output, "frame 3:")) << view.output;
    const Result render = run("render " + (dir / "spot.crm").string() + common + " -o " + headless, kDrivers);
    ASSERT_EQ(render.status, 0) << render.output;
    EXPECT_EQ(differingPixels(shot, headless), 0) << backend;
  }
}

}  // namespace
}  // namespace cellrelief
