// SPDX-License-Identifier: MIT
/// @file polycube_result.h
/// What `cellrelief polycube mesh -o dir` writes, read back as a mesh a scene can hold: the cubes
/// with their frame (polycube.txt), the mesh with its texture positions (mesh_texture.obj), T2
/// (polycube_texture.png, every level) and what T2 holds (polycube_texture.txt: `use color` or
/// `use normal`). The look-up table is not a file of its own: it is a function of the cubes,
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

inline void writeTextureInfo(TextureUse use, const std::filesystem::path& path) {
  io::writeTextAtomically(path, [&](std::ostream& out) {
    out << "# cellrelief polycube T2: what its texels hold\nuse " << (use == TextureUse::Normal ? "normal" : "color")
        << '\n';
  });
}

inline TextureUse readTextureInfo(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return TextureUse::Color;  // written by an older version: colour
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (line == "use color") return TextureUse::Color;
    if (line == "use normal") return TextureUse::Normal;
    throw Error(ErrorKind::FileFormat, path, "expected 'use color' or 'use normal', got '" + line.substr(0, 80) + "'");
  }
  return TextureUse::Color;
}

/// The result in `dir` as a textured mesh in world space. Every error names the file it is about.
inline std::shared_ptr<TexturedMesh> readPolycubeResult(const std::filesystem::path& dir) {
  const PolycubeFile cubes = readPolycube(dir / kResultCubes);
  if (!cubes.hasFrame)
    throw Error(ErrorKind::FileFormat, dir / kResultCubes, "no frame line: where the lattice lies in world space");
  TexturedMeshFile mapped = readTexturedMesh(dir / kResultMesh);
  auto surface = std::make_shared<const PolycubeSurface>(detail::aboutFile(dir / kResultCubes, [&] {
    return PolycubeSurface(cubes.polycube);
  }));
  const std::filesystem::path png = dir / kResultTexture;
  io::ImageFile image = io::readImage(png);
  auto* rgba = std::get_if<Image<std::uint8_t>>(&image.pixels);
  if (!rgba) throw Error(ErrorKind::FileFormat, png, "T2 must have 8 bits per channel");
  auto out = std::make_shared<TexturedMesh>();
  out->t2 = std::make_shared<const PolycubeTexture>(
      detail::aboutFile(png, [&] { return PolycubeTexture::fromAtlas(surface, std::move(*rgba)); }));
  out->use = readTextureInfo(dir / kResultTextureInfo);
  out->texture.assign(mapped.texture.begin(), mapped.texture.end());
  out->mesh = std::move(mapped.mesh);
  detail::aboutFile(dir / kResultMesh, [&] { out->validate(); });
  return out;
}

}  // namespace cellrelief::polycube
