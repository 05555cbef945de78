// SPDX-License-Identifier: MIT
/// @file format_checks.h
/// Structure checks that run before OpenMesh parses a file, for the failures its readers pass over
/// silently: an OBJ vertex that is not a finite number (OpenMesh drops it and shifts every later
/// index), an ASCII OFF shorter than its header says (OpenMesh fills the rest with zeros), and a
/// binary STL whose size does not match its triangle count. Each names the line or count at fault.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cellrelief/core/error.h"

namespace cellrelief::io::detail {

inline bool parseFinite(const std::string& token, double& value) {
  const char* s = token.c_str();
  char* end = nullptr;
  value = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(value);
}

/// Every `v` line has three finite coordinates.
inline void checkObj(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
    std::istringstream ls(line.substr(2));
    for (int k = 0; k < 3; ++k) {
      std::string token;
      double v;
      if (!(ls >> token))
        throw Error(ErrorKind::FileFormat, path,
                    "line " + std::to_string(lineNo) + ": vertex has fewer than 3 coordinates");
      if (!parseFinite(token, v))
        throw Error(ErrorKind::InvalidInput, path,
                    "line " + std::to_string(lineNo) + ": vertex coordinate '" + token +
                        "' is not a finite number");
    }
  }
}

/// The header's counts are met by the body, and vertex coordinates are finite (ASCII OFF only).
inline void checkOff(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t lineNo = 0;
  auto nextLine = [&](std::string& out) {
    while (std::getline(in, out)) {
      ++lineNo;
      const auto hash = out.find('#');
      if (hash != std::string::npos) out.erase(hash);
      if (out.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
  };
  auto fail = [&](ErrorKind kind, const std::string& problem) {
    throw Error(kind, path, problem);
  };
  if (!nextLine(line)) fail(ErrorKind::FileFormat, "no OFF header");
  std::istringstream hs(line);
  std::string magic;
  hs >> magic;
  if (magic.find("OFF") == std::string::npos) fail(ErrorKind::FileFormat, "not an OFF file (no 'OFF' header)");
  std::string rest;
  std::getline(hs, rest);  // counts may follow the magic word on the same line
  if (rest.find("BINARY") != std::string::npos) return;  // binary OFF: left to OpenMesh
  if (rest.find_first_not_of(" \t\r") == std::string::npos && nextLine(line)) rest = line;
  long long nv = -1, nf = -1;
  std::istringstream cs(rest);
  cs >> nv >> nf;
  if (nv < 0 || nf < 0) fail(ErrorKind::FileFormat, "OFF header has no vertex and face counts");
  const int dims = magic.find("4OFF") != std::string::npos ? 4 : 3;
  for (long long i = 0; i < nv; ++i) {
    if (!nextLine(line))
      fail(ErrorKind::FileFormat, "file ends early: the header declares " + std::to_string(nv) +
                                      " vertices, found " + std::to_string(i) + " (truncated file)");
    std::istringstream ls(line);
    for (int k = 0; k < dims; ++k) {
      std::string token;
      double v;
      if (!(ls >> token))
        fail(ErrorKind::FileFormat, "line " + std::to_string(lineNo) + ": vertex " +
                                        std::to_string(i) + " has fewer than 3 coordinates");
      if (!parseFinite(token, v))
        fail(ErrorKind::InvalidInput, "line " + std::to_string(lineNo) + ": vertex " +
                                          std::to_string(i) + " coordinate '" + token +
                                          "' is not a finite number");
    }
  }
  for (long long i = 0; i < nf; ++i) {
    if (!nextLine(line))
      fail(ErrorKind::FileFormat, "file ends early: the header declares " + std::to_string(nf) +
                                      " faces, found " + std::to_string(i) + " (truncated file)");
    std::istringstream ls(line);
    long long n = -1, index = 0;
    ls >> n;
    if (n < 0) fail(ErrorKind::FileFormat, "line " + std::to_string(lineNo) + ": face " +
                                               std::to_string(i) + " has no corner count");
    for (long long k = 0; k < n; ++k) {
      if (!(ls >> index))
        fail(ErrorKind::FileFormat, "line " + std::to_string(lineNo) + ": face " +
                                        std::to_string(i) + " has fewer than " +
                                        std::to_string(n) + " vertex indices");
      if (index < 0 || index >= nv)
        fail(ErrorKind::InvalidInput, "line " + std::to_string(lineNo) + ": face " +
                                          std::to_string(i) + " refers to vertex " +
                                          std::to_string(index) + " but there are only " +
                                          std::to_string(nv) + " vertices");
    }
  }
}

/// A binary STL has at least 84 + 50 n bytes (some writers pad); an ASCII one ends with `endsolid`.
inline void checkStl(const std::filesystem::path& path) {
  const auto size = std::filesystem::file_size(path);
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  in.read(head, sizeof head);
  std::uint32_t declared = 0;
  std::memcpy(&declared, head + 80, 4);
  // A binary file of exactly the declared size is binary even when its header says "solid".
  const bool exactBinary = size >= 84 && size == 84 + 50ull * declared;
  const bool ascii = !exactBinary && std::strncmp(head, "solid", 5) == 0 && [&] {
    std::ifstream text(path);
    std::string all((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
    return all.find("facet") != std::string::npos || size < 84;
  }();
  if (ascii) {
    std::ifstream text(path);
    std::string all((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
    if (all.find("endsolid") == std::string::npos)
      throw Error(ErrorKind::FileFormat, path, "ASCII STL without 'endsolid' (truncated file)");
    return;
  }
  if (size < 84) throw Error(ErrorKind::FileFormat, path, "binary STL shorter than its 84-byte header");
  std::uint32_t count = 0;
  std::memcpy(&count, head + 80, 4);
  const std::uint64_t expected = 84 + 50ull * count;
  if (size < expected)
    throw Error(ErrorKind::FileFormat, path,
                "binary STL declares " + std::to_string(count) + " triangles (" +
                    std::to_string(expected) + " bytes) but has " + std::to_string(size) +
                    " bytes (truncated or not STL)");
}

}  // namespace cellrelief::io::detail
