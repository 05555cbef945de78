// SPDX-License-Identifier: MIT
/// @file polycube_result.h
/// What `cellrelief polycube mesh -o dir` writes, read back as a mesh a scene can hold: the cubes
/// with their frame (polycube.txt), the mesh with its texture positions (mesh_texture.obj), T2
/// (polycube_texture.png, every level) and what T2 holds (polycube_texture.txt: `use color` or
/// `use normal`, S, the squarelet count, checked against the others). The look-up table is not a file of its own: it is a function of the cubes,
/// rebuilt here exactly as it was.
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <variant>

#include "cellrelief/io/image_io.h"
#include "cellrelief/polycube/polycube_file.h"
#include "cellrelief/polycube/textured_mesh.h"

namespace cellrelief::polycube {

inline constexpr const char* kResultCubes = "polycube.txt";
inline constexpr const char* kResultMesh = "mesh_texture.obj";
inline constexpr const char* kResultTexture = "polycube_texture.png";
inline constexpr const char* kResultTextureInfo = "polycube_texture.txt";

namespace detail {
/// Runs `work`; an Error without a file gets `path` as its file.
template <class Work>
auto aboutFile(const std::filesystem::path& path, Work&& work) {
  try {
    return work();
  } catch (const Error& e) {
    if (!e.path().empty()) throw;
    throw Error(e.kind(), path, e.problem());
  }
}
}  // namespace detail

/// Whether `dir` holds a polycube result (its cube file and mapped mesh).
inline bool isPolycubeResult(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::is_directory(dir, ec) && std::filesystem::exists(dir / kResultCubes, ec) &&
         std::filesystem::exists(dir / kResultMesh, ec);
}

/// What polycube_texture.txt says: what T2 holds, its S and its squarelet count (0: not given).
struct TextureInfo {
  TextureUse use = TextureUse::Color;
  int texels = 0;
  std::uint32_t squarelets = 0;
};

inline void writeTextureInfo(const PolycubeTexture& t2, TextureUse use, const std::filesystem::path& path) {
  io::writeTextAtomically(path, [&](std::ostream& out) {
    out << "# cellrelief polycube T2: what its texels hold, texels per squarelet side, squarelets\n"
        << "use " << (use == TextureUse::Normal ? "normal" : "color") << "\ntexels " << t2.texelsPerSquarelet()
        << "\nsquarelets " << t2.surface().lut().tileCount() << '\n';
  });
}

inline TextureInfo readTextureInfo(const std::filesystem::path& path) {
  TextureInfo info;
  std::ifstream in(path);
  if (!in) return info;  // absent: colour, S from the image's size
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string_view> f = detail::fields(line);
    int value = 0;
    if (f.size() == 2 && f[0] == "use" && (f[1] == "color" || f[1] == "normal")) {
      info.use = f[1] == "normal" ? TextureUse::Normal : TextureUse::Color;
    } else if (f.size() == 2 && f[0] == "texels" && detail::parseInt(f[1], value) && value > 0) {
      info.texels = value;
    } else if (f.size() == 2 && f[0] == "squarelets" && detail::parseInt(f[1], value) && value > 0) {
      info.squarelets = std::uint32_t(value);
    } else {
      throw Error(ErrorKind::FileFormat, path, "line " + std::to_string(number) +
                                                   ": expected 'use color|normal', 'texels S' or 'squarelets K', got '" +
                                                   line.substr(0, 80) + "'");
    }
  }
  return info;
}

/// Writes what readPolycubeResult reads back into `dir` (made when missing): the cubes with their
/// frame, the mesh with its texture positions, T2 and what it holds. Each file atomically.
inline void writePolycubeResult(const std::filesystem::path& dir, const Polycube& cubes, const PolycubeFrame& frame,
                                const TriangleMesh& mesh, std::span<const Vec3d> texture, const PolycubeTexture& t2,
                                TextureUse use) {
  std::filesystem::create_directories(dir);
  writePolycube(cubes, frame, dir / kResultCubes);
  writeTexturedMesh(mesh, texture, dir / kResultMesh);
  io::writePng(t2.atlas(), dir / kResultTexture);
  writeTextureInfo(t2, use, dir / kResultTextureInfo);
}

/// The result in `dir` as a textured mesh in world space. Every error names the file it is about.
inline std::shared_ptr<TexturedMesh> readPolycubeResult(const std::filesystem::path& dir) {
  const PolycubeFile cubes = readPolycube(dir / kResultCubes);
  const TextureInfo info = readTextureInfo(dir / kResultTextureInfo);
  TexturedMeshFile mapped = readTexturedMesh(dir / kResultMesh);
  auto surface = std::make_shared<const PolycubeSurface>(detail::aboutFile(dir / kResultCubes, [&] {
    return PolycubeSurface(cubes.polycube);
  }));
  const std::filesystem::path png = dir / kResultTexture;
  io::ImageFile image = io::readImage(png);
  auto* rgba = std::get_if<Image<std::uint8_t>>(&image.pixels);
  if (!rgba) throw Error(ErrorKind::FileFormat, png, "T2 must have 8 bits per channel");
  if (info.squarelets != 0 && info.squarelets != surface->lut().tileCount())
    throw Error(ErrorKind::FileFormat, dir / kResultTextureInfo,
                "T2 has " + std::to_string(info.squarelets) + " squarelets, the polycube of " + kResultCubes + " " +
                    std::to_string(surface->lut().tileCount()) + ": the files are not one result");
  auto out = std::make_shared<TexturedMesh>();
  out->t2 = std::make_shared<const PolycubeTexture>(
      detail::aboutFile(png, [&] { return PolycubeTexture::fromAtlas(surface, std::move(*rgba), info.texels); }));
  out->use = info.use;
  out->texture.assign(mapped.texture.begin(), mapped.texture.end());
  out->mesh = std::move(mapped.mesh);
  detail::aboutFile(dir / kResultMesh, [&] { out->validate(); });
  return out;
}

}  // namespace cellrelief::polycube
