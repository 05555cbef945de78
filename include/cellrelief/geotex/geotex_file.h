// SPDX-License-Identifier: MIT
/// @file geotex_file.h
/// The geometry-texture file (.cgt), with the discipline of the .crm file: one versioned,
/// checksummed, little-endian file written atomically; a fixed header, the chart records, the
/// height codes (1 or 2 bytes each), the normals, the colours, then a CRC-32 of everything before
/// it. Loading checks the magic, the version, every size against the header and the file's own
/// size (before allocating), the checksum and the model's invariants, and names the file and the
/// problem when any fails; a round trip is bit-exact.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/geotex/geotex_model.h"
#include "cellrelief/io/checksummed_file.h"

namespace cellrelief::geotex {

inline constexpr char kGeoTexMagic[8] = {'C', 'R', 'G', 'E', 'O', 'T', 'E', 'X'};
inline constexpr std::uint32_t kGeoTexFileVersion = 1;

namespace detail {
/// The fixed header, 72 bytes.
struct GeoTexHeader {
  char magic[8];
  std::uint32_t version;
  std::uint32_t headerBytes;
  std::uint8_t heightBits;
  std::uint8_t hasColors;
  std::uint8_t reserved[6];
  std::uint64_t chartCount;
  std::uint64_t texelCount;
  std::uint64_t chartBytes;
  std::uint64_t heightBytes;
  std::uint64_t normalBytes;
  std::uint64_t colorBytes;
};
static_assert(sizeof(GeoTexHeader) == 72);
static_assert(std::endian::native == std::endian::little,
              "the .cgt format is little-endian and is read by copying host-order values");

/// Visits a chart record's fields in file order: 15 doubles (origin, three axes, size), width,
/// height, first texel. One list for writing and reading, so the two cannot drift.
template <class Chart, class Visit>
void forEachField(Chart& c, Visit&& visit) {
  for (int a = 0; a < 3; ++a) visit(c.originWS[a]);
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) visit(c.axisWS[k][a]);
  for (int a = 0; a < 3; ++a) visit(c.sizeWS[a]);
  visit(c.width);
  visit(c.height);
  visit(c.firstTexel);
}

inline std::vector<char> packCharts(const std::vector<ChartBox>& charts) {
  std::vector<char> bytes(charts.size() * kChartRecordBytes);
  char* p = bytes.data();
  for (const ChartBox& c : charts)
    forEachField(c, [&](const auto& value) {
      std::memcpy(p, &value, sizeof value);
      p += sizeof value;
    });
  return bytes;
}

inline std::vector<ChartBox> unpackCharts(const std::vector<char>& bytes) {
  std::vector<ChartBox> charts(bytes.size() / kChartRecordBytes);
  const char* p = bytes.data();
  for (ChartBox& c : charts)
    forEachField(c, [&](auto& value) {
      std::memcpy(&value, p, sizeof value);
      p += sizeof value;
    });
  return charts;
}
}  // namespace detail

/// Writes the model atomically: the target is replaced only by a complete file.
inline void writeGeoTex(const GeoTexModel& model, const std::filesystem::path& path) {
  model.validate(path.string());
  detail::GeoTexHeader h{};
  std::memcpy(h.magic, kGeoTexMagic, 8);
  h.version = kGeoTexFileVersion;
  h.headerBytes = sizeof h;
  h.heightBits = std::uint8_t(model.heightCodec.bits);
  h.hasColors = model.hasColors() ? 1 : 0;
  h.chartCount = model.charts.size();
  h.texelCount = model.texelCount();
  const std::vector<char> charts = detail::packCharts(model.charts);
  std::vector<std::uint8_t> heights8;
  if (model.heightCodec.bits == 8) heights8.assign(model.heights.begin(), model.heights.end());
  const char* heights = model.heightCodec.bits == 8 ? reinterpret_cast<const char*>(heights8.data())
                                                    : reinterpret_cast<const char*>(model.heights.data());
  h.chartBytes = charts.size();
  h.heightBytes = model.heights.size() * std::uint64_t(model.heightCodec.bytesPerCode());
  h.normalBytes = model.normals.size() * 4;
  h.colorBytes = model.colors.size() * 4;

  io::ChecksummedWriter out(path);
  out.put(&h, sizeof h);
  out.put(charts.data(), charts.size());
  out.put(heights, h.heightBytes);
  out.put(model.normals.data(), h.normalBytes);
  out.put(model.colors.data(), h.colorBytes);
  out.commit();
}

/// Reads a model; throws Error (FileNotFound, FileFormat) naming the file and the problem.
inline GeoTexModel readGeoTex(const std::filesystem::path& path) {
  io::ChecksummedReader in(path, "a geometry-texture model");
  auto fail = [&](const std::string& problem) { in.fail(problem); };
  const auto h = in.readHeader<detail::GeoTexHeader>(kGeoTexMagic, kGeoTexFileVersion);
  if (!HeightCodec::supports(h.heightBits) || h.hasColors > 1 || h.chartCount > (1ull << 24) ||
      h.texelCount > (1ull << 36))
    fail("corrupted header (values out of range)");
  const HeightCodec codec{.bits = h.heightBits};
  if (h.chartBytes != h.chartCount * kChartRecordBytes ||
      h.heightBytes != h.texelCount * std::uint64_t(codec.bytesPerCode()) || h.normalBytes != h.texelCount * 4 ||
      h.colorBytes != (h.hasColors ? h.texelCount * 4 : 0))
    fail("corrupted header (section sizes disagree with the counts)");
  in.expectSize(sizeof h + h.chartBytes + h.heightBytes + h.normalBytes + h.colorBytes + 4);

  GeoTexModel m;
  m.heightCodec = codec;
  std::vector<char> charts(h.chartBytes);
  in.read(charts.data(), h.chartBytes);
  m.charts = detail::unpackCharts(charts);
  m.heights.resize(h.texelCount);
  if (codec.bits == 8) {
    std::vector<std::uint8_t> codes(h.texelCount);
    in.read(codes.data(), h.heightBytes);
    std::copy(codes.begin(), codes.end(), m.heights.begin());
  } else {
    in.read(m.heights.data(), h.heightBytes);
  }
  m.normals.resize(h.texelCount);
  in.read(m.normals.data(), h.normalBytes);
  if (h.hasColors) {
    m.colors.resize(h.texelCount);
    in.read(m.colors.data(), h.colorBytes);
  }
  in.finish();
  try {
    m.validate(path.string());
  } catch (const Error& e) {
    fail("corrupted: " + e.problem());
  }
  return m;
}

}  // namespace cellrelief::geotex
