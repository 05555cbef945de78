// SPDX-License-Identifier: MIT
/// @file indirection_map.h
/// The indirection map of section 3.6. The optimizers give M: texture (s, t) -> base plane (u, v).
/// A renderer knows (u, v), where its ray hit the relief, and needs the texture coordinate, M^-1:
/// it fetches colour at (u, v) + I(u, v) with I = M^-1 - id. M^-1 is obtained by rasterizing the
/// relaxed grid in the base plane with per-vertex labels (the texture coordinates (i/g, j/g)),
/// interpolated linearly over the same two triangles per cell that define M, so M(M^-1(x)) = x up
/// to rounding. A plain CPU scan converter (texel centres, top-left fill rule) does it.
///
/// Packing: the paper's printed 8-bit packing formula does not round-trip (it maps I outside
/// [0, 1]); we use min/max normalization per channel instead, q = (I - bias) / scale with
/// bias = min I and scale = max I - min I, stored beside the image, and offer 16-bit or float.
/// Pre-warp (section 5.2): a structured texture C (bricks, text) would be distorted by the
/// indirection; C'(s) = C(M(s)) undoes it, since C'(M^-1(x)) = C(x).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/indirection/grid.h"

namespace cellrelief::indirection {

/// I(u, v) = M^-1(u, v) - (u, v) as two float channels at texel centres of a w x h image.
inline Image<float> indirectionMap(const Grid& grid, int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error(ErrorKind::InvalidArgument, "indirection map size " + std::to_string(width) + "x" +
                                                std::to_string(height) + " is out of range");
  constexpr float kUnset = std::numeric_limits<float>::quiet_NaN();
  Image<float> out(width, height, 2, kUnset);
  const int g = grid.g();
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i)
      for (const auto& tri : kCellTriangles) {
        Vec2f p[3], label[3];  // p in texels, labels in texture space
        for (int k = 0; k < 3; ++k) {
          const int vi = i + tri[k][0], vj = j + tri[k][1];
          const Vec2f q = grid.vertex(vi, vj);
          p[k] = {q.x * float(width), q.y * float(height)};
          label[k] = {float(vi) / float(g), float(vj) / float(g)};
        }
        const float area = signedArea2(p[0], p[1], p[2]);
        if (!(area > 0)) continue;  // flipped or degenerate: covered by its neighbours
        const int x0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
        const int x1 = std::min(width - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
        const int y0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
        const int y1 = std::min(height - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) {
            const Vec2f c(float(x) + 0.5f, float(y) + 0.5f);
            // Barycentrics; texel centres on an edge go to one side only (top-left style rule).
            float w[3];
            bool inside = true;
            for (int k = 0; k < 3 && inside; ++k) {
              const Vec2f a = p[(k + 1) % 3], b = p[(k + 2) % 3];
              w[k] = signedArea2(a, b, c);
              const Vec2f e = b - a;
              const bool topLeft = (e.y < 0) || (e.y == 0 && e.x > 0);
              inside = w[k] > 0 || (w[k] == 0 && topLeft);
            }
            if (!inside) continue;
            const Vec2f st = (w[0] * label[0] + w[1] * label[1] + w[2] * label[2]) / area;
            out.at(x, y, 0) = st.x - c.x / float(width);
            out.at(x, y, 1) = st.y - c.y / float(height);
          }
      }
  // Texel centres the triangles missed (only possible at the very border, through rounding):
  // take the nearest set neighbour in the row, else the column.
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (std::isnan(out.at(x, y, 0))) {
        bool done = false;
        for (int r = 1; r < std::max(width, height) && !done; ++r)
          for (const Vec2i d : {Vec2i(r, 0), Vec2i(-r, 0), Vec2i(0, r), Vec2i(0, -r)}) {
            const int nx = x + d.x, ny = y + d.y;
            if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            if (std::isnan(out.at(nx, ny, 0))) continue;
            out.at(x, y, 0) = out.at(nx, ny, 0);
            out.at(x, y, 1) = out.at(nx, ny, 1);
            done = true;
            break;
          }
        if (!done) out.at(x, y, 0) = out.at(x, y, 1) = 0;
      }
  return out;
}

/// I = M^-1 - id quantized per channel: value = bias + scale * q, q in [0, 1].
template <TexelScalar T>
struct PackedIndirection {
  Image<T> texels;  ///< 2 channels (plus an unused third when written as RGB)
  Vec2f scale{1.0f}, bias{0.0f};
  /// I at texel (x, y).
  Vec2f decode(int x, int y) const {
    const Vec4f q = texels.fetch(x, y);
    return {bias.x + scale.x * q.x, bias.y + scale.y * q.y};
  }
};

/// Quantizes I with min/max normalization into `channels` (2 or 3: RGB with B = 0) channels of T.
template <TexelScalar T>
PackedIndirection<T> packIndirection(const Image<float>& map, int channels = 2) {
  if (map.isEmpty() || map.channels() < 2)
    throw Error(ErrorKind::InvalidArgument, "packIndirection: needs a 2-channel indirection map");
  PackedIndirection<T> p;
  p.texels = Image<T>(map.width(), map.height(), std::clamp(channels, 2, 3));
  for (int c = 0; c < 2; ++c) {
    float lo = HUGE_VALF, hi = -HUGE_VALF;
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x) {
        lo = std::min(lo, map.at(x, y, c));
        hi = std::max(hi, map.at(x, y, c));
      }
    p.bias[c] = lo;
    p.scale[c] = hi > lo ? hi - lo : 0.0f;
    const float inv = hi > lo ? 1.0f / (hi - lo) : 0.0f;
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x)
        p.texels.at(x, y, c) = floatToTexel<T>((map.at(x, y, c) - lo) * inv);
  }
  return p;
}

/// Looks up I bilinearly at (u, v) (texel centres, clamped) from a float indirection map.
inline Vec2f sampleIndirection(const Image<float>& map, Vec2f uv) {
  const Vec4f s = map.sample(uv, Sampler{Filter::Bilinear, Wrap::Clamp});
  return {s.x, s.y};
}

/// Pre-warp of a structured texture by M^-1 (section 5.2): C'(s) = C(M(s)), sampled bilinearly.
template <TexelScalar T>
Image<T> prewarp(const Image<T>& texture, const Grid& grid, Wrap wrap = Wrap::Clamp) {
  Image<T> out(texture.width(), texture.height(), texture.channels());
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x) {
      const Vec2f st((x + 0.5f) / float(out.width()), (y + 0.5f) / float(out.height()));
      const Vec4f c = texture.sample(grid.map(st), Sampler{Filter::Bilinear, wrap});
      for (int k = 0; k < out.channels(); ++k) out.at(x, y, k) = floatToTexel<T>(c[k]);
    }
  return out;
}

}  // namespace cellrelief::indirection
