// SPDX-License-Identifier: MIT
/// @file command_info.cpp
/// `cellrelief info <mesh|image>`: what a file holds and what is unusual about it.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>

#include "commands.h"

namespace cellrelief::app {

std::string formatBytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int u = 0;
  while (bytes >= 1024 && u < 4) {
    bytes /= 1024;
    ++u;
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, u == 0 ? "%.0f %s" : "%.2f %s", bytes, units[u]);
  return buffer;
}

int parseGridSize(const std::string& grid) {
  if (grid == "auto") return 0;
  try {
    std::size_t used = 0;
    const int n = std::stoi(grid, &used);
    if (used == grid.size() && n >= 1) return n;
  } catch (const std::exception&) {
  }
  throw Error(ErrorKind::InvalidArgument,
              "--grid takes a whole number >= 1 or 'auto', not '" + grid + "'");
}

namespace {

void printImageInfo(const std::string& path) {
  const io::ImageFile file = io::readImage(path);
  std::printf("image      %s\n", path.c_str());
  std::printf("format     %s\n", file.format.c_str());
  std::printf("size       %d x %d\n", file.width(), file.height());
  std::printf("channels   %d\n", file.channels());
  std::printf("bit depth  %d\n", file.bitDepth());
  Vec4f lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (int y = 0; y < file.height(); ++y)
    for (int x = 0; x < file.width(); ++x) {
      const Vec4f t = file.fetch(x, y);
      lo = glm::min(lo, t);
      hi = glm::max(hi, t);
    }
  const double scale = file.bitDepth() == 8 ? 255.0 : 65535.0;
  for (int c = 0; c < file.channels(); ++c)
    std::printf("channel %d  min %.0f  max %.0f\n", c, lo[c] * scale, hi[c] * scale);
}

}  // namespace

void printMeshInfo(const std::string& path) {
  const auto start = std::chrono::steady_clock::now();
  const TriangleMesh mesh = io::readMesh(path);
  const double loadSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const MeshTopology t = analyzeTopology(mesh);
  const Aabbf box = mesh.bounds();
  std::printf("mesh                  %s\n", path.c_str());
  std::printf("vertices              %zu (%zu unreferenced)\n", t.vertices, t.unreferencedVertices);
  std::printf("triangles             %zu (from %zu polygons)\n", t.triangles, mesh.sourcePolygons);
  std::printf("attributes            %s%s%s\n", mesh.hasNormals() ? "normals " : "",
              mesh.hasColors() ? "colors " : "", mesh.hasUVs() ? "uvs" : "");
  std::printf("bounds                (%g, %g, %g) - (%g, %g, %g), diagonal %g\n", box.min.x,
              box.min.y, box.min.z, box.max.x, box.max.y, box.max.z, box.diagonal());
  std::printf("components            %zu\n", t.components);
  std::printf("edges                 %zu\n", t.edges);
  std::printf("boundary              %zu edges in %zu loops%s\n", t.boundaryEdges, t.boundaryLoops,
              t.closed() ? " (closed)" : " (open)");
  std::printf("euler characteristic  %lld\n", t.eulerCharacteristic);
  if (t.genus)
    std::printf("genus                 %d\n", *t.genus);
  else
    std::printf("genus                 undefined (needs one closed, manifold, oriented component)\n");
  std::printf("non-manifold edges    %zu\n", t.nonManifoldEdges);
  std::printf("non-manifold vertices %zu\n", t.nonManifoldVertices);
  std::printf("misoriented edges     %zu\n", t.misorientedEdges);
  std::printf("degenerate triangles  %zu\n", t.degenerateTriangles);
  std::printf("duplicate positions   %zu\n", t.duplicatePositions);
  std::vector<std::string> unusual;
  if (!t.closed()) unusual.push_back("open");
  if (t.components > 1) unusual.push_back("multi-component");
  if (t.nonManifoldEdges || t.nonManifoldVertices) unusual.push_back("non-manifold");
  if (t.misorientedEdges) unusual.push_back("inconsistently oriented");
  if (t.degenerateTriangles) unusual.push_back("degenerate triangles");
  if (t.unreferencedVertices) unusual.push_back("unreferenced vertices");
  if (t.duplicatePositions) unusual.push_back("duplicate vertices");
  std::string summary;
  for (const std::string& u : unusual) summary += (summary.empty() ? "" : ", ") + u;
  std::printf("unusual               %s\n", summary.empty() ? "nothing" : summary.c_str());
  std::printf("load time             %.3f s\n", loadSeconds);
}

Command addInfoCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Print what a mesh or image file holds and what is unusual about it");
  auto path = std::make_shared<std::string>();
  cmd->add_option("file", *path, "Mesh (.obj .ply .off .stl) or image (.png .jpg .tga .bmp)")
      ->required();
  return {cmd, [path]() {
            if (io::isImageFile(*path))
              printImageInfo(*path);
            else
              printMeshInfo(*path);
            return 0;
          }};
}

}  // namespace cellrelief::app
