// SPDX-License-Identifier: MIT
// Mesh I/O on the real data: every mesh in ../shared/data loads and matches the figures that
// SOURCES.md gives for it (counted independently by a separate script); formats round-trip.
#include <gtest/gtest.h>

#include <cstring>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>

#include "test_support.h"

namespace cellrelief {
namespace {

using test::dataDir;

TEST(MeshIO, EveryMeshMatchesTheFiguresInSources) {
  const std::filesystem::path sources = dataDir() / "SOURCES.md";
  CELLRELIEF_REQUIRE_FILE(sources);
  int checked = 0;
  for (const test::SourceRow& row : test::readSources()) {
    if (!row.figures.count("V") || !io::isMeshFile(row.path)) continue;
    const std::filesystem::path path = dataDir() / row.path;
    CELLRELIEF_REQUIRE_FILE(path);
    SCOPED_TRACE(row.path);
    const TriangleMesh mesh = io::readMesh(path);
    const MeshTopology t = analyzeTopology(mesh);
    auto expect = [&](const char* key, long long actual) {
      if (row.figures.count(key)) {
        EXPECT_EQ(actual, row.figures.at(key)) << key;
      }
    };
    expect("V", static_cast<long long>(mesh.vertexCount()));
    expect("F", static_cast<long long>(mesh.sourcePolygons));
    expect("tris", static_cast<long long>(mesh.triangleCount()));
    expect("chi", t.eulerCharacteristic);
    expect("comps", static_cast<long long>(t.components));
    expect("bnd", static_cast<long long>(t.boundaryEdges));
    expect("nm-e", static_cast<long long>(t.nonManifoldEdges));
    expect("nm-v", static_cast<long long>(t.nonManifoldVertices));
    expect("zero-area", static_cast<long long>(t.degenerateTriangles));
    expect("unref", static_cast<long long>(t.unreferencedVertices));
    expect("misoriented", static_cast<long long>(t.misorientedEdges));
    if (row.figures.count("genus")) {
      ASSERT_TRUE(t.genus.has_value());
      EXPECT_EQ(*t.genus, row.figures.at("genus"));
    }
    ++checked;
  }
  EXPECT_GE(checked, 30) << "SOURCES.md lists 33 meshes";
}

TEST(MeshIO, TriangleStripsOfIgeaAreExpanded) {
  const auto path = dataDir() / "meshes/large/igea__common-3d-test-models.ply";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh m = io::readMesh(path);
  EXPECT_EQ(m.triangleCount(), 268686u);
  const MeshTopology t = analyzeTopology(m);
  EXPECT_TRUE(t.closed() && t.manifold() && t.oriented());  // strip winding alternates correctly
}

TEST(MeshIO, AttributesArriveWhenPresent) {
  const auto spot = dataDir() / "meshes/small/spot__common-3d-test-models.obj";
  const auto egea = dataDir() / "meshes/medium/egea__4AxisMilling.obj";
  CELLRELIEF_REQUIRE_FILE(spot);
  CELLRELIEF_REQUIRE_FILE(egea);
  const TriangleMesh s = io::readMesh(spot);
  ASSERT_TRUE(s.hasUVs());
  EXPECT_EQ(s.uvs.size(), 3 * s.triangleCount());
  // The extreme `vt` values of spot.obj (a few lie just outside [0, 1] in the file itself).
  Vec2f lo(1e9f), hi(-1e9f);
  for (const Vec2f& uv : s.uvs) {
    lo = glm::min(lo, uv);
    hi = glm::max(hi, uv);
  }
  EXPECT_FLOAT_EQ(lo.x, -0.0522421f);
  EXPECT_FLOAT_EQ(hi.y, 1.00065f);
  EXPECT_FALSE(s.hasNormals());
  const TriangleMesh e = io::readMesh(egea);
  EXPECT_TRUE(e.hasNormals());
  EXPECT_TRUE(e.hasUVs());
  const TriangleMesh bare = io::readMesh(egea, {.normals = false, .colors = false, .uvs = false});
  EXPECT_FALSE(bare.hasNormals() || bare.hasUVs());
}

TEST(MeshIO, PolygonsAreTriangulated) {
  const auto shelf = dataDir() / "meshes/robustness/platonic_shelf__geometry-central.obj";
  CELLRELIEF_REQUIRE_FILE(shelf);
  const TriangleMesh m = io::readMesh(shelf);
  EXPECT_EQ(m.sourcePolygons, 50u);
  EXPECT_EQ(m.triangleCount(), 80u);  // 32 triangles + 6 quads * 2 + 12 pentagons * 3
}

TEST(MeshIO, OffLayoutsOfTheHeaderWordAreRead) {
  test::TempDir dir;
  // Comments, the counts on the header line, per-vertex normal, color (integers on one line,
  // numbers 0..1 on the others) and texture coordinates, a face with its own color, and a face
  // of two corners, which is skipped.
  test::writeBytes(dir / "layout.off",
                   "# a comment before the header\n"
                   "STCNOFF 4 3 0\n"
                   "0 0 0  0 0 1  255 0 0      0.25 0.5  # integer color\n"
                   "1 0 0  0 0 1  0 1.0 0 0.5  1 0\n"
                   "\n"
                   "0 1 0  0 0 1  0 0 1.0      0 1\n"
                   "0 0 1  1 0 0  0.5 0.5 0.5  1 1\n"
                   "3 0 1 2  0.1 0.2 0.3\n"
                   "2 0 3\n"
                   "4 0 1 3 2\n");
  const TriangleMesh m = io::readMesh(dir / "layout.off");
  ASSERT_EQ(m.vertexCount(), 4u);
  EXPECT_EQ(m.triangleCount(), 3u);  // the triangle and the fanned quad
  EXPECT_EQ(m.sourcePolygons, 2u);
  ASSERT_TRUE(m.hasNormals() && m.hasColors() && m.hasUVs());
  EXPECT_EQ(m.normals[3], Vec3f(1, 0, 0));
  EXPECT_EQ(m.colors[0], Color8(255, 0, 0, 255));
  EXPECT_EQ(m.colors[1], Color8(0, 255, 0, 128));
  EXPECT_EQ(m.colors[3], Color8(128, 128, 128, 255));
  EXPECT_EQ(m.uvs[0], Vec2f(0.25f, 0.5f));  // corner 0 of triangle 0 is vertex 0
  EXPECT_EQ(m.uvs[1], Vec2f(1, 0));
  // Homogeneous positions are divided by w; w = 0 is no point.
  test::writeBytes(dir / "w.off", "4OFF\n3 1\n0 0 0 2\n2 0 0 2\n0 4 0 2\n3 0 1 2\n");
  EXPECT_EQ(io::readMesh(dir / "w.off").positions[2], Vec3f(0, 2, 0));
  test::writeBytes(dir / "w0.off", "4OFF\n3 1\n0 0 0 1\n2 0 0 0\n0 4 0 1\n3 0 1 2\n");
  try {
    io::readMesh(dir / "w0.off");
    ADD_FAILURE() << "w = 0 was read";
  } catch (const Error& e) {
    EXPECT_TRUE(std::string(e.what()).find("line 4: vertex 1 has the homogeneous coordinate w = 0") !=
                std::string::npos)
        << e.what();
  }
}

/// A binary OFF by hand: Geomview's big-endian layout, or the machine's little-endian order.
std::string binaryOff(bool big, std::uint32_t corners = 3) {
  std::string bytes = "# binary\nCOFF BINARY\n";
  auto put = [&](std::uint32_t w) {
    for (int k = 0; k < 4; ++k) bytes.push_back(char(big ? (w >> (24 - 8 * k)) & 255 : (w >> (8 * k)) & 255));
  };
  auto putFloat = [&](float f) {
    std::uint32_t w;
    std::memcpy(&w, &f, 4);
    put(w);
  };
  for (std::uint32_t count : {3u, 1u, 0u}) put(count);
  const float vertices[3][7] = {{0, 0, 0, 1, 0, 0, 1}, {1, 0, 0, 0, 1, 0, 1}, {0, 2, 0, 0, 0, 1, 0.5f}};
  for (const auto& v : vertices)
    for (float x : v) putFloat(x);
  put(corners);
  for (std::uint32_t k = 0; k < 3; ++k) put(k);
  put(0);  // no face color
  return bytes;
}

TEST(MeshIO, BinaryOffInEitherByteOrderIsRead) {
  test::TempDir dir;
  for (bool big : {true, false}) {
    test::writeBytes(dir / "b.off", binaryOff(big));
    const TriangleMesh m = io::readMesh(dir / "b.off");
    ASSERT_EQ(m.triangleCount(), 1u) << big;
    EXPECT_EQ(m.positions[2], Vec3f(0, 2, 0)) << big;
    ASSERT_TRUE(m.hasColors());
    EXPECT_EQ(m.colors[2], Color8(0, 0, 255, 128)) << big;
  }
  // A face claiming more corners than the file holds is refused, not read past the end.
  test::writeBytes(dir / "b.off", binaryOff(true, 1000000));
  EXPECT_THROW(io::readMesh(dir / "b.off"), Error);
  std::string cut = binaryOff(true);
  cut.resize(cut.size() - 6);
  test::writeBytes(dir / "b.off", cut);
  EXPECT_THROW(io::readMesh(dir / "b.off"), Error);
}

class MeshRoundTrip : public ::testing::TestWithParam<std::pair<const char*, bool>> {};

TEST_P(MeshRoundTrip, WriteThenReadGivesTheSameMesh) {
  const auto [extension, binary] = GetParam();
  DisplacedSphereOptions o;
  o.subdivisions = 3;
  const TriangleMesh mesh = makeDisplacedSphere(o);
  test::TempDir dir;
  const auto path = dir / (std::string("mesh") + extension);
  io::writeMesh(mesh, path, {.binary = binary});
  const TriangleMesh back = io::readMesh(path);
  ASSERT_EQ(back.vertexCount(), mesh.vertexCount());
  ASSERT_EQ(back.triangleCount(), mesh.triangleCount());
  const bool exact = binary && std::string(extension) != ".stl";
  if (std::string(extension) != ".stl") {  // STL has no shared vertices: order may change
    for (std::size_t i = 0; i < mesh.vertexCount(); ++i) {
      if (exact) {
        ASSERT_EQ(back.positions[i], mesh.positions[i]) << i;
      } else {
        ASSERT_NEAR(glm::distance(back.positions[i], mesh.positions[i]), 0.0f, 1e-5f) << i;
      }
    }
    EXPECT_EQ(back.triangles, mesh.triangles);
  }
  EXPECT_EQ(analyzeTopology(back).genus, 0);
  if ((std::string(extension) == ".ply" && binary) || std::string(extension) == ".off")
    EXPECT_EQ(back.colors, mesh.colors);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                          std::filesystem::directory_iterator()),
            1)
      << "a temporary file was left behind";
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshRoundTrip,
                         ::testing::Values(std::pair{".ply", true}, std::pair{".ply", false},
                                           std::pair{".obj", false}, std::pair{".off", false},
                                           std::pair{".stl", true}, std::pair{".stl", false}),
                         [](const auto& param) {
                           return std::string(param.param.first + 1) +
                                  (param.param.second ? "_binary" : "_ascii");
                         });

}  // namespace
}  // namespace cellrelief
