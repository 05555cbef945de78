// SPDX-License-Identifier: MIT
/// @file format_checks.h
/// Structure checks that run before OpenMesh parses a file, for the failures its readers pass over
/// silently: an OBJ vertex that is not a finite number (OpenMesh drops it and shifts every later
/// index), an ASCII OFF shorter than its header says (OpenMesh fills the rest with zeros), and a
/// binary STL whose size does not match its triangle count. Each names the line or count at fault.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"

namespace cellrelief::io::detail {

/// A finite decimal number, the whole token. Hexadecimal floats ("0x.5") are refused: strtod takes
/// them, but OpenMesh's stream extraction reads "0" and derails on the rest (as it does on a NUL).
inline bool parseFinite(const std::string& token, double& value) {
  // No hexadecimal floats, and no NUL bytes (strtod would stop at one and call the token whole).
  if (token.find_first_of(std::string("xXpP\0", 5)) != std::string::npos) return false;
  const char* s = token.c_str();
  char* end = nullptr;
  value = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(value);
}

/// A non-negative decimal integer, the whole token, below 2^62.
inline bool parseIndex(const std::string& token, long long& value) {
  if (token.empty() || token.size() > 18 || token.find_first_not_of("0123456789") != std::string::npos)
    return false;
  value = std::stoll(token);
  return true;
}

/// One corner of an OBJ face, "v", "v/vt", "v//vn" or "v/vt/vn": each index a non-zero integer
/// (negative counts back from the last one) that names an element already defined.
struct ObjCornerProblem {
  ErrorKind kind = ErrorKind::FileFormat;  ///< FileFormat: malformed; InvalidInput: out of range
  std::string text;                        ///< empty: the corner is fine
};

inline ObjCornerProblem objCornerProblem(const std::string& corner, const std::array<long long, 3>& defined) {
  static constexpr const char* kNames[3] = {"vertex", "texture coordinate", "normal"};
  std::size_t start = 0;
  for (int part = 0; part < 3; ++part) {
    const std::size_t slash = corner.find('/', start);
    const std::string text = corner.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (!text.empty() || part == 0) {
      const bool negative = !text.empty() && text[0] == '-';
      long long index = 0;
      if (!parseIndex(negative ? text.substr(1) : text, index) || index == 0)
        return {ErrorKind::FileFormat, "face corner '" + corner + "' has no valid " + kNames[part] + " index"};
      if (index > defined[part])
        return {ErrorKind::InvalidInput, "face corner '" + corner + "' refers to " + kNames[part] + " " +
                                             (negative ? "-" : "") + std::to_string(index) + " but only " +
                                             std::to_string(defined[part]) + " are defined before it"};
    }
    if (slash == std::string::npos) return {};
    if (part == 2) return {ErrorKind::FileFormat, "face corner '" + corner + "' has more than three parts"};
    start = slash + 1;
  }
  return {};
}

/// Every `v` line has three finite coordinates, and every `f` corner indices that exist (OpenMesh
/// asserts, and aborts the program, on a corner without a vertex index such as "/6/5").
inline void checkObj(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t lineNo = 0;
  std::array<long long, 3> defined{0, 0, 0};  // v, vt, vn lines so far
  auto fail = [&](ErrorKind kind, const std::string& problem) {
    throw Error(kind, path, "line " + std::to_string(lineNo) + ": " + problem);
  };
  while (std::getline(in, line)) {
    ++lineNo;
    std::istringstream ls(line);
    std::string keyword;
    ls >> keyword;
    if (keyword == "vt") ++defined[1];
    if (keyword == "vn") ++defined[2];
    if (keyword == "f") {
      for (std::string corner; ls >> corner;)
        if (const ObjCornerProblem problem = objCornerProblem(corner, defined); !problem.text.empty())
          fail(problem.kind, problem.text);
    }
    if (keyword != "v") continue;
    ++defined[0];
    for (int k = 0; k < 3; ++k) {
      std::string token;
      double v;
      if (!(ls >> token)) fail(ErrorKind::FileFormat, "vertex has fewer than 3 coordinates");
      if (!parseFinite(token, v))
        fail(ErrorKind::InvalidInput, "vertex coordinate '" + token + "' is not a finite number");
    }
  }
}

inline int offDims(const std::string& prefix) { return prefix.find('4') != std::string::npos ? 4 : 3; }

/// A binary OFF: after the header line, vertex, face and edge counts (32-bit, big-endian as the
/// format says, or little-endian as some writers do), then the vertices and faces; the counts must
/// fit the file (a face needs at least its count and three indices).
inline void checkBinaryOffCounts(const std::filesystem::path& path, int dims) {
  std::ifstream in(path, std::ios::binary);
  std::string header;
  std::getline(in, header);
  unsigned char c[12] = {};
  in.read(reinterpret_cast<char*>(c), 12);
  const std::uint64_t size = std::filesystem::file_size(path);
  const std::uint64_t body = size > header.size() + 1 ? size - header.size() - 1 : 0;
  auto fits = [&](bool big) {
    auto at = [&](int i) {
      const unsigned char* p = c + 4 * i;
      return big ? (std::uint64_t(p[0]) << 24) | (std::uint64_t(p[1]) << 16) | (std::uint64_t(p[2]) << 8) | p[3]
                 : (std::uint64_t(p[3]) << 24) | (std::uint64_t(p[2]) << 16) | (std::uint64_t(p[1]) << 8) | p[0];
    };
    return in.gcount() == 12 && at(0) < (1u << 31) && at(1) < (1u << 31) &&
           12 + at(0) * 4 * std::uint64_t(dims) + at(1) * 16 <= body;
  };
  if (!fits(true) && !fits(false))
    throw Error(ErrorKind::FileFormat, path,
                "binary OFF whose vertex and face counts do not fit its " + std::to_string(size) +
                    " bytes (truncated or corrupt)");
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
  // The header word exactly: [ST][C][N][4]OFF (OpenMesh reads anything else, NUL bytes and all,
  // into loops that never end).
  const std::size_t off = magic.find("OFF");
  const std::string pre = off == std::string::npos ? magic : magic.substr(0, off);
  const bool known = off != std::string::npos && off + 3 == magic.size() && [&] {
    std::size_t k = 0;
    for (const char* part : {"ST", "C", "N", "4"})
      if (pre.compare(k, std::strlen(part), part) == 0) k += std::strlen(part);
    return k == pre.size();
  }();
  if (!known)
    fail(ErrorKind::FileFormat, "not an OFF file: the header word is '" + magic.substr(0, 40) +
                                    "', not [ST][C][N][4]OFF");
  std::string rest;
  std::getline(hs, rest);  // counts, or BINARY, may follow the magic word on the same line
  {
    std::istringstream rs(rest);
    for (std::string t; rs >> t;) {
      long long v;
      if (t != "BINARY" && !parseIndex(t, v))
        fail(ErrorKind::FileFormat, "unexpected '" + t.substr(0, 40) + "' after the OFF header word");
    }
  }
  if (rest.find("BINARY") != std::string::npos) {
    checkBinaryOffCounts(path, offDims(pre));
    return;
  }
  if (rest.find_first_not_of(" \t\r") == std::string::npos && nextLine(line)) rest = line;
  // The counts: vertices, faces and (often left out) edges, plain integers and nothing else.
  std::vector<std::string> counts;
  {
    std::istringstream cs(rest);
    for (std::string t; cs >> t;) counts.push_back(t);
  }
  long long nv = -1, nf = -1, ne = 0;
  if (counts.size() < 2 || counts.size() > 3 || !parseIndex(counts[0], nv) || !parseIndex(counts[1], nf) ||
      (counts.size() == 3 && !parseIndex(counts[2], ne)))
    fail(ErrorKind::FileFormat, "OFF header has no vertex, face and edge counts (three integers): '" +
                                    rest.substr(0, 60) + "'");
  // No vertex or no face is no surface, and OpenMesh's reader loops on such a header followed by
  // anything: refused before it runs.
  if (nv == 0 || nf == 0)
    fail(ErrorKind::InvalidInput, "the OFF header declares " + std::to_string(nv) + " vertices and " +
                                      std::to_string(nf) + " faces: no surface");
  // The header word's prefixes say what each vertex line holds: [ST][C][N][4]OFF, texture
  // coordinates (2), a color (3 or 4, or 1 color-map index), a normal (3), a fourth coordinate.
  // OpenMesh reads the values it expects from each line; a line short of them, or a token that is
  // not a number, derails every later line.
  const std::string& prefix = pre;
  const int dims = offDims(prefix);
  const int needed = dims + (prefix.find('N') != std::string::npos ? 3 : 0) +
                     (prefix.find("ST") != std::string::npos ? 2 : 0) +
                     (prefix.find('C') != std::string::npos ? 1 : 0);
  for (long long i = 0; i < nv; ++i) {
    if (!nextLine(line))
      fail(ErrorKind::FileFormat, "file ends early: the header declares " + std::to_string(nv) +
                                      " vertices, found " + std::to_string(i) + " (truncated file)");
    const std::string where = "line " + std::to_string(lineNo) + ": vertex " + std::to_string(i);
    std::istringstream ls(line);
    int count = 0;
    for (std::string token; ls >> token; ++count) {
      double v;
      if (!parseFinite(token, v))
        fail(count < dims ? ErrorKind::InvalidInput : ErrorKind::FileFormat,
             where + (count < dims ? " coordinate '" : " value '") + token + "' is not a finite number");
    }
    if (count < needed)
      fail(ErrorKind::FileFormat, where + " has " + std::to_string(count) + " values, a " + magic +
                                      " vertex needs at least " + std::to_string(needed));
  }
  // OpenMesh reads face lines as a stream of numbers: a count or index that is not a plain
  // integer, or values after a face of fewer than 3 corners (which it skips without reading them),
  // shift every later face, and a count it then reads from a coordinate sends it into a loop that
  // never ends. So each face line is checked whole: the count and indices are plain integers, and
  // what follows them (a color) only on a face it keeps.
  for (long long i = 0; i < nf; ++i) {
    if (!nextLine(line))
      fail(ErrorKind::FileFormat, "file ends early: the header declares " + std::to_string(nf) +
                                      " faces, found " + std::to_string(i) + " (truncated file)");
    const std::string where = "line " + std::to_string(lineNo) + ": face " + std::to_string(i);
    std::istringstream ls(line);
    std::vector<std::string> tokens;
    for (std::string t; ls >> t;) tokens.push_back(t);
    long long n = -1;
    if (tokens.empty() || !parseIndex(tokens[0], n))
      fail(ErrorKind::FileFormat, where + " has no corner count (a non-negative integer)");
    if (std::size_t(n) + 1 > tokens.size())
      fail(ErrorKind::FileFormat, where + " has fewer than " + std::to_string(n) + " vertex indices");
    for (long long k = 0; k < n; ++k) {
      long long index = -1;
      if (!parseIndex(tokens[std::size_t(k) + 1], index))
        fail(ErrorKind::FileFormat, where + " has a vertex index '" + tokens[std::size_t(k) + 1] +
                                        "' that is not a non-negative integer");
      if (index >= nv)
        fail(ErrorKind::InvalidInput, where + " refers to vertex " + std::to_string(index) +
                                          " but there are only " + std::to_string(nv) + " vertices");
    }
    const std::size_t extra = tokens.size() - std::size_t(n) - 1;
    if (n < 3 && extra > 0)
      fail(ErrorKind::FileFormat, where + " has " + std::to_string(n) +
                                      " corners and more values after them (a face needs 3 corners)");
    for (std::size_t k = std::size_t(n) + 1; k < tokens.size(); ++k) {
      double v;
      if (!parseFinite(tokens[k], v))
        fail(ErrorKind::FileFormat, where + " has a color value '" + tokens[k] + "' that is not a number");
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
