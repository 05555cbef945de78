// SPDX-License-Identifier: MIT
/// @file fuzz_readers.h
/// What every fuzz target does with its input: hand the bytes to one of the project's readers
/// through a file (the readers' public API takes paths, and the format comes from the extension),
/// then use what was read the way `cellrelief info` and the tracer would. A reader may refuse the
/// input with cellrelief::Error; anything else (a crash, another exception, a sanitizer report, a
/// leak, a stall) is a defect. The same functions replay the corpus and every input that ever failed
/// in the ordinary test build (fuzz_regressions), so a fixed defect stays fixed without clang.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>

namespace cellrelief::fuzz {

/// Reads the bytes as a mesh file with this extension (".obj", ".ply", ".off", ".stl").
/// Returns true when the reader accepted the file.
bool readMeshBytes(std::string_view extension, const std::uint8_t* data, std::size_t size);
/// Reads the bytes as an image file (".png", ".jpg", ".tga", ".bmp").
bool readImageBytes(std::string_view extension, const std::uint8_t* data, std::size_t size,
                    std::uint64_t maxPixels = std::numeric_limits<std::uint64_t>::max());
/// Reads the bytes as a relief model (.crm). When `fixChecksum` is set the last four bytes are
/// replaced by the checksum of the rest first, so mutations reach the checks behind the CRC.
bool readModelBytes(const std::uint8_t* data, std::size_t size, bool fixChecksum);
/// Reads the bytes as a geometry-texture model (.cgt), checksum fixed on request as for .crm, and
/// ray casts what was read.
bool readGeoTexBytes(const std::uint8_t* data, std::size_t size, bool fixChecksum);
/// Reads the bytes as a polycube cube file (.txt) and checks its surface as `cellrelief polycube
/// --cubes` does.
bool readPolycubeBytes(const std::uint8_t* data, std::size_t size);
/// Reads the bytes as a mesh with its polycube texture positions (mesh_texture.obj, `v`, `vt u v
/// w`, `f a/t b/t c/t`) and checks what was read as a renderer would.
bool readPolycubeMapBytes(const std::uint8_t* data, std::size_t size);

}  // namespace cellrelief::fuzz
