// SPDX-License-Identifier: MIT
/// @file bmp_rle.h
/// Decoder for run-length encoded 8-bit and 4-bit BMPs (BI_RLE8, BI_RLE4), which stb_image does not
/// read; real height maps are stored that way (Irrlicht's terrain-heightmap.bmp). Output is RGB8,
/// top row first, like stb's palettized BMP path, so both kinds of BMP load alike.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cellrelief/core/image.h"

namespace cellrelief::io::detail {

/// True when the bytes are a BMP with RLE8 or RLE4 compression.
inline bool isRleBmp(const std::vector<unsigned char>& b) {
  if (b.size() < 54 || b[0] != 'B' || b[1] != 'M') return false;
  std::uint32_t compression;
  std::memcpy(&compression, &b[30], 4);
  return compression == 1 || compression == 2;
}

/// Decodes an RLE BMP; `problem` is set (and an empty image returned) when the data is malformed.
inline Image<std::uint8_t> decodeRleBmp(const std::vector<unsigned char>& b, std::string& problem) {
  auto u32 = [&](std::size_t o) { std::uint32_t v; std::memcpy(&v, &b[o], 4); return v; };
  auto i32 = [&](std::size_t o) { std::int32_t v; std::memcpy(&v, &b[o], 4); return v; };
  auto u16 = [&](std::size_t o) { std::uint16_t v; std::memcpy(&v, &b[o], 2); return v; };
  const std::uint32_t dataOffset = u32(10), headerSize = u32(14);
  const std::int32_t width = i32(18), rawHeight = i32(22);
  const int bits = u16(28);
  const std::uint32_t compression = u32(30);
  std::uint32_t paletteSize = u32(46);
  if (width <= 0 || rawHeight == 0 || width > 65536 || std::abs(rawHeight) > 65536 ||
      (bits != 8 && bits != 4) || (compression == 1) != (bits == 8)) {
    problem = "RLE BMP with unsupported size or bit depth";
    return {};
  }
  // A run codes at most 255 pixels in 2 bytes; end-of-line and end-of-bitmap codes leave the rest
  // as background, so more is possible, but not 256 times more: beyond that a small file that
  // claims a huge image is a decompression bomb, refused before it costs the memory.
  const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(std::abs(rawHeight));
  if (pixels > 256 * std::uint64_t(b.size()) + 65536) {
    problem = "RLE BMP of " + std::to_string(width) + "x" + std::to_string(std::abs(rawHeight)) +
              " pixels in " + std::to_string(b.size()) + " bytes: more than run-length coding can hold";
    return {};
  }
  if (paletteSize == 0) paletteSize = 1u << bits;
  const std::size_t paletteOffset = 14 + headerSize;
  if (paletteOffset + 4ull * paletteSize > b.size() || dataOffset >= b.size()) {
    problem = "RLE BMP palette or pixel data lies outside the file (truncated?)";
    return {};
  }
  const bool bottomUp = rawHeight > 0;
  const int height = std::abs(rawHeight);
  std::vector<std::uint8_t> indices(std::size_t(width) * height, 0);
  int x = 0, y = 0;  // y counts rows in file order
  std::size_t p = dataOffset;
  auto put = [&](std::uint8_t index) {
    if (x < width && y < height) indices[std::size_t(y) * width + x] = index;
    ++x;
  };
  bool done = false;
  while (!done) {
    if (p + 1 >= b.size()) {
      problem = "RLE BMP data ends before its end-of-bitmap marker (truncated file)";
      return {};
    }
    const std::uint8_t count = b[p], value = b[p + 1];
    p += 2;
    if (count > 0) {  // a run
      for (int k = 0; k < count; ++k)
        put(bits == 8 ? value : (k % 2 == 0 ? value >> 4 : value & 15));
      continue;
    }
    if (value == 0) {  // end of line
      x = 0;
      ++y;
    } else if (value == 1) {  // end of bitmap
      done = true;
    } else if (value == 2) {  // delta
      if (p + 1 >= b.size()) {
        problem = "RLE BMP delta goes past the end of the file (truncated file)";
        return {};
      }
      x += b[p];
      y += b[p + 1];
      p += 2;
    } else {  // absolute mode: `value` literal indices, padded to 16 bits
      const std::size_t bytes = bits == 8 ? value : (value + 1) / 2;
      if (p + bytes > b.size()) {
        problem = "RLE BMP literal run goes past the end of the file (truncated file)";
        return {};
      }
      for (int k = 0; k < value; ++k)
        put(bits == 8 ? b[p + k] : (k % 2 == 0 ? b[p + k / 2] >> 4 : b[p + k / 2] & 15));
      p += bytes + (bytes & 1);
    }
    if (y >= height || x > 1 << 20) done = true;  // past the last row: nothing more to place
  }
  Image<std::uint8_t> image(width, height, 3);
  for (int row = 0; row < height; ++row) {
    const int outRow = bottomUp ? height - 1 - row : row;
    for (int col = 0; col < width; ++col) {
      const std::uint32_t index = indices[std::size_t(row) * width + col];
      if (index >= paletteSize) {
        problem = "RLE BMP pixel refers to palette entry " + std::to_string(index) +
                  " of " + std::to_string(paletteSize);
        return {};
      }
      const std::size_t e = paletteOffset + 4ull * index;  // palette entries are B, G, R, 0
      image.at(col, outRow, 0) = b[e + 2];
      image.at(col, outRow, 1) = b[e + 1];
      image.at(col, outRow, 2) = b[e + 0];
    }
  }
  return image;
}

}  // namespace cellrelief::io::detail
