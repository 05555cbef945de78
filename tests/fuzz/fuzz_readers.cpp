// SPDX-License-Identifier: MIT
/// @file fuzz_readers.cpp
/// The readers under fuzzing (see fuzz_readers.h). Compiled once, linked into every target.
#include "fuzz_readers.h"

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <cellrelief/core/error.h>
#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/geotex/geotex_file.h>
#include <cellrelief/io/detail/crc32.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/polycube_file.h>
#include <cellrelief/relief/model_file.h>
#include <cellrelief/relief/reconstruct.h>
#include <cellrelief/trace/geotex_tracer.h>

namespace cellrelief::fuzz {
namespace {

/// One scratch file per process and extension, in memory when /dev/shm exists; removed at exit.
class ScratchFile {
 public:
  explicit ScratchFile(std::string_view extension) {
    const std::filesystem::path dir =
        std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    mPath = dir / ("cellrelief_fuzz_" + std::to_string(::getpid()) + std::string(extension));
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove(mPath, ec);
  }
  const std::filesystem::path& write(const std::uint8_t* data, std::size_t size) {
    std::FILE* f = std::fopen(mPath.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write the scratch file " + mPath.string());
    if (size > 0 && std::fwrite(data, 1, size, f) != size) {
      std::fclose(f);
      throw std::runtime_error("cannot write the scratch file " + mPath.string());
    }
    std::fclose(f);
    return mPath;
  }

 private:
  std::filesystem::path mPath;
};

ScratchFile& scratchFor(std::string_view extension) {
  // A handful of extensions per process; the map keeps each file's name stable.
  static std::vector<std::pair<std::string, std::unique_ptr<ScratchFile>>> files;
  for (auto& [ext, file] : files)
    if (ext == extension) return *file;
  files.emplace_back(std::string(extension), std::make_unique<ScratchFile>(extension));
  return *files.back().second;
}

/// What `cellrelief info` computes on a mesh: every index and attribute gets used.
void useMesh(const TriangleMesh& mesh) {
  const MeshTopology topology = analyzeTopology(mesh);
  if (topology.vertices != mesh.positions.size()) std::abort();
  const Aabbf box = mesh.bounds();
  if (!std::isfinite(box.min.x) || !std::isfinite(box.max.z)) std::abort();  // validate() promised finite
}

}  // namespace

bool readMeshBytes(std::string_view extension, const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = scratchFor(extension).write(data, size);
  try {
    const TriangleMesh mesh = io::readMesh(path);
    if (mesh.triangles.empty()) std::abort();  // readMesh promises triangles
    useMesh(mesh);
    return true;
  } catch (const Error&) {
    return false;
  }
}

bool readImageBytes(std::string_view extension, const std::uint8_t* data, std::size_t size,
                    std::uint64_t maxPixels) {
  const std::filesystem::path& path = scratchFor(extension).write(data, size);
  try {
    const io::ImageFile image = io::readImage(path, {.maxPixels = maxPixels});
    // Touch every pixel: a short buffer behind a large header shows up here under ASan.
    std::uint64_t sum = 0;
    std::visit([&](const auto& im) {
      for (const auto v : im.levelData(0)) sum += v;
    }, image.pixels);
    return sum != ~std::uint64_t(0);
  } catch (const Error&) {
    return false;
  }
}

namespace {
/// The bytes, with the last four replaced by the CRC-32 of the rest when `fixChecksum` is set.
std::vector<std::uint8_t> withChecksum(const std::uint8_t* data, std::size_t size, bool fixChecksum) {
  std::vector<std::uint8_t> bytes(data, data + size);
  if (fixChecksum && bytes.size() >= 4) {
    const std::uint32_t crc = io::detail::crc32(bytes.data(), bytes.size() - 4);
    std::memcpy(bytes.data() + bytes.size() - 4, &crc, 4);
  }
  return bytes;
}
}  // namespace

bool readModelBytes(const std::uint8_t* data, std::size_t size, bool fixChecksum) {
  const std::vector<std::uint8_t> bytes = withChecksum(data, size, fixChecksum);
  const std::filesystem::path& path = scratchFor(".crm").write(bytes.data(), bytes.size());
  try {
    const relief::ReliefModel model = relief::readRelief(path);
    // A model that passed validation must be usable: rebuild it at the coarsest level of detail,
    // by both methods (the closed one walks the neighbours of every cell).
    if (model.cells.size() <= 4096) {
      const int lod = relief::maxLevelOfDetail(model);
      (void)relief::reconstruct(model, {lod, relief::ReconstructionMethod::PerFace});
      // The closed lattice costs cells x ((T - 1) / 2^lod)^3: kept within a fuzz input's second.
      const double cubes = double((model.texels - 1) >> lod);
      if (double(model.cells.size()) * cubes * cubes * cubes <= double(1 << 20))
        (void)relief::reconstruct(model, {lod, relief::ReconstructionMethod::Closed});
    }
    return true;
  } catch (const Error&) {
    return false;
  }
}

bool readGeoTexBytes(const std::uint8_t* data, std::size_t size, bool fixChecksum) {
  const std::vector<std::uint8_t> bytes = withChecksum(data, size, fixChecksum);
  const std::filesystem::path& path = scratchFor(".cgt").write(bytes.data(), bytes.size());
  try {
    const geotex::GeoTexModel model = geotex::readGeoTex(path);
    // A model that passed validation must be traceable: rays from six sides through its bounds.
    const trace::GeoTexTracer<float> tracer(model);
    const Aabbd bounds = model.boundsWS();
    const Vec3f centre(bounds.center());
    const float reach = float(bounds.diagonal()) + 1.0f;
    for (int a = 0; a < 6; ++a) {
      Vec3f d(0);
      d[a % 3] = a < 3 ? 1.0f : -1.0f;
      const Hitf hit = tracer.intersect(Rayf(centre - reach * d + Vec3f(0.013f, 0.007f, 0.011f), d));
      if (hit.valid() && !(hit.t >= 0)) std::abort();  // a hit behind the origin
    }
    return true;
  } catch (const Error&) {
    return false;
  }
}

bool readPolycubeBytes(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = scratchFor(".txt").write(data, size);
  try {
    const polycube::PolycubeFile file = polycube::readPolycube(path);
    if (file.polycube.empty()) std::abort();  // readPolycube promises cubes
    const polycube::SurfaceStats stats = file.polycube.surfaceStats();
    if (stats.faces == 0 || stats.faces % 2 != 0) std::abort();  // a closed union of cubes
    (void)file.polycube.nonManifoldVertices();
    (void)file.polycube.surfaceMesh(file.frame);
    return true;
  } catch (const Error&) {
    return false;
  }
}

bool readPolycubeMapBytes(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path& path = scratchFor(".obj").write(data, size);
  try {
    const polycube::TexturedMeshFile file = polycube::readTexturedMesh(path);
    file.mesh.validate();
    if (file.texture.size() != file.mesh.positions.size() || file.mesh.triangles.empty()) std::abort();
    for (const Vec3d& t : file.texture)
      if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) std::abort();  // promised finite
    return true;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace cellrelief::fuzz
