// SPDX-License-Identifier: MIT
/// @file fuzz_target.cpp
/// One libFuzzer target: CELLRELIEF_FUZZ_READER picks the reader (mesh, image, model) and
/// CELLRELIEF_FUZZ_EXTENSION the file extension it is handed, so every target is this file built
/// with two definitions (tests/fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <stb_image.h>

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
static long long jpegPixels(const std::uint8_t* b, std::size_t size) {
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
    if (frame && p + 9 <= size) return (long long)((b[p + 5] << 8) | b[p + 6]) * ((b[p + 7] << 8) | b[p + 8]);
    p += 2 + std::size_t((b[p + 2] << 8) | b[p + 3]);
  }
  return 0;
}

[[maybe_unused]] static bool withinPixelBudget(const std::uint8_t* data, std::size_t size) {
  constexpr long long kPixelBudget = 1 << 18;
  const std::string_view extension = CELLRELIEF_FUZZ_EXTENSION;
  if (extension == ".jpg") return jpegPixels(data, size) <= kPixelBudget;
  int w = 0, h = 0, channels = 0;  // PNG, TGA, BMP: stb reads only the header here
  if (size > (1u << 30) || !stbi_info_from_memory(data, int(size), &w, &h, &channels)) return true;
  return (long long)w * h <= kPixelBudget;
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
