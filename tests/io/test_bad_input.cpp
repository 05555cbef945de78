// SPDX-License-Identifier: MIT
// Bad input: every case gives an Error that names the file and the problem, never a crash, never
// a silent wrong mesh; failed writes leave nothing behind. Robustness meshes load and say what is
// unusual about them.
#include <cstring>
#include <sys/stat.h>
#include <limits>

#include <gtest/gtest.h>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>

#include "test_support.h"

namespace cellrelief {
namespace {

using test::dataDir;
using test::writeBytes;

/// Reads `path`, expects an Error of `kind` whose message holds the path and `words`.
template <class Reader>
void expectError(Reader read, const std::filesystem::path& path, ErrorKind kind,
                 const std::string& words) {
  try {
    read(path);
    FAIL() << path << ": no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.kind(), kind) << what;
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find(words), std::string::npos) << "'" << words << "' not in: " << what;
  }
}

void expectMeshError(const std::filesystem::path& path, ErrorKind kind, const std::string& words) {
  expectError([](const auto& p) { io::readMesh(p); }, path, kind, words);
}

std::string plyHeader(const std::string& format, int vertices, int faces) {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string binaryTriangle(float badX, int badIndex) {
  std::string body;
  const float v[9] = {badX, 0, 0, 1, 0, 0, 0, 1, 0};
  body.append(reinterpret_cast<const char*>(v), sizeof v);
  const unsigned char n = 3;
  const int idx[3] = {0, 1, badIndex};
  body.append(reinterpret_cast<const char*>(&n), 1);
  body.append(reinterpret_cast<const char*>(idx), sizeof idx);
  return body;
}

TEST(BadMeshInput, MissingFile) {
  test::TempDir dir;
  expectMeshError(dir / "absent.obj", ErrorKind::FileNotFound, "no such file");
}

TEST(BadMeshInput, EmptyFiles) {
  test::TempDir dir;
  for (const char* ext : {".obj", ".ply", ".off", ".stl"}) {
    writeBytes(dir / (std::string("empty") + ext), "");
    expectMeshError(dir / (std::string("empty") + ext), ErrorKind::FileFormat, "file is empty");
  }
}

TEST(BadMeshInput, UnknownFormat) {
  test::TempDir dir;
  writeBytes(dir / "mesh.xyz", "1 2 3\n");
  expectMeshError(dir / "mesh.xyz", ErrorKind::Unsupported, "unsupported mesh format '.xyz'");
}

TEST(BadMeshInput, TruncatedBinaryPly) {
  test::TempDir dir;
  const std::string full = plyHeader("binary_little_endian", 3, 1) + binaryTriangle(0, 2);
  writeBytes(dir / "cut.ply", full.substr(0, full.size() - 5));
  expectMeshError(dir / "cut.ply", ErrorKind::FileFormat, "truncated");
  const auto igea = dataDir() / "meshes/large/igea__common-3d-test-models.ply";
  CELLRELIEF_REQUIRE_FILE(igea);
  const std::string bytes = test::readBytes(igea);
  for (double fraction : {0.05, 0.5, 0.99}) {  // in the vertices, and in the strip
    writeBytes(dir / "igea_cut.ply", bytes.substr(0, std::size_t(bytes.size() * fraction)));
    expectMeshError(dir / "igea_cut.ply", ErrorKind::FileFormat, "truncated");
  }
  writeBytes(dir / "header_only.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n");
  expectMeshError(dir / "header_only.ply", ErrorKind::FileFormat, "end_header");
}

// Mutated headers that once sent OpenMesh's PLY reader into loops of over a minute (issue 13):
// each must fail at once, naming the line.
TEST(BadMeshInput, MalformedPlyHeaderLinesFailAtOnce) {
  test::TempDir dir;
  const std::string body = binaryTriangle(0, 2);
  const std::string vertexProperties = "property float x\nproperty float y\nproperty float z\n";
  const std::string faceProperties = "property list uchar int vertex_indices\nend_header\n";
  const std::pair<std::string, std::string> formats[] = {
      {"format binary_little_endian \n", "malformed format line"},
      {"format binary_little_endian 1e308\n", "malformed format line"},
      {"format binary_little_endian -inf\n", "malformed format line"},
      {"format binary_little_endian 2.0\n", "malformed format line"}};
  int index = 0;
  for (const auto& [format, words] : formats) {
    const auto path = dir / ("format" + std::to_string(index++) + ".ply");
    writeBytes(path, "ply\n" + format + "element vertex 3\n" + vertexProperties + "element face 1\n" +
                         faceProperties + body);
    expectMeshError(path, ErrorKind::FileFormat, words);
  }
  for (const char* count : {"", " inf", " 1e308", " -1", " 12abc", " 99999999999999999999"}) {
    const auto path = dir / ("count" + std::to_string(index++) + ".ply");
    writeBytes(path, "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + vertexProperties +
                         "element face" + std::string(count) + "\n" + faceProperties + body);
    expectMeshError(path, ErrorKind::FileFormat, "malformed element line");
  }
  writeBytes(dir / "nameless.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + vertexProperties +
                                        "element face 1\nproperty list uchar int \t\nend_header\n" + body);
  expectMeshError(dir / "nameless.ply", ErrorKind::FileFormat, "malformed property line");
  // A count beyond the file's bytes cannot be real (an element without properties, which holds
  // no bytes, still sent OpenMesh through its whole count).
  writeBytes(dir / "huge_count.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + vertexProperties +
                                          "element face 1\nproperty list uchar int vertex_indices\n"
                                          "element nothing 999999999999999999\nend_header\n" + body);
  expectMeshError(dir / "huge_count.ply", ErrorKind::FileFormat, "more than the file's");
}

TEST(BadMeshInput, GarbageBytes) {
  test::TempDir dir;
  std::string garbage(4096, '\0');
  std::uint32_t state = 12345;
  for (char& c : garbage) c = char((state = state * 1664525u + 1013904223u) >> 24);
  garbage[0] = 'G';  // not accidentally 'ply' or 'solid'
  const std::pair<const char*, const char*> cases[] = {
      {".ply", "not a PLY file"}, {".off", "not an OFF file"}, {".stl", "truncated or not STL"},
      {".obj", "no vertices"}};
  for (const auto& [ext, words] : cases) {
    writeBytes(dir / (std::string("garbage") + ext), garbage);
    expectMeshError(dir / (std::string("garbage") + ext),
                    std::string(ext) == ".obj" ? ErrorKind::InvalidInput : ErrorKind::FileFormat,
                    words);
  }
}

TEST(BadMeshInput, NonFiniteCoordinates) {
  test::TempDir dir;
  writeBytes(dir / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  expectMeshError(dir / "nan.obj", ErrorKind::InvalidInput, "line 2: vertex coordinate 'nan'");
  writeBytes(dir / "inf.obj", "v 0 0 0\nv 1 -inf 0\nv 0 1 0\nf 1 2 3\n");
  expectMeshError(dir / "inf.obj", ErrorKind::InvalidInput, "'-inf' is not a finite number");
  writeBytes(dir / "nan.off", "OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n");
  expectMeshError(dir / "nan.off", ErrorKind::InvalidInput, "not a finite number");
  writeBytes(dir / "nan.ply", plyHeader("binary_little_endian", 3, 1) +
                                  binaryTriangle(std::numeric_limits<float>::quiet_NaN(), 2));
  expectMeshError(dir / "nan.ply", ErrorKind::InvalidInput, "vertex 0 has a non-finite");
  writeBytes(dir / "inf.ply", plyHeader("binary_little_endian", 3, 1) +
                                  binaryTriangle(std::numeric_limits<float>::infinity(), 2));
  expectMeshError(dir / "inf.ply", ErrorKind::InvalidInput, "non-finite");
}

TEST(BadMeshInput, FaceIndicesOutOfRange) {
  test::TempDir dir;
  writeBytes(dir / "oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  expectMeshError(dir / "oor.obj", ErrorKind::InvalidInput, "line 4: face corner '9' refers to vertex 9");
  writeBytes(dir / "oor.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  expectMeshError(dir / "oor.off", ErrorKind::InvalidInput, "refers to vertex 3");
  writeBytes(dir / "oor.ply", plyHeader("binary_little_endian", 3, 1) + binaryTriangle(0, 77));
  expectMeshError(dir / "oor.ply", ErrorKind::InvalidInput, "refers to vertex 77");
  writeBytes(dir / "neg.ply", plyHeader("ascii", 3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -5\n");
  expectMeshError(dir / "neg.ply", ErrorKind::InvalidInput, "refers to vertex");
}

TEST(BadMeshInput, NoFaces) {
  test::TempDir dir;
  writeBytes(dir / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expectMeshError(dir / "points.obj", ErrorKind::InvalidInput, "no faces");
  writeBytes(dir / "points.ply", plyHeader("ascii", 3, 0) + "0 0 0\n1 0 0\n0 1 0\n");
  expectMeshError(dir / "points.ply", ErrorKind::InvalidInput, "no faces");
  writeBytes(dir / "short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n");
  expectMeshError(dir / "short.off", ErrorKind::FileFormat, "declares 4 vertices, found 3");
}

TEST(BadMeshInput, WritingNeverLeavesPartialOutput) {
  test::TempDir dir;
  TriangleMesh bad = makeIcosphere(1);
  bad.triangles[3][1] = 1000;
  EXPECT_THROW(io::writeMesh(bad, dir / "bad.ply"), Error);
  EXPECT_THROW(io::writeMesh(makeIcosphere(1), dir / "no/such/folder/x.ply"), Error);
  EXPECT_THROW(io::writeMesh(makeIcosphere(1), dir / "x.fbx"), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  // An existing file is replaced only by a complete one.
  writeBytes(dir / "keep.ply", "old");
  EXPECT_THROW(io::writeMesh(bad, dir / "keep.ply"), Error);
  EXPECT_EQ(test::readBytes(dir / "keep.ply"), "old");
}

TEST(BadOutputPath, AnAtomicWriteNeverReplacesAFolderOrADevice) {
  // Writing is a rename over the target: over a named pipe (as over /dev/null) or a folder it
  // would replace the node with a plain file. Such targets are refused and left as they were.
  test::TempDir dir;
  const auto pipe = dir / "pipe.png", folder = dir / "folder.png";
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  std::filesystem::create_directory(folder);
  const Image<std::uint8_t> image(4, 4, 3, 7);
  for (const auto& target : {pipe, folder}) {
    try {
      io::writePng(image, target);
      ADD_FAILURE() << "wrote over " << target;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(std::filesystem::is_fifo(pipe));
  EXPECT_TRUE(std::filesystem::is_directory(folder));
}

TEST(BadImageInput, MissingEmptyTruncatedAndGarbage) {
  test::TempDir dir;
  auto read = [](const auto& p) { io::readImage(p); };
  expectError(read, dir / "absent.png", ErrorKind::FileNotFound, "no such file");
  writeBytes(dir / "empty.png", "");
  expectError(read, dir / "empty.png", ErrorKind::FileFormat, "file is empty");
  writeBytes(dir / "garbage.png", std::string(512, 'x'));
  expectError(read, dir / "garbage.png", ErrorKind::FileFormat, "not a readable");
  Image<std::uint8_t> im(64, 64, 3, 200);
  io::writePng(im, dir / "ok.png");
  const std::string bytes = test::readBytes(dir / "ok.png");
  writeBytes(dir / "cut.png", bytes.substr(0, bytes.size() / 2));
  expectError(read, dir / "cut.png", ErrorKind::FileFormat, "truncated PNG: chunk 'IDAT' claims");
  const auto rle = dataDir() / "heightmaps/irrlicht/terrain-heightmap.bmp";
  CELLRELIEF_REQUIRE_FILE(rle);
  const std::string rleBytes = test::readBytes(rle);
  writeBytes(dir / "cut.bmp", rleBytes.substr(0, rleBytes.size() / 2));
  expectError(read, dir / "cut.bmp", ErrorKind::FileFormat, "truncated");
}

// Real non-manifold, degenerate, open and multi-component meshes load, and the topology report
// names what is unusual about each.
TEST(RobustnessMeshes, LoadAndReportWhatIsUnusual) {
  const auto folder = dataDir() / "meshes/robustness";
  CELLRELIEF_REQUIRE_FILE(folder);
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!io::isMeshFile(entry.path())) continue;
    SCOPED_TRACE(entry.path().filename().string());
    const TriangleMesh m = io::readMesh(entry.path());
    const MeshTopology t = analyzeTopology(m);
    const std::string name = entry.path().filename().string();
    if (name.starts_with("degtri")) EXPECT_GT(t.degenerateTriangles, 0u);
    if (name.starts_with("fan3") || name.starts_with("bad_cube") ||
        name.starts_with("triple_vierbein") || name.starts_with("degenerated"))
      EXPECT_GT(t.nonManifoldEdges, 0u);
    if (name.starts_with("hourglass") || name.starts_with("non_manifold_vertex"))
      EXPECT_GT(t.nonManifoldVertices, 0u);
    if (name.starts_with("camelhead") || name.starts_with("mech-holes") ||
        name.starts_with("head_open") || name.starts_with("moebius"))
      EXPECT_GT(t.boundaryLoops, 0u);
    if (name.starts_with("moebius")) EXPECT_GT(t.misorientedEdges, 0u);
    if (name.starts_with("platonic_shelf") || name.starts_with("non_manifold_stitching"))
      EXPECT_GT(t.components, 1u);
    if (name.starts_with("non_manifold_stitching")) EXPECT_GT(t.duplicatePositions, 0u);
    ++loaded;
  }
  EXPECT_GE(loaded, 18);
}

}  // namespace
}  // namespace cellrelief
