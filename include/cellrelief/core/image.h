// SPDX-License-Identifier: MIT
/// @file image.h
/// 2D images and array textures with a mip chain, sampled like a GPU samples them.
///
/// Texels are interleaved scalars (uint8, uint16 UNORM, or float) with 1 to 4 channels. The memory
/// of one mip level of an ImageArray is [layer][row][column][channel], contiguous: exactly what
/// glTexSubImage3D and a Vulkan buffer-to-image copy of a 2D array take, so backends upload levels
/// as they are. Sampling follows OpenGL: texel centres at (i + 0.5) / size, bilinear weights
/// between the four nearest centres, clamp-to-edge or repeat; integer texels read as UNORM.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/quantize.h"

namespace cellrelief {

/// A scalar a texel channel is stored as.
template <class T>
concept TexelScalar =
    std::same_as<T, std::uint8_t> || std::same_as<T, std::uint16_t> || std::same_as<T, float>;

enum class Wrap { Clamp, Repeat };
enum class Filter { Nearest, Bilinear };

struct Sampler {
  Filter filter = Filter::Bilinear;
  Wrap wrap = Wrap::Clamp;
};

/// The stored value read as a float: UNORM for integer texels, as is for float.
template <TexelScalar T>
inline float texelToFloat(T v) {
  if constexpr (std::same_as<T, float>)
    return v;
  else
    return dequantizeUnorm<T>(v);
}

/// A float written as a texel: UNORM quantization (round to nearest, clamped) for integer texels.
template <TexelScalar T>
inline T floatToTexel(float v) {
  if constexpr (std::same_as<T, float>)
    return v;
  else
    return quantizeUnorm<T>(v);
}

/// Array texture: `layers` images of one size, each with the same mip chain.
template <TexelScalar T>
class ImageArray {
 public:
  using Scalar = T;
  /// Upper bound on one dimension; beyond it a request is a mistake, not an image.
  static constexpr int kMaxDimension = 1 << 16;

  ImageArray() = default;
  ImageArray(int width, int height, int layers, int channels, T fill = T{}) {
    if (width <= 0 || height <= 0 || layers <= 0 || width > kMaxDimension ||
        height > kMaxDimension)
      throw Error(ErrorKind::InvalidArgument, "image size " + std::to_string(width) + "x" +
                                                  std::to_string(height) + "x" +
                                                  std::to_string(layers) + " is out of range");
    if (channels < 1 || channels > 4)
      throw Error(ErrorKind::InvalidArgument,
                  "image channel count " + std::to_string(channels) + " is not 1 to 4");
    mLayers = layers;
    mChannels = channels;
    mLevels.push_back({width, height,
                       std::vector<T>(std::size_t(width) * height * layers * channels, fill)});
  }

  bool isEmpty() const { return mLevels.empty(); }
  int width(int level = 0) const { return mLevels[level].width; }
  int height(int level = 0) const { return mLevels[level].height; }
  int layers() const { return mLayers; }
  int channels() const { return mChannels; }
  int levelCount() const { return static_cast<int>(mLevels.size()); }

  /// All texels of one level, [layer][row][column][channel].
  std::span<T> levelData(int level = 0) { return mLevels[level].texels; }
  std::span<const T> levelData(int level = 0) const { return mLevels[level].texels; }
  std::size_t byteSize() const {
    std::size_t bytes = 0;
    for (const Level& l : mLevels) bytes += l.texels.size() * sizeof(T);
    return bytes;
  }

  T& at(int x, int y, int layer, int channel, int level = 0) {
    return mLevels[level].texels[index(x, y, layer, channel, level)];
  }
  T at(int x, int y, int layer, int channel, int level = 0) const {
    return mLevels[level].texels[index(x, y, layer, channel, level)];
  }

  /// One texel as a float vector; missing channels read as (0, 0, 0, 1) like a GPU.
  Vec4f fetch(int x, int y, int layer, int level = 0) const {
    Vec4f r(0, 0, 0, 1);
    const std::size_t base = index(x, y, layer, 0, level);
    for (int c = 0; c < mChannels; ++c) r[c] = texelToFloat(mLevels[level].texels[base + c]);
    return r;
  }

  /// Samples layer `layer` of level `level` at uv (texel centres at (i + 0.5) / size).
  /// Non-finite coordinates read texel (0, 0); huge ones are reduced before any integer cast.
  Vec4f sample(Vec2f uv, int layer, const Sampler& sampler = {}, int level = 0) const {
    const int w = width(level), h = height(level);
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return fetch(0, 0, layer, level);
    if (sampler.wrap == Wrap::Repeat) {
      uv -= glm::floor(uv);  // into [0, 1): the same texels, and no overflow below
    } else {
      uv = glm::clamp(uv, Vec2f(-1.0f), Vec2f(2.0f));
    }
    const float x = uv.x * static_cast<float>(w), y = uv.y * static_cast<float>(h);
    if (sampler.filter == Filter::Nearest) {
      const int ix = wrapIndex(static_cast<int>(std::floor(x)), w, sampler.wrap);
      const int iy = wrapIndex(static_cast<int>(std::floor(y)), h, sampler.wrap);
      return fetch(ix, iy, layer, level);
    }
    const float fx = x - 0.5f, fy = y - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float ax = fx - x0f, ay = fy - y0f;
    const int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
    const int xa = wrapIndex(x0, w, sampler.wrap), xb = wrapIndex(x0 + 1, w, sampler.wrap);
    const int ya = wrapIndex(y0, h, sampler.wrap), yb = wrapIndex(y0 + 1, h, sampler.wrap);
    const Vec4f top = glm::mix(fetch(xa, ya, layer, level), fetch(xb, ya, layer, level), ax);
    const Vec4f bottom = glm::mix(fetch(xa, yb, layer, level), fetch(xb, yb, layer, level), ax);
    return glm::mix(top, bottom, ay);
  }

  /// Rebuilds levels 1.. down to 1x1. Each texel of a level is the area-weighted mean of the texels
  /// of the level above that its footprint covers, so odd sizes lose nothing at the edges.
  void generateMips() {
    mLevels.resize(1);
    while (mLevels.back().width > 1 || mLevels.back().height > 1) {
      const Level& src = mLevels.back();
      Level dst{std::max(1, src.width / 2), std::max(1, src.height / 2), {}};
      dst.texels.resize(std::size_t(dst.width) * dst.height * mLayers * mChannels);
      const double sx = double(src.width) / dst.width, sy = double(src.height) / dst.height;
      for (int layer = 0; layer < mLayers; ++layer)
        for (int y = 0; y < dst.height; ++y)
          for (int x = 0; x < dst.width; ++x)
            for (int c = 0; c < mChannels; ++c) {
              const double v = boxAverage(src, layer, c, x * sx, (x + 1) * sx, y * sy, (y + 1) * sy);
              dst.texels[(((std::size_t(layer) * dst.height + y) * dst.width) + x) * mChannels +
                         c] = floatToTexel<T>(static_cast<float>(v));
            }
      mLevels.push_back(std::move(dst));
    }
  }

  static int wrapIndex(int i, int size, Wrap wrap) {
    if (wrap == Wrap::Repeat) {
      const int m = i % size;
      return m < 0 ? m + size : m;
    }
    return std::clamp(i, 0, size - 1);
  }

 protected:
  struct Level {
    int width = 0;
    int height = 0;
    std::vector<T> texels;
  };

  std::size_t index(int x, int y, int layer, int channel, int level) const {
    const Level& l = mLevels[level];
    return (((std::size_t(layer) * l.height + y) * l.width) + x) * mChannels + channel;
  }

  double boxAverage(const Level& src, int layer, int c, double x0, double x1, double y0,
                    double y1) const {
    double sum = 0, weight = 0;
    // ceil() of a product that rounds just above the size must not step past the last texel.
    const int yEnd = std::min(static_cast<int>(std::ceil(y1)), src.height);
    const int xEnd = std::min(static_cast<int>(std::ceil(x1)), src.width);
    for (int y = static_cast<int>(y0); y < yEnd; ++y) {
      const double wy = std::min<double>(y + 1, y1) - std::max<double>(y, y0);
      for (int x = static_cast<int>(x0); x < xEnd; ++x) {
        const double wx = std::min<double>(x + 1, x1) - std::max<double>(x, x0);
        const std::size_t i =
            (((std::size_t(layer) * src.height + y) * src.width) + x) * mChannels + c;
        sum += wx * wy * texelToFloat(src.texels[i]);
        weight += wx * wy;
      }
    }
    return sum / weight;
  }

  std::vector<Level> mLevels;
  int mLayers = 0;
  int mChannels = 0;
};

/// A 2D image: an array texture with one layer, with the layer argument dropped.
template <TexelScalar T>
class Image : public ImageArray<T> {
 public:
  Image() = default;
  Image(int width, int height, int channels, T fill = T{})
      : ImageArray<T>(width, height, 1, channels, fill) {}

  T& at(int x, int y, int channel, int level = 0) { return ImageArray<T>::at(x, y, 0, channel, level); }
  T at(int x, int y, int channel, int level = 0) const {
    return ImageArray<T>::at(x, y, 0, channel, level);
  }
  Vec4f fetch(int x, int y, int level = 0) const { return ImageArray<T>::fetch(x, y, 0, level); }
  Vec4f sample(Vec2f uv, const Sampler& sampler = {}, int level = 0) const {
    return ImageArray<T>::sample(uv, 0, sampler, level);
  }
};

}  // namespace cellrelief
