// SPDX-License-Identifier: MIT
/// @file fuzz_target.cpp
/// One libFuzzer target: CELLRELIEF_FUZZ_READER picks the reader (mesh, image, model, ...) and
/// CELLRELIEF_FUZZ_EXTENSION the file extension it is handed, so every target is this file built
/// with two definitions (tests/fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdint>

#include "fuzz_readers.h"

#define CELLRELIEF_FUZZ_MESH 1
#define CELLRELIEF_FUZZ_IMAGE 2
#define CELLRELIEF_FUZZ_MODEL 3
#define CELLRELIEF_FUZZ_POLYCUBE 4
#define CELLRELIEF_FUZZ_POLYCUBE_MAP 5
#define CELLRELIEF_FUZZ_GEOTEX 6

/// Decoding costs about 0.3 us a pixel in the release build and 20 times that under ASan and
/// UBSan, so an image of more than 2^18 pixels (a 2.9 KB JPEG can claim 625,000) passes the 1 s
/// limit under the sanitizers without being slow in use: the image targets refuse such images
/// (ImageReadOptions::maxPixels), and the release build's replay of tests/fuzz/regressions reads
/// them whole (valid-tall-image-slow-under-sanitizers.jpg: 0.17 s there, 3 s here).
[[maybe_unused]] constexpr std::uint64_t kPixelBudget = 1 << 18;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#if CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_MESH
  cellrelief::fuzz::readMeshBytes(CELLRELIEF_FUZZ_EXTENSION, data, size);
#elif CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_IMAGE
  cellrelief::fuzz::readImageBytes(CELLRELIEF_FUZZ_EXTENSION, data, size, kPixelBudget);
#elif CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_MODEL
  // Half the inputs as they are (the header and checksum checks), half with the checksum made
  // right, so that mutations of the look-up table and maps reach the checks behind it.
  cellrelief::fuzz::readModelBytes(data, size, size > 0 && (data[size - 1] & 1));
#elif CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_POLYCUBE
  cellrelief::fuzz::readPolycubeBytes(data, size);
#elif CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_POLYCUBE_MAP
  cellrelief::fuzz::readPolycubeMapBytes(data, size);
#elif CELLRELIEF_FUZZ_READER == CELLRELIEF_FUZZ_GEOTEX
  cellrelief::fuzz::readGeoTexBytes(data, size, size > 0 && (data[size - 1] & 1));
#else
#error "CELLRELIEF_FUZZ_READER must be CELLRELIEF_FUZZ_MESH, _IMAGE, _MODEL, _POLYCUBE, _POLYCUBE_MAP or _GEOTEX"
#endif
  return 0;
}
