// SPDX-License-Identifier: MIT
/// @file ply_scan.h
/// A PLY structure scanner that runs next to OpenMesh's PLY reader. OpenMesh reads vertices and
/// faces; this walks every element of the body to (a) find truncation, which OpenMesh reports for
/// some elements and not others, and (b) decode `tristrips` elements, which OpenMesh does not know
/// (the Igea model is stored as one strip with -1 restarts).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/math.h"

namespace cellrelief::io::detail {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
  std::string name;
  int size = 0;          // bytes of the value type (of the items, for lists)
  bool isFloat = false;  // float or double
  bool isSigned = false;
  bool isList = false;
  int countSize = 0;     // bytes of the list count type
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyScan {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::vector<Vec3u> stripTriangles;  // triangles decoded from tristrips elements
  bool hasStrips = false;
};

inline int plyTypeSize(const std::string& t, bool& isFloat, bool& isSigned) {
  isFloat = (t == "float" || t == "float32" || t == "double" || t == "float64");
  isSigned = isFloat || t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" ||
             t == "int32";
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" ||
      t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

/// Whether a format line's version token is 1.0, the only PLY version ("1", "1.0", "1.00").
inline bool plyVersionOne(const std::string& v) {
  if (v.empty() || v[0] != '1') return false;
  if (v.size() == 1) return true;
  if (v[1] != '.') return false;
  return std::all_of(v.begin() + 2, v.end(), [](char c) { return c == '0'; });
}

/// An element count: decimal digits only, at most 18 of them (beyond any file); nothing else.
inline std::optional<std::uint64_t> plyCount(const std::string& t) {
  if (t.empty() || t.size() > 18) return std::nullopt;
  std::uint64_t n = 0;
  for (char c : t) {
    if (c < '0' || c > '9') return std::nullopt;
    n = 10 * n + std::uint64_t(c - '0');
  }
  return n;
}

/// Appends the triangles of one strip; odd triangles are flipped to keep the winding, and the
/// degenerate triangles that stitch strips together are dropped.
inline void appendStrip(const std::vector<std::int64_t>& strip, std::vector<Vec3u>& out) {
  for (std::size_t i = 2; i < strip.size(); ++i) {
    std::int64_t a = strip[i - 2], b = strip[i - 1], c = strip[i];
    if (i % 2 == 1) std::swap(a, b);
    if (a == b || b == c || a == c) continue;
    out.push_back(Vec3u(std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)));
  }
}

class PlyBodyReader {
 public:
  PlyBodyReader(std::istream& in, PlyFormat format) : mIn(in), mFormat(format) {}

  /// ASCII only: starts the next item, one line of the body (blank lines skipped); false at end
  /// of file. An item must be one whole line: OpenMesh reads the values of a line it was not
  /// meant to as the next item's, and a count read from a coordinate sends it through millions
  /// of corners.
  bool beginItem() {
    if (mFormat != PlyFormat::Ascii) return true;
    std::string line;
    while (std::getline(mIn, line)) {
      std::istringstream ls(line);
      mTokens.clear();
      mNext = 0;
      for (std::string t; ls >> t;) mTokens.push_back(t);
      if (!mTokens.empty()) return true;
    }
    return false;
  }
  /// ASCII only: throws when the item's line holds more values than its properties.
  void endItem() const {
    if (mFormat == PlyFormat::Ascii && mNext != mTokens.size())
      throw std::runtime_error("a line holds " + std::to_string(mTokens.size()) + " values, its properties " +
                               std::to_string(mNext));
  }

  /// Reads one value; returns false at end of file (truncation).
  bool read(int size, bool isFloat, bool isSigned, double& value) {
    if (mFormat == PlyFormat::Ascii) {
      if (mNext == mTokens.size()) return false;
      const std::string& token = mTokens[mNext++];
      if (!parseAscii(token, size, isFloat, isSigned, value))
        throw std::runtime_error("'" + token.substr(0, 40) + "' is not " +
                                 (isFloat ? "a decimal number" : "an integer of its property's type"));
      return true;
    }
    unsigned char bytes[8];
    if (!mIn.read(reinterpret_cast<char*>(bytes), size)) return false;
    if (mFormat == PlyFormat::BinaryBigEndian) std::reverse(bytes, bytes + size);
    value = decode(bytes, size, isFloat, isSigned);
    return true;
  }

 private:
  static double decode(const unsigned char* b, int size, bool isFloat, bool isSigned) {
    if (isFloat) {
      if (size == 4) {
        float f;
        std::memcpy(&f, b, 4);
        return f;
      }
      double d;
      std::memcpy(&d, b, 8);
      return d;
    }
    std::uint64_t u = 0;
    std::memcpy(&u, b, size);  // little-endian host (x86_64, aarch64)
    if (isSigned) {
      const int shift = 64 - 8 * size;
      return double(std::int64_t(u << shift) >> shift);
    }
    return double(u);
  }

  /// A whole token: a decimal number for float properties, an integer in the type's range for
  /// integer ones (OpenMesh's stream extraction stops at the first character it cannot use).
  static bool parseAscii(const std::string& t, int size, bool isFloat, bool isSigned, double& value) {
    if (isFloat) {
      // No hexadecimal floats, and no NUL bytes (strtod stops at one and calls the token whole).
      if (t.find_first_of(std::string("xXpP\0", 5)) != std::string::npos) return false;
      char* end = nullptr;
      value = std::strtod(t.c_str(), &end);
      return end != t.c_str() && *end == '\0';
    }
    const std::size_t digits = (t[0] == '-' || t[0] == '+') ? 1 : 0;
    if (digits == t.size() || t.size() - digits > 20 ||
        t.find_first_not_of("0123456789", digits) != std::string::npos || (t[0] == '-' && !isSigned))
      return false;
    value = std::strtod(t.c_str(), nullptr);
    const double range = std::ldexp(1.0, 8 * size - (isSigned ? 1 : 0));
    return isSigned ? value >= -range && value < range : value < range;
  }

  std::istream& mIn;
  PlyFormat mFormat;
  std::vector<std::string> mTokens;  // ASCII: the current item's values
  std::size_t mNext = 0;
};

/// Parses the header and walks the body. Throws Error(FileFormat) naming the file and the problem.
inline PlyScan scanPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  auto fail = [&](const std::string& problem) {
    throw Error(ErrorKind::FileFormat, path, problem);
  };
  std::string line;
  if (!std::getline(in, line) || (line != "ply" && line != "ply\r"))
    fail("not a PLY file (the first line is not 'ply')");
  PlyScan scan;
  bool haveFormat = false, ended = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "format") {
      std::string f, version, extra;
      ls >> f >> version >> extra;
      if (f == "ascii") scan.format = PlyFormat::Ascii;
      else if (f == "binary_little_endian") scan.format = PlyFormat::BinaryLittleEndian;
      else if (f == "binary_big_endian") scan.format = PlyFormat::BinaryBigEndian;
      else fail("unknown PLY format '" + f + "'");
      // Checked here, because OpenMesh's reader loops for minutes on a version that is empty,
      // huge or not finite (found by mutating headers).
      if (!plyVersionOne(version) || !extra.empty())
        fail("malformed format line '" + line + "' (expected 'format " + f + " 1.0')");
      haveFormat = true;
    } else if (key == "element") {
      PlyElement e;
      std::string count, extra;
      ls >> e.name >> count >> extra;
      // A count is a whole decimal number: "inf", "1e308" or an empty count would otherwise be read
      // as something else (0, 1) and send OpenMesh's reader into a long loop.
      const std::optional<std::uint64_t> n = plyCount(count);
      if (e.name.empty() || !n || !extra.empty())
        fail("malformed element line '" + line + "' (expected 'element <name> <count>')");
      e.count = *n;
      scan.elements.push_back(e);
    } else if (key == "property") {
      if (scan.elements.empty()) fail("property before any element: '" + line + "'");
      PlyProperty p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string countType, itemType;
        ls >> countType >> itemType >> p.name;
        bool f, s;
        p.isList = true;
        p.countSize = plyTypeSize(countType, f, s);
        p.size = plyTypeSize(itemType, p.isFloat, p.isSigned);
        if (p.countSize == 0 || p.size == 0 || f) fail("unknown list types in '" + line + "'");
      } else {
        ls >> p.name;
        p.size = plyTypeSize(type, p.isFloat, p.isSigned);
        if (p.size == 0) fail("unknown property type '" + type + "'");
      }
      // A property without a name (or with more words) is malformed; OpenMesh loops on a nameless one.
      std::string extra;
      ls >> extra;
      if (p.name.empty() || !extra.empty()) fail("malformed property line '" + line + "' (expected one name)");
      scan.elements.back().properties.push_back(p);
    } else if (key == "end_header") {
      ended = true;
      break;
    } else if (key != "comment" && key != "obj_info" && !key.empty()) {
      fail("unexpected header line '" + line + "'");
    }
  }
  if (!haveFormat) fail("PLY header has no format line");
  // Every item of an element with properties takes at least one byte, so no count can exceed the
  // file's size; one without properties takes none, but OpenMesh's reader still steps through
  // its count, for ages when the count is huge.
  std::error_code sizeError;
  const std::uintmax_t fileBytes = std::filesystem::file_size(path, sizeError);
  for (const PlyElement& e : scan.elements)
    if (!sizeError && e.count > fileBytes)
      fail("element '" + e.name + "' claims " + std::to_string(e.count) + " items, more than the file's " +
           std::to_string(fileBytes) + " bytes");
  if (!ended) fail("PLY header has no end_header (file truncated or not PLY)");

  PlyBodyReader body(in, scan.format);
  for (const PlyElement& e : scan.elements) {
    if (e.properties.empty()) continue;  // holds no bytes
    const bool strips = (e.name == "tristrips");
    scan.hasStrips = scan.hasStrips || strips;
    std::vector<std::int64_t> strip;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      auto truncated = [&]() {
        fail("file ends early: element '" + e.name + "' " + std::to_string(i) + " of " +
             std::to_string(e.count) + " is incomplete (truncated file)");
      };
      if (!body.beginItem()) truncated();
      for (const PlyProperty& p : e.properties) {
        double v = 0;
        try {
          if (!p.isList) {
            if (!body.read(p.size, p.isFloat, p.isSigned, v)) truncated();
            continue;
          }
          if (!body.read(p.countSize, false, false, v)) truncated();
          if (!(v >= 0 && v <= 1e9))  // also NaN
            fail("element '" + e.name + "' has a list of " + std::to_string(v) + " items");
          const auto n = static_cast<std::uint64_t>(v);
          const bool keep = strips && p.name == "vertex_indices";
          for (std::uint64_t k = 0; k < n; ++k) {
            if (!body.read(p.size, p.isFloat, p.isSigned, v)) truncated();
            if (!keep) continue;
            if (!(v < 4294967295.0))
              fail("strip index " + std::to_string(v) + " is out of range");
            if (v < 0) {  // -1 restarts the strip
              appendStrip(strip, scan.stripTriangles);
              strip.clear();
            } else {
              strip.push_back(static_cast<std::int64_t>(v));
            }
          }
          if (keep) {
            appendStrip(strip, scan.stripTriangles);
            strip.clear();
          }
        } catch (const std::runtime_error& ex) {
          if (dynamic_cast<const Error*>(&ex)) throw;
          fail(std::string("element '") + e.name + "' " + std::to_string(i) + ": " + ex.what());
        }
      }
      try {
        body.endItem();
      } catch (const std::runtime_error& ex) {
        fail(std::string("element '") + e.name + "' " + std::to_string(i) + ": " + ex.what());
      }
    }
  }
  return scan;
}

}  // namespace cellrelief::io::detail
