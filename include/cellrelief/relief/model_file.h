// SPDX-License-Identifier: MIT
/// @file model_file.h
/// The relief model file (.crm). It lives in `relief`, not `io`, because dependencies point
/// downward (io <- relief): it uses io's atomic writes and checksum.
/// One versioned, checksummed, little-endian file, written
/// atomically. Layout in docs/format.md: a fixed header, then the cell look-up table and the map
/// sections exactly as they sit in memory (and on the GPU), then a CRC-32 of everything before it.
/// Loading checks the magic, the version, every size against the header, the checksum and the
/// look-up table's invariants, and names the file and the problem when any fails; a round trip is
/// bit-exact.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <filesystem>
#include <fstream>
#include <limits>
#include <tuple>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/io/checksummed_file.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::relief {

inline constexpr char kReliefMagic[8] = {'C', 'E', 'L', 'L', 'R', 'E', 'L', 'F'};
/// Version 2 added the centre-inside bit (bit 30) of interior cells' packed coordinates; version 3
/// the distance codec's zero code (distances before a face, DistanceCodec).
inline constexpr std::uint32_t kReliefFileVersion = 3;

namespace detail {
/// The fixed header, 120 bytes.
struct ReliefHeader {
  char magic[8];
  std::uint32_t version;
  std::uint32_t headerBytes;
  std::int32_t gridSize;
  std::int32_t texels;
  std::uint8_t distanceBits;
  std::uint8_t normalFormat;
  std::uint8_t colorFormat;
  std::uint8_t reserved0;
  float distanceMax;
  double originWS[3];
  double cellSizeWS;
  std::uint64_t cellCount;
  std::uint64_t layerCount;
  std::uint64_t cellBytes;
  std::uint64_t distanceBytes;
  std::uint64_t normalBytes;
  std::uint64_t colorBytes;
  std::uint32_t distanceZeroCode;
  std::uint32_t reserved1;
};
static_assert(sizeof(ReliefHeader) == 120);
static_assert(std::endian::native == std::endian::little,
              "the .crm format is little-endian and is read by copying host-order structs");

template <class T>
std::span<const char> bytesOf(const ImageArray<T>& image) {
  if (image.isEmpty()) return {};
  const auto d = image.levelData(0);
  return {reinterpret_cast<const char*>(d.data()), d.size() * sizeof(T)};
}
}  // namespace detail

/// Writes the model (level 0 of each map) atomically.
inline void writeRelief(const ReliefModel& model, const std::filesystem::path& path) {
  detail::ReliefHeader h{};
  std::memcpy(h.magic, kReliefMagic, 8);
  h.version = kReliefFileVersion;
  h.headerBytes = sizeof(h);
  h.gridSize = model.gridSize;
  h.texels = model.texels;
  h.distanceBits = std::uint8_t(model.distanceCodec.bits);
  h.normalFormat = std::uint8_t(model.normalFormat);
  h.colorFormat = std::uint8_t(model.colorFormat);
  h.distanceMax = model.distanceCodec.distanceMax;
  h.distanceZeroCode = model.distanceCodec.zeroCode;
  for (int a = 0; a < 3; ++a) h.originWS[a] = model.originWS[a];
  h.cellSizeWS = model.cellSizeWS;
  h.cellCount = model.cells.size();
  h.layerCount = std::uint64_t(model.layerCount());
  const std::span<const char> cells(reinterpret_cast<const char*>(model.cells.data()),
                                    model.cells.size() * sizeof(CellRecord));
  const std::span<const char> distances =
      model.visitDistances([](const auto& maps) { return detail::bytesOf(maps); });
  const std::span<const char> normals = model.normalFormat == NormalFormat::Octahedral16
                                            ? detail::bytesOf(model.normals16)
                                            : detail::bytesOf(model.normals8);
  const std::span<const char> colors = detail::bytesOf(model.colors);
  h.cellBytes = cells.size();
  h.distanceBytes = distances.size();
  h.normalBytes = normals.size();
  h.colorBytes = colors.size();

  io::ChecksummedWriter out(path);
  out.put(&h, sizeof h);
  for (const auto& section : {cells, distances, normals, colors}) out.put(section.data(), section.size());
  out.commit();
}

/// Reads a model; throws Error (FileNotFound, FileFormat) naming the file and the problem.
inline ReliefModel readRelief(const std::filesystem::path& path) {
  io::ChecksummedReader in(path, "a cellrelief model");
  auto fail = [&](const std::string& problem) { in.fail(problem); };
  const auto h = in.readHeader<detail::ReliefHeader>(kReliefMagic, kReliefFileVersion);
  const std::uint64_t T = std::uint64_t(h.texels);
  const std::uint64_t layers = h.layerCount;
  const bool sane = h.gridSize >= 1 && h.gridSize <= 1024 && h.texels >= 2 && h.texels <= 1025 &&
                    DistanceCodec::supports(h.distanceBits) && h.normalFormat <= 2 &&
                    h.colorFormat <= 1 && h.cellCount <= (1ull << 30) && layers <= 6 * h.cellCount &&
                    layers <= std::uint64_t(std::numeric_limits<int>::max()) &&
                    std::isfinite(h.distanceMax) && h.distanceMax > 0 && h.cellSizeWS > 0 &&
                    h.distanceZeroCode <= DistanceCodec{.bits = h.distanceBits}.maxCode() / 2;
  if (!sane) fail("corrupted header (values out of range)");
  const std::uint64_t samples = layers * T * T;
  const std::uint64_t normalBytesPerSample =
      h.normalFormat == 2 ? 4 : (h.normalFormat == 1 ? 4 : 0);
  if (h.cellBytes != h.cellCount * sizeof(CellRecord) ||
      h.distanceBytes != samples * DistanceCodec{.bits = h.distanceBits}.bytesPerCode() ||
      h.normalBytes != samples * normalBytesPerSample || h.colorBytes != samples * (h.colorFormat ? 4 : 0))
    fail("corrupted header (section sizes disagree with the counts)");
  in.expectSize(sizeof h + h.cellBytes + h.distanceBytes + h.normalBytes + h.colorBytes + 4);

  ReliefModel m;
  m.gridSize = h.gridSize;
  m.texels = h.texels;
  m.distanceCodec = {.bits = h.distanceBits, .distanceMax = h.distanceMax, .zeroCode = h.distanceZeroCode};
  m.normalFormat = NormalFormat(h.normalFormat);
  m.colorFormat = ColorFormat(h.colorFormat);
  m.originWS = Vec3d(h.originWS[0], h.originWS[1], h.originWS[2]);
  m.cellSizeWS = h.cellSizeWS;
  m.cells.resize(h.cellCount);
  in.read(reinterpret_cast<char*>(m.cells.data()), h.cellBytes);
  const int L = int(layers);
  if (layers > 0) {
    m.visitDistances([&](auto& maps) {
      maps = std::decay_t<decltype(maps)>(h.texels, h.texels, L, 1);
      in.read(reinterpret_cast<char*>(maps.levelData(0).data()), h.distanceBytes);
    });
    if (m.normalFormat == NormalFormat::Octahedral16) {
      m.normals16 = ImageArray<std::uint16_t>(h.texels, h.texels, L, 2);
      in.read(reinterpret_cast<char*>(m.normals16.levelData(0).data()), h.normalBytes);
    } else if (m.normalFormat == NormalFormat::Rgba8) {
      m.normals8 = ImageArray<std::uint8_t>(h.texels, h.texels, L, 4);
      in.read(reinterpret_cast<char*>(m.normals8.levelData(0).data()), h.normalBytes);
    }
    if (m.colorFormat == ColorFormat::Rgba8) {
      m.colors = ImageArray<std::uint8_t>(h.texels, h.texels, L, 4);
      in.read(reinterpret_cast<char*>(m.colors.levelData(0).data()), h.colorBytes);
    }
  }
  in.finish();
  // The look-up table must describe the maps it comes with.
  std::uint64_t nextLayer = 0;
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    const CellRecord& r = m.cells[i];
    const Vec3i p = r.ijk();
    // The projection must be the one its configuration chooses (type and face or axis), with a
    // finite point in the cell: nothing downstream then indexes out of range.
    const bool flagsOk = !r.centreInside() || r.configuration == 0;
    bool ok = flagsOk && p.x < m.gridSize && p.y < m.gridSize && p.z < m.gridSize && r.configuration < 64 &&
              (r.presentFaces & ~cells::domainFacesOf(r.configuration)) == 0 &&
              r.firstLayer == nextLayer;
    if (ok) {
      const auto chosen = projection::chooseProjection<double>(r.configuration);
      // (Perspective cells store 0 there.)
      ok = r.projectionType == std::uint8_t(chosen.type) &&
           r.faceOrAxis == std::uint8_t(std::max(0, chosen.faceOrAxis));
      for (const float c : r.point) ok = ok && std::isfinite(c) && c >= 0.0f && c <= 1.0f;
    }
    if (i > 0 && ok) {  // sorted by (k, j, i), no cell twice
      const Vec3i q = m.cells[i - 1].ijk();
      ok = std::tie(q.z, q.y, q.x) < std::tie(p.z, p.y, p.x);
    }
    if (!ok) fail("corrupted look-up table at cell " + std::to_string(i));
    nextLayer += std::popcount(unsigned(r.presentFaces));
  }
  if (nextLayer != layers) fail("corrupted look-up table (layer count mismatch)");
  return m;
}

}  // namespace cellrelief::relief
