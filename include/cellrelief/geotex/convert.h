// SPDX-License-Identifier: MIT
/// @file convert.h
/// Mesh to geometry textures, in named steps: partition (VSA), widen each region by a ring of
/// faces, frame each chart (median normal, 2D PCA, exact bounds), size its maps (a power of two per
/// axis that follows the chart's extent, up to a maximum), rasterize its triangles along z into
/// height, normal and colour maps (the topmost surface per texel), smooth the heights if asked,
/// dilate the normal and colour maps into empty texels (so filtering and mip-maps at a chart's edge
/// read sensible values; the paper's Fig. 4f), and quantize. Also: a height-map image (a DEM) as
/// one chart directly, the paper's geological application.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/core/octahedral.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/quantize.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/geotex/charts.h"
#include "cellrelief/geotex/geotex_model.h"
#include "cellrelief/geotex/vsa.h"

namespace cellrelief::geotex {

struct GeoTexOptions {
  VsaOptions vsa;
  int maxTexels = 128;    ///< the largest map side; every side is a power of two
  int minTexels = 4;      ///< the smallest map side
  int heightBits = 16;    ///< 8 or 16
  int rings = 1;          ///< rings of faces added around each region (0: none; cracks show)
  bool colors = true;     ///< keep a colour map when the mesh has vertex colours
  double smoothing = 0;   ///< sigma, in texels, of a Gaussian applied to the heights (0: none)
  int dilation = 4;       ///< texels the normal and colour maps grow into empty texels
};

/// What the conversion found per chart.
struct ChartReport {
  std::size_t ownFaces = 0, ringFaces = 0;
  std::size_t foldedFaces = 0;  ///< own faces that face away from z (inverted when rasterized)
  double ownArea = 0, foldedArea = 0;
  std::uint64_t emptyTexels = 0;
};

struct GeoTexConversion {
  GeoTexModel model;
  VsaPartition partition;
  std::vector<ChartReport> charts;
  std::size_t foldedFaces() const {
    std::size_t n = 0;
    for (const ChartReport& c : charts) n += c.foldedFaces;
    return n;
  }
  std::uint64_t emptyTexels() const {
    std::uint64_t n = 0;
    for (const ChartReport& c : charts) n += c.emptyTexels;
    return n;
  }
};

/// A chart's maps before quantization: heights in world units above the box's base (NaN: empty).
struct ChartMaps {
  int width = 0, height = 0;
  std::vector<float> heights;
  std::vector<Vec3f> normals;
  std::vector<Vec4f> colors;  ///< empty when the mesh has none
  bool empty(std::size_t t) const { return std::isnan(heights[t]); }
};

namespace detail {

inline int mapSide(double extent, double texelSize, const GeoTexOptions& o) {
  const double texels = std::ceil(extent / texelSize - 1e-9);
  const auto wanted = std::uint32_t(std::clamp(texels, 1.0, double(o.maxTexels)));
  return std::clamp(int(std::bit_ceil(wanted)), o.minTexels, o.maxTexels);
}

/// Rasterizes the chart's triangles along its z axis: every texel centre inside a triangle's
/// projection takes the triangle's height there if it is the highest so far, with the
/// interpolated normal and colour of that point.
inline ChartMaps rasterizeChart(const TriangleMesh& mesh, std::span<const std::uint32_t> faces,
                                const ChartBox& box, std::span<const Vec3f> vertexNormals, bool colors) {
  ChartMaps maps;
  maps.width = int(box.width);
  maps.height = int(box.height);
  const std::size_t n = box.texelCount();
  maps.heights.assign(n, std::numeric_limits<float>::quiet_NaN());
  maps.normals.assign(n, Vec3f(0, 0, 1));
  if (colors) maps.colors.assign(n, Vec4f(0));
  std::vector<double> best(n, -std::numeric_limits<double>::infinity());
  for (const std::uint32_t f : faces) {
    const Vec3u& t = mesh.triangles[f];
    Vec3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = box.toChart(Vec3d(mesh.positions[t[k]]));
    const double area2 = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    if (!(std::abs(area2) > 1e-12)) continue;  // seen edge-on: no texel centre inside
    const int i0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}) - 0.5)));
    const int i1 = std::min(maps.width - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}) - 0.5)));
    const int j0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}) - 0.5)));
    const int j1 = std::min(maps.height - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}) - 0.5)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double x = i + 0.5, y = j + 0.5;
        // Barycentrics from signed areas; a small slack so centres on a shared edge are covered.
        const double w1 = ((x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (y - p[0].y)) / area2;
        const double w2 = ((p[1].x - p[0].x) * (y - p[0].y) - (x - p[0].x) * (p[1].y - p[0].y)) / area2;
        const double w0 = 1 - w1 - w2;
        constexpr double kSlack = 1e-9;
        if (w0 < -kSlack || w1 < -kSlack || w2 < -kSlack) continue;
        const double z = w0 * p[0].z + w1 * p[1].z + w2 * p[2].z;
        const std::size_t texel = std::size_t(j) * maps.width + i;
        if (z <= best[texel]) continue;
        best[texel] = z;
        maps.heights[texel] = float(z);
        const Vec3f normal = float(w0) * vertexNormals[t[0]] + float(w1) * vertexNormals[t[1]] +
                             float(w2) * vertexNormals[t[2]];
        const float len = glm::length(normal);
        maps.normals[texel] = len > 0 ? normal / len : Vec3f(box.axisWS[2]);
        if (colors) {
          Vec4f c(0);
          const double w[3] = {w0, w1, w2};
          for (int k = 0; k < 3; ++k) c += float(w[k]) * Vec4f(mesh.colors[t[k]]);
          maps.colors[texel] = c;
        }
      }
  }
  return maps;
}

/// Gaussian smoothing of the heights over non-empty texels (normalized convolution, separable):
/// empty texels neither contribute nor change.
inline void smoothHeights(ChartMaps& maps, double sigma) {
  if (!(sigma > 0)) return;
  const int radius = int(std::ceil(3 * sigma));
  std::vector<double> kernel(2 * radius + 1);
  for (int k = -radius; k <= radius; ++k) kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  const int w = maps.width, h = maps.height;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<float> out = maps.heights;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        if (maps.empty(std::size_t(j) * w + i)) continue;
        double sum = 0, weight = 0;
        for (int k = -radius; k <= radius; ++k) {
          const int x = pass == 0 ? i + k : i, y = pass == 0 ? j : j + k;
          if (x < 0 || y < 0 || x >= w || y >= h || maps.empty(std::size_t(y) * w + x)) continue;
          sum += kernel[k + radius] * maps.heights[std::size_t(y) * w + x];
          weight += kernel[k + radius];
        }
        out[std::size_t(j) * w + i] = float(sum / weight);
      }
    maps.heights = std::move(out);
  }
}

/// Grows the normal and colour maps into empty texels, one ring of texels per pass, each new
/// texel the mean of its filled 4-neighbours.
inline void dilateMaps(ChartMaps& maps, int passes) {
  const int w = maps.width, h = maps.height;
  std::vector<char> filled(maps.heights.size());
  for (std::size_t t = 0; t < filled.size(); ++t) filled[t] = !maps.empty(t);
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<char> next = filled;
    bool grew = false;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const std::size_t t = std::size_t(j) * w + i;
        if (filled[t]) continue;
        Vec3f normal(0);
        Vec4f color(0);
        int count = 0;
        const int offsets[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
        for (const auto& o : offsets) {
          const int x = i + o[0], y = j + o[1];
          if (x < 0 || y < 0 || x >= w || y >= h || !filled[std::size_t(y) * w + x]) continue;
          normal += maps.normals[std::size_t(y) * w + x];
          if (!maps.colors.empty()) color += maps.colors[std::size_t(y) * w + x];
          ++count;
        }
        if (count == 0) continue;
        const float len = glm::length(normal);
        if (len > 0) maps.normals[t] = normal / len;
        if (!maps.colors.empty()) maps.colors[t] = color / float(count);
        next[t] = 1;
        grew = true;
      }
    filled.swap(next);
    if (!grew) break;
  }
}

/// Quantizes a chart's maps onto the end of the model's arrays.
inline void appendMaps(const ChartMaps& maps, ChartBox& box, GeoTexModel& model) {
  box.firstTexel = model.heights.size();
  const HeightCodec& codec = model.heightCodec;
  for (std::size_t t = 0; t < maps.heights.size(); ++t) {
    model.heights.push_back(maps.empty(t) ? codec.emptyCode() : codec.encode(maps.heights[t] / box.sizeWS.z));
    const Vec2f e = octahedralEncode(maps.normals[t]);
    model.normals.push_back(std::uint32_t(quantizeUnorm<std::uint16_t>(e.x)) | (std::uint32_t(quantizeUnorm<std::uint16_t>(e.y)) << 16));
    if (!maps.colors.empty()) model.colors.push_back(Color8(glm::clamp(glm::round(maps.colors[t]), Vec4f(0), Vec4f(255))));
  }
  model.charts.push_back(box);
}

}  // namespace detail

namespace detail {

inline void checkOptions(const GeoTexOptions& options) {
  auto refuse = [](const std::string& problem) { throw Error(ErrorKind::InvalidInput, "geometry textures", problem); };
  if (!HeightCodec::supports(options.heightBits)) refuse("height bits must be 8 or 16");
  if (options.maxTexels < 2 || options.maxTexels > 4096 || !std::has_single_bit(unsigned(options.maxTexels)))
    refuse("the largest map side must be a power of two from 2 to 4096");
  if (options.minTexels < 1 || options.minTexels > options.maxTexels)
    refuse("the smallest map side must be from 1 to the largest");
}

/// The texel size of the model: the largest chart's extent over the largest map side.
inline double modelTexelSize(const std::vector<ChartFrame>& frames, const GeoTexOptions& options) {
  double largest = 0;
  for (const ChartFrame& f : frames) largest = std::max({largest, f.maximum.x - f.minimum.x, f.maximum.y - f.minimum.y});
  if (!(largest > 0))
    throw Error(ErrorKind::InvalidInput, "geometry textures", "every chart is a point or a line: the mesh has no extent");
  return largest / options.maxTexels;
}

/// The chart's box: its frame's bounds, at least a texel wide, with half a texel of room below and
/// above so that a flat chart still has a volume to search; and its map size.
inline ChartBox chartBox(const ChartFrame& f, double texelSize, const GeoTexOptions& options) {
  ChartBox box;
  Vec3d lo = f.minimum, hi = f.maximum;
  for (int a = 0; a < 2; ++a)  // a chart thinner than a texel gets one texel, centred
    if (hi[a] - lo[a] < texelSize) {
      const double mid = 0.5 * (lo[a] + hi[a]);
      lo[a] = mid - 0.5 * texelSize;
      hi[a] = mid + 0.5 * texelSize;
    }
  lo.z -= 0.5 * texelSize;
  hi.z += 0.5 * texelSize;
  for (int a = 0; a < 3; ++a) box.axisWS[a] = f.axis[a];
  box.originWS = lo.x * f.axis[0] + lo.y * f.axis[1] + lo.z * f.axis[2];
  box.sizeWS = hi - lo;
  box.width = std::uint32_t(mapSide(box.sizeWS.x, texelSize, options));
  box.height = std::uint32_t(mapSide(box.sizeWS.y, texelSize, options));
  return box;
}

/// Faces, folds and empty texels of one chart.
inline ChartReport chartReport(const TriangleMesh& mesh, const ChartFaces& faces, const ChartBox& box,
                               const ChartMaps& maps) {
  ChartReport report;
  report.ownFaces = faces.ownCount;
  report.ringFaces = faces.faces.size() - faces.ownCount;
  for (std::size_t i = 0; i < faces.ownCount; ++i) {
    const Vec3u& t = mesh.triangles[faces.faces[i]];
    const Vec3d n = glm::cross(Vec3d(mesh.positions[t[1]]) - Vec3d(mesh.positions[t[0]]),
                               Vec3d(mesh.positions[t[2]]) - Vec3d(mesh.positions[t[0]]));
    const double area = 0.5 * glm::length(n);
    report.ownArea += area;
    if (area > 0 && glm::dot(n, box.axisWS[2]) <= 0) {
      ++report.foldedFaces;
      report.foldedArea += area;
    }
  }
  for (std::size_t t = 0; t < maps.heights.size(); ++t) report.emptyTexels += maps.empty(t);
  return report;
}

}  // namespace detail

/// Converts a mesh. Throws Error(InvalidInput) for bad options or a mesh VSA refuses.
inline GeoTexConversion convertMesh(const TriangleMesh& mesh, const GeoTexOptions& options = {}) {
  detail::checkOptions(options);
  GeoTexConversion result;
  result.partition = partitionVsa(mesh, options.vsa);
  const std::vector<ChartFaces> faces = chartFaces(mesh, result.partition, options.rings);
  const std::size_t charts = faces.size();
  std::vector<ChartFrame> frames(charts);
  parallelFor(0, charts, [&](std::size_t c) {
    const std::span<const std::uint32_t> own(faces[c].faces.data(), faces[c].ownCount);
    frames[c] = chartFrame(mesh, faces[c].faces, medianNormal(mesh, own, result.partition.proxies[c].normal));
  }, 1);
  const double texelSize = detail::modelTexelSize(frames, options);
  const std::vector<Vec3f> vertexNormals = mesh.hasNormals() ? mesh.normals : computeVertexNormals(mesh);
  const bool colors = options.colors && mesh.hasColors();
  std::vector<ChartBox> boxes(charts);
  std::vector<ChartMaps> maps(charts);
  result.charts.resize(charts);
  parallelFor(0, charts, [&](std::size_t c) {
    boxes[c] = detail::chartBox(frames[c], texelSize, options);
    maps[c] = detail::rasterizeChart(mesh, faces[c].faces, boxes[c], vertexNormals, colors);
    detail::smoothHeights(maps[c], options.smoothing);
    detail::dilateMaps(maps[c], options.dilation);
    result.charts[c] = detail::chartReport(mesh, faces[c], boxes[c], maps[c]);
  }, 1);
  GeoTexModel& model = result.model;
  model.heightCodec.bits = options.heightBits;
  for (std::size_t c = 0; c < charts; ++c) detail::appendMaps(maps[c], boxes[c], model);
  model.validate();
  return result;
}

/// What a height-map image stands for in world units.
struct HeightMapExtent {
  double width = 1;    ///< world size along the image's x (its columns)
  double depth = 1;    ///< world size along the image's y (its rows, top row at y = depth)
  double height = 0.2; ///< world height of the image's largest value
};

/// A height-map image (one channel, or the first of several) as one chart: the DEM is a geometry
/// texture as it stands. Texel (i, j) is the image's pixel (i, rows - 1 - j), so the picture is
/// upright seen from above; normals from central differences.
template <TexelScalar P>
GeoTexModel heightMapModel(const Image<P>& image, const HeightMapExtent& extent, int heightBits = 16) {
  auto refuse = [](const std::string& problem) { throw Error(ErrorKind::InvalidInput, "height map", problem); };
  if (image.isEmpty() || image.width() < 2 || image.height() < 2) refuse("the image must be at least 2 x 2 pixels");
  if (image.width() > 4096 || image.height() > 4096) refuse("the image is larger than 4096 pixels on a side");
  if (!(extent.width > 0 && extent.depth > 0 && extent.height > 0) ||
      !std::isfinite(extent.width + extent.depth + extent.height))
    refuse("the world extent must be finite and positive");
  if (!HeightCodec::supports(heightBits)) refuse("height bits must be 8 or 16");
  const int w = image.width(), h = image.height();
  ChartMaps maps;
  maps.width = w;
  maps.height = h;
  maps.heights.resize(std::size_t(w) * h);
  maps.normals.resize(maps.heights.size());
  const double pad = 0.5 * std::min(extent.width / w, extent.depth / h);
  auto value = [&](int i, int j) {  // chart texel (i, j), clamped, in world units above the base
    i = std::clamp(i, 0, w - 1);
    j = std::clamp(j, 0, h - 1);
    return pad + extent.height * double(texelToFloat(image.at(i, h - 1 - j, 0)));
  };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t t = std::size_t(j) * w + i;
      maps.heights[t] = float(value(i, j));
      const double dx = (value(i + 1, j) - value(i - 1, j)) / (2 * extent.width / w);
      const double dy = (value(i, j + 1) - value(i, j - 1)) / (2 * extent.depth / h);
      maps.normals[t] = Vec3f(glm::normalize(Vec3d(-dx, -dy, 1)));
    }
  ChartBox box;
  box.width = std::uint32_t(w);
  box.height = std::uint32_t(h);
  box.sizeWS = Vec3d(extent.width, extent.depth, extent.height + 2 * pad);
  GeoTexModel model;
  model.heightCodec.bits = heightBits;
  detail::appendMaps(maps, box, model);
  model.validate();
  return model;
}

}  // namespace cellrelief::geotex
