// SPDX-License-Identifier: MIT
/// @file bench_common.h
/// Shared pieces of the benchmark programs: timing (median of repeats), the 1M-triangle Igea made
/// by one Loop subdivision step through OpenMesh, the OpenVDB peer, and CSV output.
#pragma once

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <openvdb/tools/MeshToVolume.h>

#include <cellrelief/core/triangle_mesh.h>
#include <cellrelief/io/openmesh_triangles.h>

namespace cellrelief::bench {

/// The options every benchmark takes: where the data is, where the CSV goes, a quick smoke mode,
/// and the worker thread count (0: all cores).
struct BenchOptions {
  std::string data = CELLRELIEF_DATA_DIR;
  std::string out = "out/bench";
  bool quick = false;
  int threads = 0;

  void addTo(CLI::App& app) {
    app.add_option("--data", data, "Test data folder (../shared/data)")->capture_default_str();
    app.add_option("--out", out, "Where the CSV goes")->capture_default_str();
    app.add_flag("--quick", quick, "Small mesh, one repeat: a smoke run");
    app.add_option("--threads", threads, "Worker threads (0: all cores)");
  }
};

/// A frame size: "N" (N x N) or "WxH", each side from 1 to 16384 and the whole of its text ("12by3"
/// is refused, not read as 12); nullopt otherwise.
inline std::optional<std::pair<int, int>> parseFrameSize(const std::string& text) {
  auto side = [](const std::string& t) {
    int v = 0;
    const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), v);
    return error == std::errc() && end == t.data() + t.size() ? v : 0;
  };
  const std::size_t x = text.find('x');
  const int width = side(text.substr(0, x));
  const int height = x == std::string::npos ? width : side(text.substr(x + 1));
  if (width < 1 || height < 1 || width > 16384 || height > 16384) return std::nullopt;
  return std::pair{width, height};
}

/// Frame sizes separated by commas ("" gives none); nullopt if any one is not a frame size.
inline std::optional<std::vector<std::pair<int, int>>> parseFrameSizes(const std::string& list) {
  std::vector<std::pair<int, int>> sizes;
  for (std::size_t begin = 0; begin < list.size();) {
    const std::size_t comma = std::min(list.find(',', begin), list.size());
    const std::optional<std::pair<int, int>> size = parseFrameSize(list.substr(begin, comma - begin));
    if (!size) return std::nullopt;
    sizes.push_back(*size);
    begin = comma + 1;
  }
  return sizes;
}

/// Median wall time in seconds of `repeats` runs of `work`.
inline double medianSeconds(int repeats, const std::function<void()>& work) {
  std::vector<double> times;
  for (int i = 0; i < repeats; ++i) {
    const auto start = std::chrono::steady_clock::now();
    work();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

/// One Loop subdivision step (4x the triangles), through OpenMesh's subdivider. The input must be
/// a manifold mesh OpenMesh can hold.
inline TriangleMesh loopSubdivide(const TriangleMesh& mesh) {
  io::OpenMeshTriangles om = io::toOpenMesh(mesh);
  OpenMesh::Subdivider::Uniform::LoopT<io::OpenMeshTriangles> loop;
  loop.attach(om);
  loop(1);
  loop.detach();
  return io::fromOpenMesh(om);
}

/// OpenVDB's narrow-band level set of the mesh at the given voxel size (half width 3 voxels).
inline openvdb::FloatGrid::Ptr levelSet(const TriangleMesh& mesh, double voxelSize) {
  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh.positions.size());
  for (const Vec3f& p : mesh.positions) points.emplace_back(p.x, p.y, p.z);
  std::vector<openvdb::Vec3I> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const Vec3u& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  const auto xform = openvdb::math::Transform::createLinearTransform(voxelSize);
  return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles, 3.0f);
}

/// A CSV file written row by row; the header is written on creation.
class CsvWriter {
 public:
  CsvWriter(const std::filesystem::path& path, const std::string& header) : mPath(path) {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    mOut.open(path);
    mOut << header << "\n";
  }
  template <class... Args>
  void row(const Args&... args) {
    bool first = true;
    ((mOut << (first ? "" : ",") << args, first = false), ...);
    mOut << "\n";
    mOut.flush();
  }
  const std::filesystem::path& path() const { return mPath; }

 private:
  std::filesystem::path mPath;
  std::ofstream mOut;
};

}  // namespace cellrelief::bench
