// SPDX-License-Identifier: MIT
/// @file format_checks.h
/// Structure checks that run before OpenMesh parses a file, for the failures its readers pass over
/// silently: an OBJ vertex that is not a finite number (OpenMesh drops it and shifts every later
/// index), and a binary STL whose size does not match its triangle count. Each names the line or
/// count at fault. (OFF has its own reader, off_reader.h.)
#pragma once

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cellrelief/core/error.h"

namespace cellrelief::io::detail {

/// A finite decimal number, the whole token. Hexadecimal floats ("0x.5") are refused: strtod takes
/// them, but OpenMesh's stream extraction reads "0" and derails on the rest (as it does on a NUL).
inline bool parseFinite(std::string_view view, double& value) {
  // No hexadecimal floats, and no NUL bytes (strtod would stop at one and call the token whole).
  if (view.find_first_of(std::string_view("xXpP\0", 5)) != std::string_view::npos) return false;
  const std::string token(view);  // strtod needs the terminator (short tokens stay on the stack)
  const char* s = token.c_str();
  char* end = nullptr;
  value = std::strtod(s, &end);
  return end != s && *end == '\0' && std::isfinite(value);
}

/// A non-negative decimal integer, the whole token, below 2^62.
inline bool parseIndex(std::string_view token, long long& value) {
  if (token.empty() || token.size() > 18 || token.find_first_not_of("0123456789") != std::string_view::npos)
    return false;
  return std::from_chars(token.data(), token.data() + token.size(), value).ec == std::errc();
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
