// SPDX-License-Identifier: MIT
/// @file polycube_file.h
/// A polycube as a text file of integer cube coordinates, for polycubes made by hand or by
/// another tool (the paper's were hand made):
///
///     # comments and blank lines are ignored
///     frame 0.1 -0.2 0.0 0.25     (optional, once: lattice origin x y z and cube size, world units)
///     0 0 0                       (one cube per line: its minimum corner on the integer lattice)
///     1 0 0
///
/// Reading refuses, naming the file and line, anything else: a line that is not three integers,
/// a coordinate out of range, a second frame line, a cube size that is not positive and finite,
/// more than kMaxCubes cubes, or a file without cubes. Writing is atomic.
///
/// `writeTexturedMesh` writes a mesh with its 3D texture positions as Wavefront OBJ: `v` the
/// mesh's vertices, `vt u v w` each vertex's texture position in the polycube's lattice
/// coordinates (the look-up table's space), `f a/a b/b c/c`.
#pragma once

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "cellrelief/io/atomic_file.h"
#include "cellrelief/io/detail/format_checks.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/polycube/polycube.h"

namespace cellrelief::polycube {

inline constexpr std::size_t kMaxCubes = std::size_t(1) << 24;

struct PolycubeFile {
  Polycube polycube;
  PolycubeFrame frame;
  bool hasFrame = false;
};

namespace detail {

/// Splits on spaces and tabs.
inline std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

/// A whole token as an int (cube coordinates may be negative).
inline bool parseInt(std::string_view text, int& value) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && end == text.data() + text.size();
}

}  // namespace detail

inline PolycubeFile readPolycube(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(ErrorKind::FileNotFound, path, "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::FileNotFound, path, "cannot open the file");
  PolycubeFile file;
  std::vector<Vec3i> cubes;
  std::string line;
  std::size_t number = 0;
  auto fail = [&](const std::string& what) {
    throw Error(ErrorKind::FileFormat, path, "line " + std::to_string(number) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++number;
    if (line.size() > 4096) fail("longer than 4096 characters");
    const std::vector<std::string_view> f = detail::fields(line);
    if (f.empty() || f[0].front() == '#') continue;
    if (f[0] == "frame") {
      if (file.hasFrame) fail("a second frame line");
      double v[4];
      if (f.size() != 5 || !io::detail::parseFinite(f[1], v[0]) || !io::detail::parseFinite(f[2], v[1]) ||
          !io::detail::parseFinite(f[3], v[2]) || !io::detail::parseFinite(f[4], v[3]))
        fail("expected 'frame x y z size' with four finite numbers");
      if (!(v[3] > 0)) fail("the frame's cube size must be positive");
      file.frame = {Vec3d(v[0], v[1], v[2]), v[3]};
      file.hasFrame = true;
      continue;
    }
    Vec3i c;
    if (f.size() != 3 || !detail::parseInt(f[0], c.x) || !detail::parseInt(f[1], c.y) ||
        !detail::parseInt(f[2], c.z))
      fail("expected three integers 'x y z', got '" + line.substr(0, 80) + "'");
    for (int a = 0; a < 3; ++a)
      if (std::abs(c[a]) > Polycube::kMaxCoordinate - 2)
        fail("coordinate " + std::to_string(c[a]) + " is out of range (|c| <= " +
             std::to_string(Polycube::kMaxCoordinate - 2) + ")");
    if (cubes.size() == kMaxCubes) fail("more than " + std::to_string(kMaxCubes) + " cubes");
    cubes.push_back(c);
  }
  if (in.bad()) throw Error(ErrorKind::FileFormat, path, "read error");
  if (cubes.empty()) throw Error(ErrorKind::FileFormat, path, "no cubes in the file");
  file.polycube = Polycube(std::move(cubes));
  return file;
}

inline void writePolycube(const Polycube& polycube, const PolycubeFrame& frame, const std::filesystem::path& path) {
  io::writeTextAtomically(path, [&](std::ostream& out) {
    out.precision(17);
    out << "# cellrelief polycube: one unit cube per line, its minimum corner on the integer lattice\n"
        << "frame " << frame.origin.x << ' ' << frame.origin.y << ' ' << frame.origin.z << ' ' << frame.cubeSize
        << '\n';
    for (const Vec3i& c : polycube.cubes()) out << c.x << ' ' << c.y << ' ' << c.z << '\n';
  });
}

inline void writeTexturedMesh(const TriangleMesh& mesh, std::span<const Vec3d> texture,
                              const std::filesystem::path& path) {
  if (texture.size() != mesh.positions.size())
    throw Error(ErrorKind::InvalidArgument, path, "one texture position per vertex is needed");
  io::writeTextAtomically(path, [&](std::ostream& out) {
    out.precision(9);
    out << "# cellrelief polycube map: vt u v w is each vertex's texture position in the polycube's lattice\n";
    for (const Vec3f& p : mesh.positions) out << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    out.precision(12);
    for (const Vec3d& u : texture) out << "vt " << u.x << ' ' << u.y << ' ' << u.z << '\n';
    for (const Vec3u& t : mesh.triangles)
      out << "f " << t[0] + 1 << '/' << t[0] + 1 << ' ' << t[1] + 1 << '/' << t[1] + 1 << ' ' << t[2] + 1 << '/'
          << t[2] + 1 << '\n';
  });
}

/// A mesh with one 3D texture position per vertex, as writeTexturedMesh writes it.
struct TexturedMeshFile {
  TriangleMesh mesh;
  std::vector<Vec3d> texture;
};

/// Reads what writeTexturedMesh wrote: `v x y z`, `vt u v w`, `f a/t b/t c/t` (triangles, 1-based
/// or negative indices). Every corner of a vertex must name the same texture position; a vertex no
/// triangle uses takes the vt of its own number. Refuses, naming the file and line, anything else.
inline TexturedMeshFile readTexturedMesh(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(ErrorKind::FileNotFound, path, "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::FileNotFound, path, "cannot open the file");
  TexturedMeshFile file;
  std::vector<Vec3d> vts;
  std::vector<std::int64_t> vertexVt;  // per vertex: its texture position's index, -1 while unknown
  std::string line;
  std::size_t number = 0;
  auto fail = [&](const std::string& what) {
    throw Error(ErrorKind::FileFormat, path, "line " + std::to_string(number) + ": " + what);
  };
  auto readVec3 = [&](const std::vector<std::string_view>& f, const char* what) {
    Vec3d v;
    if (f.size() != 4 || !io::detail::parseFinite(f[1], v.x) || !io::detail::parseFinite(f[2], v.y) ||
        !io::detail::parseFinite(f[3], v.z))
      fail(std::string("expected '") + what + " x y z' with three finite numbers");
    return v;
  };
  auto index = [&](std::string_view text, std::size_t count, const char* what) {
    int i = 0;
    if (!detail::parseInt(text, i) || i == 0) fail(std::string("bad ") + what + " index '" + std::string(text) + "'");
    const long long resolved = i > 0 ? i - 1 : (long long)count + i;
    if (resolved < 0 || resolved >= (long long)count)
      fail(std::string(what) + " index " + std::to_string(i) + " is out of range (" + std::to_string(count) + ")");
    return std::size_t(resolved);
  };
  while (std::getline(in, line)) {
    ++number;
    if (line.size() > 4096) fail("longer than 4096 characters");
    const std::vector<std::string_view> f = detail::fields(line);
    if (f.empty() || f[0].front() == '#') continue;
    if (f[0] == "v") {
      file.mesh.positions.push_back(Vec3f(readVec3(f, "v")));
      vertexVt.push_back(-1);
    } else if (f[0] == "vt") {
      vts.push_back(readVec3(f, "vt u v"));
    } else if (f[0] == "f") {
      if (f.size() != 4) fail("expected a triangle 'f a/t b/t c/t'");
      Vec3u t;
      for (int k = 0; k < 3; ++k) {
        const std::size_t slash = f[1 + k].find('/');
        if (slash == std::string_view::npos) fail("a corner without a texture position ('a/t')");
        const std::size_t v = index(f[1 + k].substr(0, slash), file.mesh.positions.size(), "vertex");
        const std::size_t vt = index(f[1 + k].substr(slash + 1), vts.size(), "texture position");
        if (vertexVt[v] >= 0 && std::size_t(vertexVt[v]) != vt && vts[std::size_t(vertexVt[v])] != vts[vt])
          fail("vertex " + std::to_string(v + 1) + " has two texture positions; a polycube map gives one per vertex");
        vertexVt[v] = std::int64_t(vt);
        t[k] = std::uint32_t(v);
      }
      file.mesh.triangles.push_back(t);
    } else {
      fail("expected v, vt or f, got '" + std::string(f[0]) + "'");
    }
  }
  if (in.bad()) throw Error(ErrorKind::FileFormat, path, "read error");
  if (file.mesh.triangles.empty()) throw Error(ErrorKind::FileFormat, path, "no triangles in the file");
  file.texture.resize(file.mesh.positions.size());
  for (std::size_t v = 0; v < vertexVt.size(); ++v) {
    // A vertex no triangle uses (meshes have them) takes the vt of its own number, as written.
    if (vertexVt[v] < 0 && v >= vts.size())
      throw Error(ErrorKind::FileFormat, path,
                  "vertex " + std::to_string(v + 1) + " is in no triangle and has no texture position of its number");
    file.texture[v] = vts[vertexVt[v] >= 0 ? std::size_t(vertexVt[v]) : v];
  }
  file.mesh.sourcePolygons = file.mesh.triangles.size();
  return file;
}

}  // namespace cellrelief::polycube
