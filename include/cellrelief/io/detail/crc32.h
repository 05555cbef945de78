// SPDX-License-Identifier: MIT
/// @file crc32.h
/// CRC-32 (the zlib/PNG polynomial, reflected 0xEDB88320), table-driven, for file checksums.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace cellrelief::io::detail {

constexpr std::array<std::uint32_t, 256> makeCrcTable() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}
inline constexpr std::array<std::uint32_t, 256> kCrcTable = makeCrcTable();

/// Continues a CRC-32 over more bytes; start with crc = 0.
inline std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc = 0) {
  const auto* p = static_cast<const unsigned char*>(data);
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) crc = kCrcTable[(crc ^ p[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

static_assert(makeCrcTable()[1] == 0x77073096u);

}  // namespace cellrelief::io::detail
