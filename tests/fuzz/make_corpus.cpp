// SPDX-License-Identifier: MIT
/// @file make_corpus.cpp
/// Writes the fuzz seeds in tests/fuzz/corpus/<target>/: small files (a few KB) the project makes
/// itself, one per feature of each format the readers handle (attributes, polygons, strips, bit
/// depths, channel counts, compression), so that mutations start from every code path. Run once by
/// hand (`make_corpus <corpus dir>`) when a reader learns a feature; the output is checked in.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include <cellrelief/core/procedural.h>
#include <cellrelief/geotex/convert.h>
#include <cellrelief/geotex/geotex_file.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/polycube_file.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/model_file.h>

namespace fs = std::filesystem;
using namespace cellrelief;

namespace {

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

void writeBytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              std::streamsize(bytes.size()));
}

TriangleMesh smallSphere(bool normals, bool colors) {
  TriangleMesh m = makeIcosphere(1);  // 80 triangles
  if (normals) m.normals = computeVertexNormals(m);
  if (colors)
    for (std::size_t i = 0; i < m.positions.size(); ++i)
      m.colors.push_back(Color8(std::uint8_t(40 * i), std::uint8_t(255 - 7 * i), 128, 255));
  return m;
}

void meshSeeds(const fs::path& root) {
  const TriangleMesh plain = makeIcosphere(0), rich = smallSphere(true, true);
  const fs::path obj = root / "obj", plyA = root / "ply_ascii", plyB = root / "ply_binary",
                 off = root / "off", stlA = root / "stl_ascii", stlB = root / "stl_binary";
  for (const fs::path& d : {obj, plyA, plyB, off, stlA, stlB}) fs::create_directories(d);
  // What the project's own writer produces.
  io::writeMesh(plain, obj / "icosahedron.obj");
  io::writeMesh(rich, obj / "sphere_normals.obj");
  io::writeMesh(plain, plyA / "icosahedron.ply", {.binary = false});
  io::writeMesh(rich, plyA / "sphere_normals_colors.ply", {.binary = false});
  io::writeMesh(plain, plyB / "icosahedron.ply");
  io::writeMesh(rich, plyB / "sphere_normals_colors.ply");
  io::writeMesh(plain, off / "icosahedron.off");
  io::writeMesh(rich, off / "sphere_colors.off");
  io::writeMesh(plain, stlA / "icosahedron.stl", {.binary = false});
  io::writeMesh(plain, stlB / "icosahedron.stl");
  io::writeMesh(smallSphere(false, false), stlB / "sphere.stl");
  // Features other writers use: polygons, texture coordinates, negative indices, strips, lists
  // with other count and index types, comments.
  writeText(obj / "quads_uvs_negative.obj",
            "# a cube of quads\nmtllib none.mtl\no cube\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 -1\nvn 0 0 1\n"
            "f 1/1/1 4/4/1 3/3/1 2/2/1\nf 5/1/2 6/2/2 7/3/2 8/4/2\ng sides\ns 1\n"
            "f -8 -7 -3 -4\nf 2 3 7 6\nf 3 4 8 7\nf 4//1 1//1 5//1 8//1\n");
  writeText(plyA / "strips_uchar_int.ply",
            "ply\nformat ascii 1.0\ncomment strips and a face list with uchar counts\n"
            "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
            "property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\n"
            "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
            "0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n1 1 0 1 1\n0.5 0.5 1 0.5 0.5\n3 0 1 4\n"
            "6 0 1 2 3 -1 4\n");
  writeText(off / "quads_noff.off",
            "NOFF\n5 5 0\n0 0 0 0 0 -1\n1 0 0 0 0 -1\n1 1 0 0 0 -1\n0 1 0 0 0 -1\n"
            "0.5 0.5 1 0 0 1\n4 0 3 2 1\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n");
  writeText(off / "layouts_stcnoff.off",
            "# every vertex value the header word can name\nSTCNOFF 4 2 0\n"
            "0 0 0 0 0 1 255 0 0 0 0\n1 0 0 0 0 1 0 1.0 0 0.5 1 0\n"
            "0 1 0 0 0 1 0 0 1.0 0 1 # a comment\n\n0 0 1 1 0 0 0.5 0.5 0.5 1 1\n"
            "3 0 1 2 0.1 0.2 0.3\n4 0 1 3 2\n");
  writeText(off / "homogeneous_4off.off", "4OFF 4 4\n0 0 0 1\n2 0 0 2\n0 3 0 3\n0 0 4 4\n"
                                          "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  {
    // Binary OFF as Geomview writes it: big-endian counts, floats and faces.
    std::vector<std::uint8_t> b;
    for (char c : std::string("COFF BINARY\n")) b.push_back(std::uint8_t(c));
    auto put = [&](std::uint32_t w) {
      for (int k = 0; k < 4; ++k) b.push_back(std::uint8_t(w >> (24 - 8 * k)));
    };
    auto putFloat = [&](float f) {
      std::uint32_t w;
      std::memcpy(&w, &f, 4);
      put(w);
    };
    for (std::uint32_t count : {4u, 4u, 6u}) put(count);
    const float vertices[4][7] = {
        {0, 0, 0, 1, 0, 0, 1}, {1, 0, 0, 0, 1, 0, 1}, {0, 1, 0, 0, 0, 1, 1}, {0, 0, 1, 1, 1, 1, 0.5f}};
    for (const auto& v : vertices)
      for (float x : v) putFloat(x);
    const std::uint32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& f : faces) {
      put(3);
      for (std::uint32_t i : f) put(i);
      put(f[0] == 0 ? 0 : 3);  // one face with a color of 3 floats
      if (f[0] != 0)
        for (int k = 0; k < 3; ++k) putFloat(0.5f);
    }
    writeBytes(off / "tetrahedron_binary.off", b);
  }
  writeText(stlA / "tetrahedron_named.stl",
            "solid tetra\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\n"
            "endfacet\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\n"
            "endfacet\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\n"
            "endfacet\nfacet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\n"
            "endfacet\nendsolid tetra\n");
}

void imageSeeds(const fs::path& root) {
  const fs::path png = root / "png", jpeg = root / "jpeg", tga = root / "tga", bmp = root / "bmp";
  for (const fs::path& d : {png, jpeg, tga, bmp}) fs::create_directories(d);
  constexpr int W = 13, H = 9;  // odd sizes: row padding and filters at the edges
  for (const int channels : {1, 2, 3, 4}) {
    Image<std::uint8_t> im8(W, H, channels);
    Image<std::uint16_t> im16(W, H, channels);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        for (int c = 0; c < channels; ++c) {
          im8.at(x, y, c) = std::uint8_t(17 * x + 29 * y + 61 * c);
          im16.at(x, y, c) = std::uint16_t(4099 * x + 997 * y + 30011 * c);
        }
    const std::string stem = "gradient_" + std::to_string(channels) + "ch";
    io::writePng(im8, png / (stem + "_8bit.png"));
    io::writePng(im16, png / (stem + "_16bit.png"));
    const auto* p = im8.levelData(0).data();
    stbi_write_tga_with_rle = 1;
    stbi_write_tga((tga / (stem + "_rle.tga")).c_str(), W, H, channels, p);
    stbi_write_tga_with_rle = 0;
    stbi_write_tga((tga / (stem + ".tga")).c_str(), W, H, channels, p);
    if (channels != 2) stbi_write_bmp((bmp / (stem + ".bmp")).c_str(), W, H, channels, p);
    if (channels == 1 || channels == 3)
      stbi_write_jpg((jpeg / (stem + ".jpg")).c_str(), W, H, channels, p, 80);
  }
  // An 8-bit run-length encoded BMP (BI_RLE8), which the project decodes itself: 4 x 2 pixels,
  // a grey ramp palette of 4 entries.
  std::vector<std::uint8_t> rle = {2, 1, 2, 2, 0, 0,  // row 0: runs of 1 and 2, end of line
                                   0, 4, 3, 2, 1, 0, 0, 1};  // row 1: 4 literal pixels, end
  std::vector<std::uint8_t> file(14 + 40 + 16);
  auto put32 = [&](std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) file[at + k] = std::uint8_t(v >> (8 * k));
  };
  file[0] = 'B', file[1] = 'M';
  put32(10, 14 + 40 + 16);
  put32(14, 40), put32(18, 4), put32(22, 2);
  file[26] = 1, file[28] = 8;
  put32(30, 1);  // BI_RLE8
  put32(34, std::uint32_t(rle.size())), put32(46, 4);
  for (int i = 0; i < 4; ++i) file[54 + 4 * i] = file[55 + 4 * i] = file[56 + 4 * i] = std::uint8_t(80 * i);
  file.insert(file.end(), rle.begin(), rle.end());
  put32(2, std::uint32_t(file.size()));
  writeBytes(bmp / "rle8_4x2.bmp", file);
}

void modelSeeds(const fs::path& root) {
  const fs::path crm = root / "crm";
  fs::create_directories(crm);
  const TriangleMesh rich = smallSphere(true, true);
  for (const int bits : {8, 16}) {
    relief::ConvertOptions o;
    o.gridSize = 2;
    o.texels = 3;
    o.distanceBits = bits;
    o.colors = bits == 16;
    o.normals = bits == 16 ? relief::NormalFormat::Octahedral16 : relief::NormalFormat::Rgba8;
    relief::writeRelief(relief::convert(rich, o), crm / ("sphere_n2_t3_" + std::to_string(bits) + "bit.crm"));
  }
}

/// Geometry textures of a small sphere: 8-bit heights, and 16-bit with a colour map.
void geotexSeeds(const fs::path& root) {
  const fs::path dir = root / "geotex";
  fs::create_directories(dir);
  const TriangleMesh rich = smallSphere(true, true);
  for (const int bits : {8, 16}) {
    geotex::GeoTexOptions o;
    o.vsa.proxies = 6;
    o.maxTexels = 4;
    o.heightBits = bits;
    o.colors = bits == 16;
    geotex::writeGeoTex(geotex::convertMesh(rich, o).model, dir / ("sphere_6_charts_" + std::to_string(bits) + "bit.cgt"));
  }
}

/// Eight cubes around an empty one: genus 1.
polycube::Polycube ringOfCubes() {
  std::vector<Vec3i> ring;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      if (x != 1 || y != 1) ring.push_back({x, y, 0});
  return polycube::Polycube(ring);
}

/// Cube files: a ring (genus 1) with a frame, and an L of cubes without one.
void polycubeSeeds(const fs::path& root) {
  const fs::path dir = root / "polycube";
  fs::create_directories(dir);
  polycube::writePolycube(ringOfCubes(), {Vec3d(-0.5, 0.25, 1), 0.125}, dir / "ring.txt");
  std::ofstream(dir / "l_shape.txt") << "# an L\n0 0 0\n1 0 0\n0 1 0\n0 0 -1\n";
}

/// Meshes with their polycube texture positions: a ring's surface mapped onto itself, and a
/// triangle written with negative indices.
void polycubeMapSeeds(const fs::path& root) {
  const fs::path dir = root / "polycube_map";
  fs::create_directories(dir);
  const TriangleMesh surface = ringOfCubes().surfaceMesh();
  const std::vector<Vec3d> texture(surface.positions.begin(), surface.positions.end());
  polycube::writeTexturedMesh(surface, texture, dir / "ring.obj");
  std::ofstream(dir / "negative.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nvt 1 0 0\nvt 0 1 0\nf -3/-3 -2/-2 -1/-1\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_corpus <corpus directory>\n";
    return 2;
  }
  try {
    const fs::path root = argv[1];
    meshSeeds(root);
    imageSeeds(root);
    modelSeeds(root);
    geotexSeeds(root);
    polycubeSeeds(root);
    polycubeMapSeeds(root);
    std::cout << "fuzz seeds written under " << root << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "make_corpus: " << e.what() << "\n";
    return 1;
  }
}
