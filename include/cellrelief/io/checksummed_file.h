// SPDX-License-Identifier: MIT
/// @file checksummed_file.h
/// The discipline every binary file of the project follows (.crm relief models, .cgt geometry
/// textures): a fixed header that starts with 8 magic bytes, a version and the header's own size;
/// sections; then a CRC-32 of everything before it. Writing goes to a temporary file renamed into
/// place only when complete. Reading checks the magic, the version, the header's size and the
/// file's size against what the header describes before anything is allocated, and the checksum
/// at the end; every failure names the file and the problem.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cellrelief/core/error.h"
#include "cellrelief/io/atomic_file.h"
#include "cellrelief/io/detail/crc32.h"

namespace cellrelief::io {

/// A header of a checksummed file: 8 magic bytes, then the version and the header's size.
template <class H>
concept ChecksummedHeader = requires(H h) {
  { h.magic[7] } -> std::convertible_to<char>;
  { h.version } -> std::convertible_to<std::uint32_t>;
  { h.headerBytes } -> std::convertible_to<std::uint32_t>;
};

class ChecksummedWriter {
 public:
  explicit ChecksummedWriter(const std::filesystem::path& path) : mFile(path), mOut(mFile.temporaryPath(), std::ios::binary) {
    if (!mOut) throw Error(ErrorKind::FileWrite, path, "cannot create the file");
  }

  void put(const void* data, std::size_t size) {
    mOut.write(static_cast<const char*>(data), std::streamsize(size));
    mCrc = detail::crc32(data, size, mCrc);
  }

  /// Appends the checksum and renames the file into place.
  void commit() {
    mOut.write(reinterpret_cast<const char*>(&mCrc), sizeof mCrc);
    mOut.flush();
    if (!mOut) throw Error(ErrorKind::FileWrite, mFile.target(), "write failed (disk full?)");
    mOut.close();
    mFile.commit();
  }

 private:
  AtomicFile mFile;
  std::ofstream mOut;
  std::uint32_t mCrc = 0;
};

class ChecksummedReader {
 public:
  /// Opens the file; `what` names the kind of file in messages ("a cellrelief model").
  ChecksummedReader(const std::filesystem::path& path, std::string what) : mPath(path), mWhat(std::move(what)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(ErrorKind::FileNotFound, path, "no such file");
    mIn.open(path, std::ios::binary);
    if (!mIn) throw Error(ErrorKind::FileNotFound, path, "cannot open for reading");
    mSize = std::filesystem::file_size(path);
  }

  std::uint64_t size() const { return mSize; }

  [[noreturn]] void fail(const std::string& problem) const { throw Error(ErrorKind::FileFormat, mPath, problem); }

  /// Reads and checks the header's magic, version and size.
  template <ChecksummedHeader H>
  H readHeader(const char (&magic)[8], std::uint32_t version) {
    H h{};
    if (mSize < 12) fail("too short to be " + mWhat + " (" + std::to_string(mSize) + " bytes)");
    mIn.read(reinterpret_cast<char*>(&h), std::streamsize(std::min<std::uint64_t>(mSize, sizeof h)));
    if (std::memcmp(h.magic, magic, 8) != 0) fail("not " + mWhat + " (wrong magic bytes)");
    if (h.version != version)
      fail("file format version " + std::to_string(h.version) + ", this build reads version " +
           std::to_string(version));
    if (mSize < sizeof h + 4) fail("truncated: the header is incomplete");
    if (h.headerBytes != sizeof h) fail("corrupted header (header size " + std::to_string(h.headerBytes) + ")");
    mCrc = detail::crc32(&h, sizeof h);
    return h;
  }

  /// Checks that the file is exactly as long as the header says (sections and checksum).
  void expectSize(std::uint64_t expected) const {
    if (mSize < expected)
      fail("truncated: " + std::to_string(mSize) + " bytes, the header describes " + std::to_string(expected));
    if (mSize > expected) fail("corrupted: " + std::to_string(mSize - expected) + " unexpected trailing bytes");
  }

  void read(void* data, std::uint64_t bytes) {
    mIn.read(static_cast<char*>(data), std::streamsize(bytes));
    if (!mIn) fail("truncated while reading");
    mCrc = detail::crc32(data, bytes, mCrc);
  }

  /// Reads the stored checksum and compares it with the bytes read.
  void finish() {
    std::uint32_t stored = 0;
    mIn.read(reinterpret_cast<char*>(&stored), 4);
    if (!mIn) fail("truncated: the checksum is missing");
    if (stored != mCrc) fail("checksum mismatch: the file is corrupted");
  }

 private:
  std::filesystem::path mPath;
  std::string mWhat;
  std::ifstream mIn;
  std::uint64_t mSize = 0;
  std::uint32_t mCrc = 0;
};

}  // namespace cellrelief::io
