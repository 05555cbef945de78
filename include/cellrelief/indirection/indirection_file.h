// SPDX-License-Identifier: MIT
/// @file indirection_file.h
/// The indirection map on disk, as `cellrelief indirect` writes it and a renderer reads it: an RGB
/// PNG of 8 or 16 bits (R = I_u, G = I_v, each min/max normalized, B = 0) and beside it a JSON
/// sidecar `<png>.json` with the decoding I = bias + scale * texel and what it was computed for
/// (height map, optimizer, grid, height scale). A PNG alone cannot hold signed offsets in texture
/// units; the sidecar keeps the file an ordinary image any tool can show.
///
/// Both files are written atomically (the sidecar first: a PNG never stands without its decoding).
/// Reading checks the sidecar and names the file and the problem on any error.
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/indirection/indirection_map.h"
#include "cellrelief/io/atomic_file.h"
#include "cellrelief/io/image_io.h"

namespace cellrelief::indirection {

/// What an indirection map was computed for, stored in its sidecar.
struct IndirectionProvenance {
  std::string heightmap, optimizer;
  int grid = 0;
  float heightScale = 0;  ///< the relief's height scale; 0 where unknown
};

/// The sidecar's path: `<png>.json`.
inline std::filesystem::path indirectionSidecar(const std::filesystem::path& png) {
  return png.string() + ".json";
}

namespace detail {
inline std::string jsonEscaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out;
}

/// The numbers of the array after `"key":` in `json`, or none when the key is absent.
inline std::vector<double> jsonNumbers(const std::string& json, const std::string& key) {
  std::vector<double> values;
  const std::size_t at = json.find("\"" + key + "\"");
  if (at == std::string::npos) return values;
  std::size_t i = json.find(':', at);
  if (i == std::string::npos) return values;
  ++i;
  while (i < json.size() && std::isspace(static_cast<unsigned char>(json[i]))) ++i;
  const bool array = i < json.size() && json[i] == '[';
  if (array) ++i;
  while (i < json.size()) {
    const char* begin = json.c_str() + i;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) break;
    values.push_back(v);
    i += std::size_t(end - begin);
    if (!array) break;
    while (i < json.size() && (std::isspace(static_cast<unsigned char>(json[i])) || json[i] == ',')) ++i;
  }
  return values;
}
}  // namespace detail

namespace detail {
inline void writeIndirectionSidecar(const std::filesystem::path& png, int bits, Vec2f scale, Vec2f bias,
                                    const IndirectionProvenance& provenance) {
  io::writeTextAtomically(indirectionSidecar(png), [&](std::ostream& out) {
    out.precision(9);
    out << "{\n  \"heightmap\": \"" << jsonEscaped(provenance.heightmap) << "\",\n  \"optimizer\": \""
        << jsonEscaped(provenance.optimizer) << "\",\n  \"grid\": " << provenance.grid
        << ",\n  \"height_scale\": " << provenance.heightScale << ",\n  \"bits\": " << bits
        << ",\n  \"decode\": \"I = bias + scale * texel (R: u, G: v)\",\n  \"scale\": [" << scale.x << ", "
        << scale.y << "],\n  \"bias\": [" << bias.x << ", " << bias.y << "]\n}\n";
  });
}
}  // namespace detail

/// Writes I (2 channels) as `png` (8 or 16 bits) and its sidecar.
inline void writeIndirectionMap(const Image<float>& map, const std::filesystem::path& png, int bits,
                                const IndirectionProvenance& provenance) {
  if (bits != 8 && bits != 16) throw Error(ErrorKind::InvalidArgument, png, "indirection maps have 8 or 16 bits");
  if (bits == 8) {
    const auto p = packIndirection<std::uint8_t>(map, 3);
    detail::writeIndirectionSidecar(png, bits, p.scale, p.bias, provenance);
    io::writePng(p.texels, png);
  } else {
    const auto p = packIndirection<std::uint16_t>(map, 3);
    detail::writeIndirectionSidecar(png, bits, p.scale, p.bias, provenance);
    io::writePng(p.texels, png);
  }
}

/// An indirection map as read back: I as floats, and what its sidecar says it was made for.
struct IndirectionFile {
  Image<float> map;  ///< 2 channels
  IndirectionProvenance provenance;
};

/// Reads `png` and its sidecar. Throws Error naming the file: no sidecar, a sidecar without a
/// finite scale and bias, or an image of fewer than 2 channels.
inline IndirectionFile readIndirectionMap(const std::filesystem::path& png) {
  const std::filesystem::path jsonPath = indirectionSidecar(png);
  const io::ImageFile image = io::readImage(png);
  std::ifstream in(jsonPath, std::ios::binary);
  if (!in)
    throw Error(ErrorKind::FileNotFound, jsonPath,
                "the indirection map's sidecar (its scale and bias) is missing; `cellrelief indirect` writes it beside the PNG");
  const std::string json{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::vector<double> scale = detail::jsonNumbers(json, "scale"), bias = detail::jsonNumbers(json, "bias");
  const auto finitePair = [](const std::vector<double>& v) {
    return v.size() == 2 && std::isfinite(v[0]) && std::isfinite(v[1]) && std::abs(v[0]) < 1e6 && std::abs(v[1]) < 1e6;
  };
  if (!finitePair(scale) || !finitePair(bias))
    throw Error(ErrorKind::FileFormat, jsonPath, "expected \"scale\": [su, sv] and \"bias\": [bu, bv], finite numbers");
  if (image.channels() < 2)
    throw Error(ErrorKind::FileFormat, png, "an indirection map needs 2 or more channels (R = I_u, G = I_v), not " +
                                                std::to_string(image.channels()));
  IndirectionFile out;
  out.map = Image<float>(image.width(), image.height(), 2);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const Vec4f q = image.fetch(x, y);
      out.map.at(x, y, 0) = float(bias[0] + scale[0] * double(q.x));
      out.map.at(x, y, 1) = float(bias[1] + scale[1] * double(q.y));
    }
  const std::vector<double> heightScale = detail::jsonNumbers(json, "height_scale");
  const std::vector<double> grid = detail::jsonNumbers(json, "grid");
  if (heightScale.size() == 1 && std::isfinite(heightScale[0]) && heightScale[0] >= 0 && heightScale[0] <= 100)
    out.provenance.heightScale = float(heightScale[0]);
  if (grid.size() == 1 && grid[0] >= 0 && grid[0] < 1e6) out.provenance.grid = int(grid[0]);
  return out;
}

}  // namespace cellrelief::indirection
