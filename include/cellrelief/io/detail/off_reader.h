// SPDX-License-Identifier: MIT
/// @file off_reader.h
/// cellrelief's own reader for ASCII OFF ([ST][C][N][4]OFF, Geomview's layout). OpenMesh's OFF
/// reader reads the file as one stream of numbers, so a line short of a value, or a value it does
/// not expect, shifts every later value, and some such files send it into loops that never end
/// (the fuzzer kept finding new ones). This reader takes the file a line at a time, checks each
/// line whole against what the header word says it holds, and names the line of any problem. It
/// fills the same polygon soup as OpenMesh's readers. Binary OFF has its own reader here too: a
/// header OpenMesh takes for binary, or not, is no longer its guess.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/io/detail/format_checks.h"
#include "cellrelief/io/detail/openmesh_importer.h"

namespace cellrelief::io::detail {

/// What an OFF header word ([ST][C][N][4]OFF) says each vertex line holds, and whether the body is
/// binary (the word "BINARY" after it).
struct OffLayout {
  std::string word;          ///< the header word as written, e.g. "CNOFF"
  bool texcoords = false;    ///< ST: two texture coordinates at the end of the vertex line
  bool colors = false;       ///< C: a color (3 or 4 values, or one colormap index)
  bool normals = false;      ///< N: a normal after the position
  int dims = 3;              ///< 4: homogeneous positions x y z w
  bool binary = false;
  std::string countsOnHeaderLine;  ///< what follows the word on its line (counts may sit there)

  /// Values a vertex line must hold at least.
  int valuesNeeded() const { return dims + (normals ? 3 : 0) + (texcoords ? 2 : 0) + (colors ? 1 : 0); }
};

/// Splits a line into its whitespace-separated tokens (a NUL byte is not whitespace: it stays in
/// its token, which then fails to parse).
inline void splitTokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  constexpr std::string_view kSpace = " \t\r\v\f";
  std::size_t i = line.find_first_not_of(kSpace);
  while (i != std::string_view::npos) {
    const std::size_t end = line.find_first_of(kSpace, i);
    tokens.push_back(line.substr(i, end == std::string_view::npos ? std::string_view::npos : end - i));
    i = end == std::string_view::npos ? end : line.find_first_not_of(kSpace, end);
  }
}

/// Lines of an OFF file with '#' comments removed and blank lines skipped.
class OffLines {
 public:
  explicit OffLines(std::istream& in) : mIn(in) {}
  bool next(std::string& line) {
    while (std::getline(mIn, line)) {
      ++mLineNo;
      if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
      if (line.find_first_not_of(" \t\r\v\f") != std::string::npos) return true;
    }
    return false;
  }
  std::size_t lineNo() const { return mLineNo; }

 private:
  std::istream& mIn;
  std::size_t mLineNo = 0;
};

/// Reads an OFF file's first line (after comments and blank lines): the header word, exactly
/// [ST][C][N][4]OFF, then BINARY or the counts, or nothing.
inline OffLayout parseOffHeader(OffLines& lines, const std::filesystem::path& path) {
  std::string line;
  if (!lines.next(line)) throw Error(ErrorKind::FileFormat, path, "no OFF header");
  std::vector<std::string_view> tokens;
  splitTokens(line, tokens);
  OffLayout layout;
  layout.word = std::string(tokens.at(0));
  const std::size_t off = layout.word.find("OFF");
  std::string_view prefix = std::string_view(layout.word).substr(0, off);
  bool known = off != std::string::npos && off + 3 == layout.word.size();
  auto take = [&](std::string_view part, bool& flag) {
    if (prefix.starts_with(part)) {
      flag = true;
      prefix.remove_prefix(part.size());
    }
  };
  bool four = false;
  take("ST", layout.texcoords);
  take("C", layout.colors);
  take("N", layout.normals);
  take("4", four);
  layout.dims = four ? 4 : 3;
  if (!known || !prefix.empty())
    throw Error(ErrorKind::FileFormat, path,
                "not an OFF file: the header word is '" + layout.word.substr(0, 40) +
                    "', not [ST][C][N][4]OFF" +
                    (prefix.find('n') != std::string_view::npos ? " (nOFF, a dimension other than 3, is not supported)"
                                                                 : ""));
  if (tokens.size() > 1 && tokens[1] == "BINARY") {
    if (tokens.size() > 2)
      throw Error(ErrorKind::FileFormat, path,
                  "unexpected '" + std::string(tokens[2].substr(0, 40)) + "' after 'BINARY' in the OFF header");
    layout.binary = true;
    return layout;
  }
  for (std::size_t k = 1; k < tokens.size(); ++k) {
    long long v;
    if (!parseIndex(tokens[k], v))
      throw Error(ErrorKind::FileFormat, path,
                  "unexpected '" + std::string(tokens[k].substr(0, 40)) + "' after the OFF header word");
    else layout.countsOnHeaderLine += std::string(tokens[k]) + " ";
  }
  return layout;
}

/// The layout an OFF file's header word states; throws on a header that is not OFF.
inline OffLayout parseOffLayout(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  OffLines lines(in);
  return parseOffHeader(lines, path);
}

/// Ends the polygon whose corners start at `firstCorner`: kept when it has 3 corners or more,
/// otherwise dropped and counted in rejectedFaces (as OpenMesh's readers do).
inline void closePolygon(PolygonSoup& soup, std::size_t firstCorner) {
  if (soup.corners.size() - firstCorner < 3) {
    soup.corners.resize(firstCorner);
    ++soup.rejectedFaces;
    return;
  }
  soup.offsets.push_back(std::uint32_t(soup.corners.size()));
}

/// Reads a binary OFF (Geomview's layout): after the header line, vertex, face and edge counts as
/// 32-bit integers, each vertex as 32-bit floats (position, then the normal, color (4) and texture
/// coordinates its header word names), each face as its corner count, the indices and a count of
/// color floats that follow. The format says big-endian; OpenMesh writes the machine's order, so
/// the order is the one whose counts fit the file. Every count and index is checked against the
/// bytes that remain before it is used.
inline PolygonSoup readBinaryOff(const std::filesystem::path& path, const OffLayout& layout) {
  std::ifstream in(path, std::ios::binary);
  OffLines lines(in);
  std::string header;
  lines.next(header);  // the body starts after the header line (and any comments before it)
  const std::vector<char> body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto fail = [&](const std::string& problem) {
    throw Error(ErrorKind::FileFormat, path, "binary OFF: " + problem);
  };
  const int vertexFloats = layout.dims + (layout.normals ? 3 : 0) + (layout.colors ? 4 : 0) + (layout.texcoords ? 2 : 0);
  auto word = [&](std::size_t at, bool big) {
    const auto* p = reinterpret_cast<const unsigned char*>(body.data() + at);
    return big ? (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3]
               : (std::uint32_t(p[3]) << 24) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[1]) << 8) | p[0];
  };
  if (body.size() < 12) fail("the file ends before the vertex, face and edge counts");
  // The byte order whose counts fit: vertices whole, and each face at least its count, three
  // indices and its color count.
  auto fits = [&](bool big) {
    const std::uint64_t nv = word(0, big), nf = word(4, big);
    return nv > 0 && nf > 0 && nv < (1u << 31) && nf < (1u << 31) &&
           12 + nv * 4 * std::uint64_t(vertexFloats) + nf * 20 <= body.size();
  };
  const bool big = fits(true);
  if (!big && !fits(false))
    fail("vertex and face counts that do not fit its " + std::to_string(body.size()) +
         " bytes after the header (truncated or corrupt)");
  const std::uint32_t nv = word(0, big), nf = word(4, big);
  auto real = [&](std::size_t at) {
    const std::uint32_t bits = word(at, big);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  };
  PolygonSoup soup;
  soup.hasNormals = layout.normals;
  soup.hasColors = layout.colors;
  soup.hasVertexUVs = layout.texcoords;
  std::size_t at = 12;
  for (std::uint32_t i = 0; i < nv; ++i, at += 4 * std::size_t(vertexFloats)) {
    float v[16];
    for (int k = 0; k < vertexFloats; ++k) {
      v[k] = real(at + 4 * std::size_t(k));
      if (!std::isfinite(v[k])) fail("vertex " + std::to_string(i) + " has a value that is not a finite number");
    }
    Vec3f p(v[0], v[1], v[2]);
    if (layout.dims == 4) {
      if (v[3] == 0.0f) fail("vertex " + std::to_string(i) + " has the homogeneous coordinate w = 0");
      p /= v[3];
    }
    soup.positions.push_back(p);
    int k = layout.dims;
    if (layout.normals) soup.normals.emplace_back(v[k], v[k + 1], v[k + 2]), k += 3;
    if (layout.colors) {
      Color8 c;
      for (int j = 0; j < 4; ++j) c[j] = std::uint8_t(std::lround(std::clamp(v[k + j], 0.0f, 1.0f) * 255.0f));
      soup.colors.push_back(c);
      k += 4;
    }
    if (layout.texcoords) soup.vertexUVs.emplace_back(v[k], v[k + 1]);
  }
  for (std::uint32_t i = 0; i < nf; ++i) {
    const std::string where = "face " + std::to_string(i);
    if (at + 4 > body.size()) fail("the file ends at " + where + " of " + std::to_string(nf) + " (truncated file)");
    const std::uint32_t n = word(at, big);
    at += 4;
    if (std::uint64_t(n) * 4 + 4 > body.size() - at)
      fail(where + " claims " + std::to_string(n) + " corners, more than the file holds");
    const std::size_t first = soup.corners.size();
    for (std::uint32_t k = 0; k < n; ++k, at += 4) {
      const std::uint32_t index = word(at, big);
      if (index >= nv)
        throw Error(ErrorKind::InvalidInput, path,
                    "binary OFF: " + where + " refers to vertex " + std::to_string(index) + " but there are only " +
                        std::to_string(nv) + " vertices");
      soup.corners.push_back(index);
    }
    const std::uint32_t colors = word(at, big);
    at += 4;
    if (colors > 4 || std::uint64_t(colors) * 4 > body.size() - at)
      fail(where + " has " + std::to_string(colors) + " color values (at most 4, within the file)");
    at += 4 * std::size_t(colors);
    closePolygon(soup, first);
  }
  return soup;
}

/// Reads an ASCII OFF into a polygon soup. Every line is checked whole: the counts are plain
/// integers, each vertex line holds the values its header word promises (finite numbers), each
/// face line a corner count, that many existing vertex indices and, on a face of 3 or more corners,
/// optional color values. Faces of fewer than 3 corners are skipped (counted in rejectedFaces).
inline PolygonSoup readAsciiOff(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  OffLines lines(in);
  const OffLayout layout = parseOffHeader(lines, path);
  auto fail = [&](ErrorKind kind, const std::string& problem) {
    throw Error(kind, path, "line " + std::to_string(lines.lineNo()) + ": " + problem);
  };
  if (layout.binary) fail(ErrorKind::FileFormat, "binary OFF given to the ASCII OFF reader");

  // The counts: vertices, faces and (often left out) edges, plain integers and nothing else.
  std::string line = layout.countsOnHeaderLine;
  if (line.empty() && !lines.next(line)) fail(ErrorKind::FileFormat, "file ends before the OFF counts");
  std::vector<std::string_view> tokens;
  splitTokens(line, tokens);
  long long nv = -1, nf = -1, ne = 0;
  if (tokens.size() < 2 || tokens.size() > 3 || !parseIndex(tokens[0], nv) || !parseIndex(tokens[1], nf) ||
      (tokens.size() == 3 && !parseIndex(tokens[2], ne)))
    fail(ErrorKind::FileFormat,
         "OFF header has no vertex, face and edge counts (three integers): '" + line.substr(0, 60) + "'");
  if (nv == 0 || nf == 0)
    fail(ErrorKind::InvalidInput, "the OFF header declares " + std::to_string(nv) + " vertices and " +
                                      std::to_string(nf) + " faces: no surface");
  if (nv >= (1ll << 32) - 1)
    fail(ErrorKind::InvalidInput, "the OFF header declares " + std::to_string(nv) +
                                      " vertices, more than 32-bit indices can address");

  PolygonSoup soup;
  // Headers can lie: reserve only what the file's size allows (a vertex line is at least 6 bytes).
  const auto bytes = std::filesystem::file_size(path);
  soup.positions.reserve(std::size_t(std::min<long long>(nv, bytes / 6 + 1)));
  soup.hasNormals = layout.normals;
  soup.hasVertexUVs = layout.texcoords;
  soup.hasColors = layout.colors;

  for (long long i = 0; i < nv; ++i) {
    if (!lines.next(line))
      fail(ErrorKind::FileFormat, "file ends early: the header declares " + std::to_string(nv) +
                                      " vertices, found " + std::to_string(i) + " (truncated file)");
    splitTokens(line, tokens);
    const std::string where = "vertex " + std::to_string(i);
    double v[64];
    const int count = int(std::min<std::size_t>(tokens.size(), 64));
    for (int k = 0; k < count; ++k)
      if (!parseFinite(tokens[k], v[k]))
        fail(k < layout.dims ? ErrorKind::InvalidInput : ErrorKind::FileFormat,
             where + (k < layout.dims ? " coordinate '" : " value '") + std::string(tokens[k].substr(0, 40)) +
                 "' is not a finite number");
    if (count < layout.valuesNeeded())
      fail(ErrorKind::FileFormat, where + " has " + std::to_string(count) + " values, a " + layout.word +
                                      " vertex needs at least " + std::to_string(layout.valuesNeeded()));
    Vec3d p(v[0], v[1], v[2]);
    if (layout.dims == 4) {
      if (v[3] == 0.0) fail(ErrorKind::InvalidInput, where + " has the homogeneous coordinate w = 0 (a point at infinity)");
      p /= v[3];
    }
    const Vec3f position(p);
    if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z))
      fail(ErrorKind::InvalidInput, where + " lies beyond the range of single precision");
    soup.positions.push_back(position);
    int k = layout.dims;
    if (layout.normals) {
      soup.normals.emplace_back(float(v[k]), float(v[k + 1]), float(v[k + 2]));
      k += 3;
    }
    if (layout.texcoords) {
      // After the color when there is one, so the last two values of the line.
      const int at = layout.colors ? count - 2 : k;
      soup.vertexUVs.emplace_back(float(v[at]), float(v[at + 1]));
    }
    if (layout.colors) {
      const int components = (layout.texcoords ? count - 2 : count) - k;
      Color8 c(255);
      if (components == 3 || components == 4) {
        // A color is integers 0..255, or numbers 0..1 when any of them is written with a point
        // or an exponent (as OpenMesh and Geomview tell them apart).
        bool real = false;
        for (int j = 0; j < components; ++j)
          real = real || tokens[std::size_t(k + j)].find_first_of(".eE") != std::string_view::npos;
        for (int j = 0; j < components; ++j)
          c[j] = std::uint8_t(std::lround(std::clamp(real ? v[k + j] * 255.0 : v[k + j], 0.0, 255.0)));
      } else if (components != 1) {  // one value is a colormap index: no color of its own
        fail(ErrorKind::FileFormat, where + " has " + std::to_string(components) +
                                        " color values; a " + layout.word +
                                        " color has 3 or 4 (or 1 colormap index)");
      }
      soup.colors.push_back(c);
    }
  }

  for (long long i = 0; i < nf; ++i) {
    if (!lines.next(line))
      fail(ErrorKind::FileFormat, "file ends early: the header declares " + std::to_string(nf) +
                                      " faces, found " + std::to_string(i) + " (truncated file)");
    splitTokens(line, tokens);
    const std::string where = "face " + std::to_string(i);
    long long n = -1;
    if (!parseIndex(tokens[0], n)) fail(ErrorKind::FileFormat, where + " has no corner count (a non-negative integer)");
    if (std::size_t(n) + 1 > tokens.size())
      fail(ErrorKind::FileFormat, where + " has fewer than " + std::to_string(n) + " vertex indices");
    const std::size_t firstCorner = soup.corners.size();
    for (long long k = 1; k <= n; ++k) {
      long long index = -1;
      if (!parseIndex(tokens[std::size_t(k)], index))
        fail(ErrorKind::FileFormat, where + " has a vertex index '" + std::string(tokens[std::size_t(k)].substr(0, 40)) +
                                        "' that is not a non-negative integer");
      if (index >= nv)
        fail(ErrorKind::InvalidInput, where + " refers to vertex " + std::to_string(index) +
                                          " but there are only " + std::to_string(nv) + " vertices");
      soup.corners.push_back(std::uint32_t(index));
    }
    const std::size_t extra = tokens.size() - std::size_t(n) - 1;
    if (n < 3 && extra > 0)
      fail(ErrorKind::FileFormat, where + " has " + std::to_string(n) +
                                      " corners and more values after them (a face needs 3 corners)");
    for (std::size_t k = std::size_t(n) + 1; k < tokens.size(); ++k) {
      double value;
      if (!parseFinite(tokens[k], value))
        fail(ErrorKind::FileFormat, where + " has a color value '" + std::string(tokens[k].substr(0, 40)) +
                                        "' that is not a number");
    }
    closePolygon(soup, firstCorner);
  }
  return soup;
}

}  // namespace cellrelief::io::detail
