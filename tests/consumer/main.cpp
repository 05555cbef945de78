// SPDX-License-Identifier: MIT
// A user's program against the installed package: make a mesh, write it, read it back, and load a
// real mesh when one is given. Exits non-zero on any mismatch.
#include <cstdio>
#include <filesystem>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/version.h>

int main(int argc, char** argv) {
  using namespace cellrelief;
  const TriangleMesh sphere = makeDisplacedSphere({.subdivisions = 4});
  const auto path = std::filesystem::temp_directory_path() / "cellrelief_consumer_sphere.ply";
  io::writeMesh(sphere, path);
  const TriangleMesh back = io::readMesh(path);
  std::filesystem::remove(path);
  const MeshTopology t = analyzeTopology(back);
  std::printf("cellrelief %s: %zu triangles, genus %d\n", CELLRELIEF_VERSION_STRING,
              back.triangleCount(), t.genus.value_or(-1));
  if (back.triangleCount() != sphere.triangleCount() || t.genus != 0) return 1;
  if (argc > 1 && std::filesystem::exists(argv[1])) {
    try {
      const TriangleMesh m = io::readMesh(argv[1]);
      std::printf("%s: %zu triangles\n", argv[1], m.triangleCount());
    } catch (const Error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  return 0;
}
