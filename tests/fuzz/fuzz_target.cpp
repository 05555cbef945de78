// SPDX-License-Identifier: MIT
/// @file fuzz_target.cpp
/// One libFuzzer target: CELLRELIEF_FUZZ_READER picks the reader (mesh, image, model) and
/// CELLRELIEF_FUZZ_EXTENSION the file extension it is handed, so every target is this file built
/// with two definitions (tests/fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdlib>
#include <cstdint>
#include <string_view>

#include "fuzz_readers.h"

#define CELLRELIEF_FUZZ_MESH 1
#define CELLRELIEF_FUZZ_IMAGE 2
#define CELLRELIEF_FUZZ_MODEL 3

/// Decoding costs about 0.3 us a pixel in the release build and 20 times that under ASan and
/// UBSan, so an image of more than 2^18 pixels (a 2.9 KB JPEG can claim 625,000) passes the 1 s
/// limit under the sanitizers without being slow in use: such inputs are skipped here and read by
/// the release build's replay of tests/fuzz/regressions (valid-tall-image-slow-under-sanitizers.jpg:
/// 0.17 s there, 3 s here).
/// The size a JPEG's frame header states, read without stb (whose header scan already runs the
/// table code the readers' checks guard): 0 when there is none.
static double jpegPixels(const std::uint8_t* b, std::size_t size) {
  std::size_t p = 2;
  while (p + 4 <= size) {
    if (b[p] != 0xFF) {
      ++p;
      continue;
    }
    const unsigned marker = b[p + 1];
    if (marker == 0xFF || marker == 0xD8 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {
      ++p;
      continue;
    }
    const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame && p + 9 <= size) return double((b[p + 5] << 8) | b[p + 6]) * double((b[p + 7] << 8) | b[p + 8]);
    p += 2 + std::size_t((b[p + 2] << 8) | b[p + 3]);
  }
  return 0;
}

/// The size the header of a PNG (IHDR), TGA or BMP states, or 0 when it is too short. Read here,
/// not by stbi_info, which tries every format (JPEG's table code among them) on what is not its own.
static double headerPixels(std::string_view extension, const std::uint8_t* b, std::size_t size) {
  auto be32 = [&](std::size_t i) { return (long long)b[i] << 24 | (long long)b[i + 1] << 16 | b[i + 2] << 8 | b[i + 3]; };
  auto le16 = [&](std::size_t i) { return (long long)(b[i] | b[i + 1] << 8); };
  auto le32abs = [&](std::size_t i) {
    return std::llabs((long long)std::int32_t(std::uint32_t(b[i]) | std::uint32_t(b[i + 1]) << 8 |
                                              std::uint32_t(b[i + 2]) << 16 | std::uint32_t(b[i + 3]) << 24));
  };
  // In double: two 32-bit sizes overflow a 64-bit product.
  if (extension == ".png") return size >= 24 ? double(be32(16)) * double(be32(20)) : 0;
  if (extension == ".tga") return size >= 16 ? double(le16(12)) * double(le16(14)) : 0;
  if (extension == ".bmp") return size >= 26 ? double(le32abs(18)) * double(le32abs(22)) : 0;
  return 0;
}

[[maybe_unused]] static bool withinPixelBudget(const std::uint8_t* data, std::size_t size) {
  constexpr double kPixelBudget = 1 << 18;
  const std::string_view extension = CELLRELIEF_FUZZ_EXTENSION;
  return (extension == ".jpg" ? jpegPixels(data, size) : headerPixels(extension, data, size)) <= kPixelBudget;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#if CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_MESH
  cellrelief::fuzz::readMeshBytes(CELLRELIEF_FUZZ_EXTENSION, data, size);
#elif CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_IMAGE
  if (!withinPixelBudget(data, size)) return 0;
  cellrelief::fuzz::readImageBytes(CELLRELIEF_FUZZ_EXTENSION, data, size);
#elif CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_MODEL
  // Half the inputs as they are (the header and checksum checks), half with the checksum made
  // right, so that mutations of the look-up table and maps reach the checks behind it.
  cellrelief::fuzz::readModelBytes(data, size, size > 0 && (data[size - 1] & 1));
#else
#error "CELLRELIEF_FUZZ_READER must be CELLRELIEF_FUZZ_MESH, _IMAGE or _MODEL"
#endif
  return 0;
}
