// SPDX-License-Identifier: MIT
/// @file relief_map.h
/// A relief map R(u, v) = (u, v, s * H(u, v)) over the unit square: a height map H in [0, 1] read
/// from a grayscale PNG/JPEG/BMP (or the alpha channel of a TGA normal map), 8 or 16 bit, times a
/// height scale s in texture units (s = 0.1: the highest point is a tenth of the tile's width).
///
/// Evaluation is the piecewise-bilinear interpolant between texel centres, (i + 0.5) / size, the
/// way a GPU samples it, so the optimizers, the distortion measure and the parallax renderer all see
/// the same surface. The gradient is the exact derivative of that interpolant (piecewise linear in
/// each direction), which the Ceres optimizer uses for analytic derivatives. Borders clamp (the
/// interpolant is constant beyond the outer texel centres) or repeat (tiling height maps).
/// Heights are stored as float in one contiguous array: the spring loop evaluates tens of millions
/// of heights per second and must not go through the channel-generic Image sampler.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/core/math.h"
#include "cellrelief/io/image_io.h"

namespace cellrelief::indirection {

/// Which channel of an image holds the height.
enum class HeightChannel {
  Auto,   ///< alpha of a 4-channel TGA (DirectX SDK normal+height maps), else the gray/RGB mean
  Gray,   ///< the gray channel, or the mean of R, G, B
  Alpha,  ///< the alpha channel (the image must have 2 or 4 channels)
};

struct ReliefOptions {
  float heightScale = 0.1f;  ///< s: the height of H = 1 in units of the tile width
  Wrap wrap = Wrap::Clamp;   ///< Repeat for tiling height maps
  HeightChannel channel = HeightChannel::Auto;
};

/// One axis of a bilinear lookup between texel centres ((i + 0.5) / size): the two texel indices,
/// the fraction between them, and its derivative d(fraction)/d(t) (0 where the clamped interpolant
/// is constant). Shared by every map of a relief surface, and followed by the GPU shader.
inline void bilinearAxis(float t, int size, bool repeat, int& i0, int& i1, float& fraction, float& slope) {
  float x = t * float(size) - 0.5f;
  slope = float(size);
  if (repeat) {
    if (!std::isfinite(x)) x = 0;
    x -= float(size) * std::floor(x / float(size));  // into [0, size)
    // Far from the map (|x| beyond 2^24: a grazing ray's end, a large UV scale) the reduction can
    // leave [0, size) where multiply and subtract are fused (aarch64, GPUs): any texel is as good
    // there, an index outside the map is not.
    if (!(x >= 0.0f && x < float(size))) x = 0.0f;
    const float fl = std::floor(x);
    i0 = std::min(int(fl), size - 1);
    i1 = i0 + 1 == size ? 0 : i0 + 1;
    fraction = x - fl;
    return;
  }
  if (!(x > 0)) {  // also NaN
    i0 = i1 = 0;
    fraction = slope = 0;
    return;
  }
  if (x >= float(size - 1)) {
    i0 = i1 = size - 1;
    fraction = slope = 0;
    return;
  }
  const float fl = std::floor(x);
  i0 = int(fl);
  i1 = i0 + 1;
  fraction = x - fl;
}

/// The relief surface R(u, v) over [0, 1]^2. Copyable value type.
class ReliefMap {
 public:
  ReliefMap() = default;
  /// `heights` are H in [0, 1], row-major, `width` x `height` texels (row 0 at v = 0).
  ReliefMap(int width, int height, std::vector<float> heights, float heightScale,
            Wrap wrap = Wrap::Clamp)
      : mWidth(width), mHeight(height), mWrap(wrap), mScale(heightScale), mH(std::move(heights)) {
    if (width < 2 || height < 2)
      throw Error(ErrorKind::InvalidInput, "a relief map needs at least 2x2 texels, not " +
                                               std::to_string(width) + "x" + std::to_string(height));
    if (mH.size() != std::size_t(width) * height)
      throw Error(ErrorKind::InvalidArgument, "relief map: " + std::to_string(mH.size()) +
                                                  " heights for " + std::to_string(width) + "x" +
                                                  std::to_string(height) + " texels");
    if (!std::isfinite(heightScale) || heightScale < 0 || heightScale > 100)
      throw Error(ErrorKind::InvalidArgument,
                  "height scale " + std::to_string(heightScale) + " is not in [0, 100]");
    for (float& h : mH) {
      if (!std::isfinite(h))
        throw Error(ErrorKind::InvalidInput, "relief map: a height is not a finite number");
      h *= heightScale;  // stored pre-scaled: one multiply less per evaluation
      mMax = std::max(mMax, h);
    }
  }

  int width() const { return mWidth; }
  int height() const { return mHeight; }
  Wrap wrap() const { return mWrap; }
  float heightScale() const { return mScale; }
  /// The larger texel size in texture units, 1 / max(width, height).
  float texelSize() const { return 1.0f / float(std::max(mWidth, mHeight)); }
  /// The highest scaled height (0 for an empty map).
  float maxHeight() const { return mMax; }
  /// The scaled height of texel (x, y).
  float texel(int x, int y) const { return mH[std::size_t(y) * mWidth + x]; }
  bool isFlat() const {
    return mScale == 0 || std::all_of(mH.begin(), mH.end(), [&](float h) { return h == mH[0]; });
  }

  /// s * H(u, v), bilinear between texel centres.
  float heightAt(float u, float v) const {
    Cell c = locate(u, v);
    const float a = mix(c.h00, c.h10, c.fx), b = mix(c.h01, c.h11, c.fx);
    return mix(a, b, c.fy);
  }
  float heightAt(Vec2f uv) const { return heightAt(uv.x, uv.y); }

  /// (dz/du, dz/dv) of the bilinear interpolant (one-sided at texel-centre lines; zero where the
  /// clamped interpolant is constant).
  Vec2f gradientAt(float u, float v) const {
    Cell c = locate(u, v);
    const float du = (mix(c.h10, c.h11, c.fy) - mix(c.h00, c.h01, c.fy)) * c.sx;
    const float dv = (mix(c.h01, c.h11, c.fx) - mix(c.h00, c.h10, c.fx)) * c.sy;
    return {du, dv};
  }
  Vec2f gradientAt(Vec2f uv) const { return gradientAt(uv.x, uv.y); }

  /// The surface point R(u, v).
  Vec3f pointAt(Vec2f uv) const { return {uv.x, uv.y, heightAt(uv.x, uv.y)}; }

  /// The area of the relief surface over the unit square, by the midpoint rule on a n x n grid.
  double surfaceArea(int n = 0) const {
    if (n <= 0) n = std::max(mWidth, mHeight);
    double area = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec2f g = gradientAt((i + 0.5f) / n, (j + 0.5f) / n);
        area += std::sqrt(1.0 + double(g.x) * g.x + double(g.y) * g.y);
      }
    return area / (double(n) * n);
  }

 private:
  struct Cell {
    float h00, h10, h01, h11, fx, fy, sx, sy;  // sx, sy: d(fx)/du, d(fy)/dv (0 where clamped)
  };
  static float mix(float a, float b, float t) { return a + (b - a) * t; }

  void axis(float t, int size, int& i0, int& i1, float& f, float& s) const {
    bilinearAxis(t, size, mWrap == Wrap::Repeat, i0, i1, f, s);
  }

  Cell locate(float u, float v) const {
    int x0, x1, y0, y1;
    Cell c;
    axis(u, mWidth, x0, x1, c.fx, c.sx);
    axis(v, mHeight, y0, y1, c.fy, c.sy);
    const float* r0 = mH.data() + std::size_t(y0) * mWidth;
    const float* r1 = mH.data() + std::size_t(y1) * mWidth;
    c.h00 = r0[x0];
    c.h10 = r0[x1];
    c.h01 = r1[x0];
    c.h11 = r1[x1];
    return c;
  }

  int mWidth = 0, mHeight = 0;
  Wrap mWrap = Wrap::Clamp;
  float mScale = 0;
  float mMax = 0;
  std::vector<float> mH;
};

/// The heights of an image file as H in [0, 1] (UNORM of the chosen channel).
inline std::vector<float> heightsOf(const io::ImageFile& file, HeightChannel channel,
                                    const std::filesystem::path& path) {
  int c = -1;  // mean of colour channels (or gray)
  if (channel == HeightChannel::Alpha ||
      (channel == HeightChannel::Auto && file.channels() == 4 && file.format == "tga")) {
    if (file.channels() != 2 && file.channels() != 4)
      throw Error(ErrorKind::InvalidInput, path,
                  "height in alpha requested, but the image has " +
                      std::to_string(file.channels()) + " channel(s) and no alpha");
    c = file.channels() - 1;
  }
  const Image<float> f = file.toFloat(c);
  const auto data = f.levelData(0);
  return {data.begin(), data.end()};
}

/// The relief map of an image already read from `path` (named in errors). Throws Error when it is
/// smaller than 2x2 or constant (no relief: nothing to parameterize).
inline ReliefMap reliefMapOf(const io::ImageFile& file, const std::filesystem::path& path,
                             const ReliefOptions& options = {}) {
  if (file.width() < 2 || file.height() < 2)
    throw Error(ErrorKind::InvalidInput, path,
                "height map of " + std::to_string(file.width()) + "x" +
                    std::to_string(file.height()) + " texels is too small (at least 2x2)");
  std::vector<float> h = heightsOf(file, options.channel, path);
  const auto [lo, hi] = std::minmax_element(h.begin(), h.end());
  if (*lo == *hi)
    throw Error(ErrorKind::InvalidInput, path,
                "height map is constant (every texel " + std::to_string(*lo) +
                    "): no relief to parameterize");
  try {
    return ReliefMap(file.width(), file.height(), std::move(h), options.heightScale, options.wrap);
  } catch (const Error& e) {
    throw Error(e.kind(), path, e.problem());
  }
}

/// Reads a relief map from a height-map image. Throws Error naming the file when it cannot be read,
/// is smaller than 2x2, or is constant.
inline ReliefMap loadReliefMap(const std::filesystem::path& path, const ReliefOptions& options = {}) {
  return reliefMapOf(io::readImage(path), path, options);
}

/// A copy of `map` box-filtered down to at most `maxSize` texels a side (tests and previews).
inline ReliefMap downsample(const ReliefMap& map, int maxSize) {
  int f = 1;
  while (std::max(map.width(), map.height()) / f > maxSize) f *= 2;
  if (f == 1) return map;
  const int w = std::max(2, map.width() / f), h = std::max(2, map.height() / f);
  std::vector<float> out(std::size_t(w) * h, 0.0f);
  const float inv = map.heightScale() > 0 ? 1.0f / map.heightScale() : 0.0f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      int n = 0;
      for (int dy = 0; dy < f && y * f + dy < map.height(); ++dy)
        for (int dx = 0; dx < f && x * f + dx < map.width(); ++dx, ++n)
          sum += map.texel(x * f + dx, y * f + dy);
      out[std::size_t(y) * w + x] = float(sum / n) * inv;
    }
  return ReliefMap(w, h, std::move(out), map.heightScale(), map.wrap());
}

}  // namespace cellrelief::indirection
