// SPDX-License-Identifier: MIT
/// @file image_checks.h
/// Structure checks that run before stb_image decodes a file, for what stb (Debian's 2.27) gets
/// wrong, found by fuzzing (tests/fuzz):
/// - a JPEG Huffman table whose 16 code counts add up to more than 256 symbols makes stb write past
///   its tables (fixed upstream in 2.28);
/// - a PNG chunk longer than the file makes stb allocate what it claims;
/// - an uncompressed TGA or BMP shorter than its header's width x height needs is decoded anyway,
///   the missing pixels read as zeros: a silent wrong image, and a 40-byte file that claims
///   16384 x 16384 pixels costs seconds and a gigabyte.
/// Each returns the problem, or an empty string when the file passes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace cellrelief::io::detail {

inline std::uint32_t le16(const std::vector<unsigned char>& b, std::size_t at) {
  return std::uint32_t(b[at]) | (std::uint32_t(b[at + 1]) << 8);
}
inline std::uint32_t le32(const std::vector<unsigned char>& b, std::size_t at) {
  return le16(b, at) | (le16(b, at + 2) << 16);
}

/// Walks the JPEG's markers (through the entropy-coded data after each scan, where progressive
/// files define further tables) and checks every Huffman table's symbol count, and that every
/// table a scan decodes with was defined before it.
inline std::string checkJpegTables(const std::vector<unsigned char>& b) {
  std::size_t p = 2;  // past SOI
  unsigned definedDc = 0, definedAc = 0;  // Huffman tables 0..3 a DHT defined so far
  bool progressive = false;
  while (p + 1 < b.size()) {
    if (b[p] != 0xFF) {  // padding between segments: stb scans over it to the next marker
      ++p;
      continue;
    }
    while (p < b.size() && b[p] == 0xFF) ++p;  // fill bytes
    if (p >= b.size()) return "";
    const unsigned marker = b[p++];
    if (marker == 0xD9) return "";  // EOI
    if (marker == 0x01 || marker == 0xD8 || (marker >= 0xD0 && marker <= 0xD7)) continue;
    if (p + 2 > b.size()) return "";
    const std::size_t length = (std::size_t(b[p]) << 8) | b[p + 1];
    if (length < 2) return "";
    auto byteAt = [&](std::size_t i) -> std::size_t { return i < b.size() ? b[i] : 0; };
    if (marker == 0xC2) progressive = true;
    if (marker == 0xDA) {  // SOS: every Huffman table the scan decodes with was defined before it
      // (stb reads an undefined one from uninitialized memory). A progressive DC scan uses only
      // DC tables (none on refinement), an AC scan only AC tables; a baseline scan both.
      const std::size_t components = byteAt(p + 2);
      const std::size_t spectral = p + 3 + 2 * components;
      const bool dcScan = byteAt(spectral) == 0, firstPass = (byteAt(spectral + 2) >> 4) == 0;
      const bool needDc = !progressive || (dcScan && firstPass), needAc = !progressive || !dcScan;
      for (std::size_t c = 0; c < components; ++c) {
        const std::size_t tables = byteAt(p + 4 + 2 * c);
        if ((needDc && !(definedDc >> (tables >> 4) & 1u)) || (needAc && !(definedAc >> (tables & 15) & 1u)))
          return "corrupt JPEG: a scan decodes with a Huffman table that no DHT segment defined";
      }
    }
    if (marker == 0xC4) {  // DHT: tables of (class/id, 16 counts, symbols)
      // As stb reads it: to the segment's stated end, bytes past the end of the file as zeros.
      std::size_t q = p + 2;
      while (q < p + length && q < b.size()) {
        const std::size_t id = byteAt(q);
        if ((id >> 4) <= 1 && (id & 15) <= 3) ((id >> 4) == 0 ? definedDc : definedAc) |= 1u << (id & 15);
        std::size_t symbols = 0;
        for (int i = 0; i < 16; ++i) symbols += byteAt(q + 1 + std::size_t(i));
        if (symbols > 256)
          return "corrupt JPEG: a Huffman table defines " + std::to_string(symbols) +
                 " codes (at most 256)";
        q += 17 + symbols;
      }
    }
    p += length;
    if (marker == 0xDA) {  // SOS: skip the entropy-coded data to the next marker
      // As stb's decoder reads it: 0xFF, any 0xFF fill bytes, then 0x00 is a data byte, and a
      // restart marker stays in the data; anything else after 0xFF (and its fill) is a marker.
      while (p + 1 < b.size()) {
        if (b[p] != 0xFF) {
          ++p;
          continue;
        }
        std::size_t q = p + 1;
        while (q < b.size() && b[q] == 0xFF) ++q;
        if (q >= b.size()) return "";
        if (b[q] != 0x00 && !(b[q] >= 0xD0 && b[q] <= 0xD7)) {
          p = q - 1;  // at the last 0xFF before the marker
          break;
        }
        p = q + 1;
      }
    }
  }
  return "";
}

/// Every chunk of a PNG fits in the file: stb grows its data buffer to the lengths the chunks
/// claim before reading them, so a 94-byte file claiming a 2 GiB data chunk allocates 2 GiB.
inline std::string checkPngChunks(const std::vector<unsigned char>& b) {
  std::size_t p = 8;  // past the signature
  while (p + 8 <= b.size()) {
    const std::uint64_t length = (std::uint64_t(b[p]) << 24) | (std::uint64_t(b[p + 1]) << 16) |
                                 (std::uint64_t(b[p + 2]) << 8) | b[p + 3];
    const std::string type(b.begin() + std::ptrdiff_t(p + 4), b.begin() + std::ptrdiff_t(p + 8));
    if (p + 12 + length > b.size())
      return "truncated PNG: chunk '" + type + "' claims " + std::to_string(length) + " bytes, the file has " +
             std::to_string(b.size() - std::min(b.size(), p + 8)) + " after its header";
    if (type == "IEND") return "";
    p += 12 + length;
  }
  return "";
}

/// The coded data of a JPEG holds at least one bit per 8 x 8 block (the DC code of a baseline or
/// first progressive scan), so width x height <= 512 x its bytes; stb decodes a file cut short
/// anyway, the missing blocks grey: a silent wrong image, and slow when the header claims a huge one.
inline std::string checkJpegSize(std::uint64_t width, std::uint64_t height, std::uint64_t bytes) {
  if (width * height <= 512 * bytes) return "";
  return "truncated JPEG: " + std::to_string(width) + "x" + std::to_string(height) +
         " pixels need at least " + std::to_string((width * height + 511) / 512) +
         " bytes of coded data, the file has " + std::to_string(bytes);
}

/// An uncompressed TGA holds width x height pixels after its header, ID and color map; a
/// run-length encoded one at least one packet (1 + pixel bytes) per 128 pixels.
inline std::string checkTgaSize(const std::vector<unsigned char>& b) {
  if (b.size() < 18) return "too short for an image (a TGA header alone is 18 bytes)";
  const std::uint64_t idLength = b[0], mapLength = le16(b, 5), mapEntryBits = b[7];
  const std::uint64_t width = le16(b, 12), height = le16(b, 14), bits = b[16];
  const unsigned type = b[2];
  // TGA has no magic number, so this is also where a file of no format we read ends up: unless
  // its header is a TGA's, it is refused here, before stb tries its other decoders on it (PNM,
  // PSD, HDR, GIF, PIC: formats this project does not read, and a larger attack surface).
  const bool tgaHeader = b[1] <= 1 && (type == 1 || type == 2 || type == 3 || type == 9 || type == 10 || type == 11) &&
                         (bits == 8 || bits == 15 || bits == 16 || bits == 24 || bits == 32) && width > 0 && height > 0;
  if (!tgaHeader) return "not a readable PNG, JPEG, TGA or BMP image: no PNG, JPEG or BMP signature and no TGA header";
  const std::uint64_t data = 18 + idLength + (b[1] ? mapLength * ((mapEntryBits + 7) / 8) : 0);
  const std::uint64_t pixelBytes = (bits + 7) / 8, pixels = width * height;
  std::uint64_t need = 0;
  if (type <= 3) need = data + pixels * pixelBytes;
  else need = data + (pixels + 127) / 128 * (1 + pixelBytes);
  if (b.size() < need)
    return "truncated TGA: " + std::to_string(width) + "x" + std::to_string(height) + " at " +
           std::to_string(bits) + " bits needs at least " + std::to_string(need) + " bytes, the file has " +
           std::to_string(b.size());
  return "";
}

/// A BMP that is not run-length encoded (BI_RGB, BI_BITFIELDS, or any other value stb reads the
/// same way) holds |height| rows of 4-byte aligned pixels from
/// its data offset. (Run-length encoded ones go to the project's own decoder, bmp_rle.h.)
inline std::string checkBmpSize(const std::vector<unsigned char>& b) {
  if (b.size() < 26) return "truncated BMP: shorter than its headers";
  const std::uint64_t offset = le32(b, 10), dib = le32(b, 14);
  // stb reads a header cut short as zeros and the rest as pixels of whatever size it then says.
  if (b.size() < 14 + std::min<std::uint64_t>(dib, 40)) return "truncated BMP: shorter than its headers";
  std::uint64_t width = 0, height = 0, bits = 0, compression = 0;
  if (dib == 12) {  // OS/2 BITMAPCOREHEADER: 16-bit sizes
    width = le16(b, 18), height = le16(b, 20), bits = le16(b, 24);
  } else if (dib >= 40) {
    width = std::uint64_t(std::abs(std::int64_t(std::int32_t(le32(b, 18)))));
    height = std::uint64_t(std::abs(std::int64_t(std::int32_t(le32(b, 22)))));
    bits = le16(b, 28), compression = le32(b, 30);
  } else {
    return "";
  }
  // stb reads every compression but run-length (1, 2: bmp_rle.h) as uncompressed pixels.
  if (compression == 1 || compression == 2) return "";
  // Rows are padded to 4 bytes; some writers leave the last one unpadded.
  const std::uint64_t row = (width * bits + 31) / 32 * 4;
  const std::uint64_t need = height == 0 ? offset : offset + row * (height - 1) + (width * bits + 7) / 8;
  if (b.size() < need)
    return "truncated BMP: " + std::to_string(width) + "x" + std::to_string(height) + " at " +
           std::to_string(bits) + " bits needs " + std::to_string(need) + " bytes, the file has " +
           std::to_string(b.size());
  return "";
}

}  // namespace cellrelief::io::detail
