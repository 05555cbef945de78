// SPDX-License-Identifier: MIT
/// @file mesh_io.h
/// Reading and writing triangle meshes: OBJ, PLY (ASCII and binary, including triangle strips), OFF
/// and STL (ASCII and binary), through OpenMesh's parsers and writers, except OFF, which has
/// cellrelief's own reader (detail/off_reader.h: OpenMesh's hangs on malformed files).
///
/// OpenMesh parses; cellrelief keeps what it parsed as a soup (detail/openmesh_importer.h), so that
/// non-manifold and multi-component meshes load unchanged. Polygons are fan-triangulated. Before
/// OpenMesh runs, structure checks (detail/format_checks.h, detail/ply_scan.h) catch what its
/// readers pass over silently. Every failure is an Error naming the file and the problem.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "cellrelief/core/error.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/io/atomic_file.h"
#include "cellrelief/io/detail/format_checks.h"
#include "cellrelief/io/detail/off_reader.h"
#include "cellrelief/io/detail/openmesh_exporter.h"
#include "cellrelief/io/detail/openmesh_importer.h"
#include "cellrelief/io/detail/ply_scan.h"
#include "cellrelief/io/paths.h"

namespace cellrelief::io {

struct MeshReadOptions {
  bool normals = true;  ///< keep per-vertex normals when the file has them
  bool colors = true;   ///< keep per-vertex colors when the file has them
  bool uvs = true;      ///< keep texture coordinates when the file has them
};

struct MeshWriteOptions {
  bool binary = true;  ///< binary PLY/STL; OBJ and OFF are always text
};

inline const std::vector<std::string>& meshExtensions() {
  static const std::vector<std::string> kExtensions{".obj", ".ply", ".off", ".stl"};
  return kExtensions;
}

inline bool isMeshFile(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  return std::find(meshExtensions().begin(), meshExtensions().end(), ext) != meshExtensions().end();
}

namespace detail {

/// OpenMesh reports problems on its global error stream `omerr`. A sink is connected to it once
/// (OpenMesh leaks a little on every connect/disconnect pair): while a capture is active, messages
/// go into the capture; otherwise they go to std::cerr as before. The mutex also serializes
/// OpenMesh's IOManager, which is not thread-safe.
class OpenMeshErrorSink : public std::streambuf {
 public:
  static OpenMeshErrorSink& instance() {
    static OpenMeshErrorSink sink;
    return sink;
  }
  std::mutex& mutex() { return mMutex; }
  void capture(std::string* target) { mTarget = target; }

 protected:
  int overflow(int c) override {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    const char ch = static_cast<char>(c);
    if (mTarget)
      mTarget->push_back(ch);
    else
      std::cerr.put(ch);
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (mTarget)
      mTarget->append(s, static_cast<std::size_t>(n));
    else
      std::cerr.write(s, n);
    return n;
  }

 private:
  OpenMeshErrorSink() : mStream(this) {
    ::omerr().disconnect(std::cerr);
    ::omerr().connect(mStream);
  }
  std::mutex mMutex;
  std::ostream mStream;
  std::string* mTarget = nullptr;
};

/// Routes OpenMesh's messages into a string for the duration of one read or write.
class CaptureOpenMeshErrors {
 public:
  CaptureOpenMeshErrors() : mLock(OpenMeshErrorSink::instance().mutex()) {
    OpenMeshErrorSink::instance().capture(&mCaptured);
    ::omlog().disable();
  }
  ~CaptureOpenMeshErrors() {
    ::omerr().flush();
    OpenMeshErrorSink::instance().capture(nullptr);
    ::omlog().enable();
  }
  std::string text() {
    ::omerr().flush();
    std::string s = mCaptured;
    std::replace(s.begin(), s.end(), '\n', ' ');
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
  }

 private:
  std::lock_guard<std::mutex> mLock;
  std::string mCaptured;
};

inline void checkReadable(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error(ErrorKind::FileNotFound, path, "no such file");
  if (!std::filesystem::is_regular_file(path, ec))
    throw Error(ErrorKind::FileNotFound, path, "not a regular file");
  if (std::filesystem::file_size(path, ec) == 0)
    throw Error(ErrorKind::FileFormat, path, "file is empty");
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw Error(ErrorKind::FileNotFound, path, "cannot open for reading");
}

/// Fan-triangulates the soup's polygons and moves its attributes into a TriangleMesh.
inline TriangleMesh toTriangleMesh(PolygonSoup& soup, const MeshReadOptions& options) {
  TriangleMesh mesh;
  mesh.positions = std::move(soup.positions);
  if (options.normals && soup.hasNormals) mesh.normals = std::move(soup.normals);
  if (options.colors && soup.hasColors) mesh.colors = std::move(soup.colors);
  const bool cornerUVs = options.uvs && soup.hasCornerUVs;
  // Polygons after the last one that had UVs (an OBJ mixing "f 1/1 2/2 3/3" and "f 1 2 3") get
  // (0, 0), as the importer pads those before it.
  if (cornerUVs) soup.cornerUVs.resize(soup.corners.size(), Vec2f(0));
  const bool vertexUVs = options.uvs && !cornerUVs && soup.hasVertexUVs;
  mesh.sourcePolygons = soup.polygonCount();
  mesh.triangles.reserve(soup.corners.size());
  for (std::size_t p = 0; p < soup.polygonCount(); ++p) {
    const std::uint32_t begin = soup.offsets[p], end = soup.offsets[p + 1];
    for (std::uint32_t k = begin + 1; k + 1 < end; ++k) {
      mesh.triangles.push_back({soup.corners[begin], soup.corners[k], soup.corners[k + 1]});
      if (cornerUVs)
        mesh.uvs.insert(mesh.uvs.end(),
                        {soup.cornerUVs[begin], soup.cornerUVs[k], soup.cornerUVs[k + 1]});
    }
  }
  if (vertexUVs) {
    mesh.uvs.reserve(3 * mesh.triangles.size());
    for (const Vec3u& t : mesh.triangles)
      for (int k = 0; k < 3; ++k)
        mesh.uvs.push_back(t[k] < soup.vertexUVs.size() ? soup.vertexUVs[t[k]] : Vec2f(0));
  }
  return mesh;
}

}  // namespace detail

/// Reads a mesh. Throws Error (FileNotFound, FileFormat, InvalidInput, Unsupported) whose message
/// starts with the path; never returns a mesh without triangles or with bad indices or coordinates.
inline TriangleMesh readMesh(const std::filesystem::path& path, const MeshReadOptions& options = {}) {
  detail::checkReadable(path);
  const std::string ext = lowerExtension(path);
  if (!isMeshFile(path))
    throw Error(ErrorKind::Unsupported, path,
                "unsupported mesh format '" + ext + "' (supported: .obj .ply .off .stl)");

  detail::PlyScan ply;
  detail::PolygonSoup soup;
  bool parsed = false;  // by cellrelief's own reader, not OpenMesh
  if (ext == ".ply") {
    ply = detail::scanPly(path.string());
  } else if (ext == ".off") {
    const detail::OffLayout layout = detail::parseOffLayout(path);
    soup = layout.binary ? detail::readBinaryOff(path, layout) : detail::readAsciiOff(path);
    parsed = true;
  } else if (ext == ".stl") {
    detail::checkStl(path);
  } else if (ext == ".obj") {
    detail::checkObj(path);
  }

  if (!parsed) {
    detail::SoupImporter importer(soup);
    using Opt = OpenMesh::IO::Options;
    Opt opt(Opt::VertexNormal | Opt::VertexColor | Opt::VertexTexCoord | Opt::FaceTexCoord);
    detail::CaptureOpenMeshErrors capture;
    const bool ok = OpenMesh::IO::IOManager().read(path.string(), importer, opt);
    if (!ok) {
      const std::string why = capture.text();
      throw Error(ErrorKind::FileFormat, path,
                  "OpenMesh could not parse the file" + (why.empty() ? "" : ": " + why));
    }
  }
  TriangleMesh mesh = detail::toTriangleMesh(soup, options);
  if (ply.hasStrips) {
    mesh.triangles.insert(mesh.triangles.end(), ply.stripTriangles.begin(),
                          ply.stripTriangles.end());
    mesh.sourcePolygons += ply.stripTriangles.size();
    mesh.uvs.clear();  // strips carry no UVs; per-corner UVs of other faces would no longer match
  }
  if (mesh.positions.empty())
    throw Error(ErrorKind::InvalidInput, path, "no vertices (not a " + ext + " mesh, or empty)");
  if (mesh.triangles.empty())
    throw Error(ErrorKind::InvalidInput, path,
                "no faces: " + std::to_string(mesh.positions.size()) +
                    " vertices but nothing to triangulate (a point cloud is not a surface)");
  mesh.validate(path.string());
  return mesh;
}

/// Writes a mesh through OpenMesh (format from the extension), atomically: on failure the target is
/// untouched and no temporary file is left behind.
inline void writeMesh(const TriangleMesh& mesh, const std::filesystem::path& path,
                      const MeshWriteOptions& options = {}) {
  if (!isMeshFile(path))
    throw Error(ErrorKind::Unsupported, path,
                "unsupported mesh format '" + lowerExtension(path) +
                    "' (supported: .obj .ply .off .stl)");
  mesh.validate(path.string());
  AtomicFile file(path);
  detail::SoupExporter exporter(mesh);
  using Opt = OpenMesh::IO::Options;
  // Ask each writer only for what its format stores (OpenMesh refuses a write otherwise).
  const std::string ext = lowerExtension(path);
  Opt opt;
  if (options.binary && (ext == ".ply" || ext == ".stl")) opt += Opt::Binary;
  if (mesh.hasNormals() && ext != ".stl") opt += Opt::VertexNormal;
  if (mesh.hasColors() && (ext == ".ply" || ext == ".off")) opt += Opt::VertexColor;
  {
    detail::CaptureOpenMeshErrors capture;
    if (!OpenMesh::IO::IOManager().write(file.temporaryPath().string(), exporter, opt)) {
      const std::string why = capture.text();
      throw Error(ErrorKind::FileWrite, path,
                  "OpenMesh could not write the file" + (why.empty() ? "" : ": " + why));
    }
  }
  file.commit();
}

}  // namespace cellrelief::io
