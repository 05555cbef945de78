// SPDX-License-Identifier: MIT
/// @file polycube_texture.h
/// T2 of PolyCube-Maps with its mip levels, and how a renderer samples it: a point near the
/// polycube's surface goes through P (polycube_surface.h) and M (lookup_table.h) to a squarelet
/// and coordinates in it, then to texels.
///
/// Layout. Every squarelet has a tile of (S + 2) x (S + 2) texels: S x S of its own, and a border
/// one texel wide that repeats the texels of the squarelets across its edges. Bilinear filtering
/// inside a tile then reads, at a squarelet's edge, the same two texel values as the squarelet on
/// the other side reads, so the filtered signal is continuous across squarelets, patches and the
/// polycube's bent edges without fetching across tiles (the paper's manual fetch becomes one
/// hardware bilinear lookup on a GPU). Across a flat border the neighbour's texels continue the
/// plane; across a bent lattice edge they are those of the face the surface turns onto, unfolded.
/// At the lattice vertex the diagonal border texel has no single neighbour (three to six faces
/// meet there); it is set so that the four texels a bilinear read averages at the vertex give one
/// value from every squarelet there (4 V - own - the two neighbours'), which keeps the read
/// continuous at the vertex and along both edges through it, whatever the vertex's valence.
///
/// Mip level k has tiles of S_k = max(1, S >> k) texels plus the border; its texels are the means
/// of 2 x 2 texels of level k - 1 in the same squarelet, never across squarelets, and its borders
/// are filled again from the neighbours at level k. The levels are stacked in one atlas image
/// (level 0 at the top) rather than kept as a GPU mip chain, because padded tiles do not halve
/// from level to level; a renderer picks the level itself and samples it bilinearly.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/polycube/polycube_surface.h"

namespace cellrelief::polycube {

/// A signal to bake, RGBA in [0, 1], at a point of the polycube's surface (lattice coordinates)
/// with the outward unit normal of the face it lies on.
using SurfaceSignal = std::function<Vec4f(const Vec3d& point, const Vec3d& normal)>;

/// How a renderer reads T2, as OpenGL's minification filters do: the nearest texel of level 0,
/// bilinear on level 0, or bilinear on the two mip levels around the footprint's and blended.
enum class TextureFilter { Nearest, Bilinear, Trilinear };

struct TextureOptions {
  int texelsPerSquarelet = 16;  ///< S, a power of two from 1 to 256
  /// GPU textures are limited in width and height (16384 on llvmpipe and lavapipe).
  int maxAtlasSize = 16384;
};

/// A squarelet's geometry: the plane normal to `axis` through its vertex, the two in-plane axes
/// (lower first), and the side of each the squarelet lies on (+1 or -1).
struct SquareletFrame {
  int axis = 0, lo = 1, hi = 2;
  int loSign = 1, hiSign = 1;

  explicit SquareletFrame(int squarelet) {
    axis = squarelet / 4;
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    lo = std::min(a, b);
    hi = std::max(a, b);
    loSign = (squarelet & 1) ? 1 : -1;
    hiSign = (squarelet & 2) ? 1 : -1;
  }
  /// The point at squarelet coordinates (s, t) (each 0..1 over half a cube), relative to the vertex.
  Vec3d offset(double s, double t) const {
    Vec3d d(0.0);
    d[lo] = 0.5 * loSign * s;
    d[hi] = 0.5 * hiSign * t;
    return d;
  }
  /// The octant (of the vertex's eight) just below the squarelet along `axis`.
  int lowerOctant() const { return ((loSign > 0) << lo) | ((hiSign > 0) << hi); }
};

class PolycubeTexture {
 public:
  /// Bakes `signal` into T2 over the surface's squarelets, with every mip level down to 1 x 1.
  /// Throws InvalidArgument for an S that is not a power of two in 1..256 and ResourceLimit when
  /// the atlas would exceed options.maxAtlasSize.
  PolycubeTexture(std::shared_ptr<const PolycubeSurface> surface, const SurfaceSignal& signal,
                  const TextureOptions& options = {});

  /// T2 as written before (atlas(), e.g. read back from a PNG): S is `texels`, or with 0 the one
  /// whose layout has the image's size. Throws InvalidInput when the image does not have that
  /// layout's size or is not RGBA8.
  static PolycubeTexture fromAtlas(std::shared_ptr<const PolycubeSurface> surface, Image<std::uint8_t> atlas,
                                   int texels = 0);

  const PolycubeSurface& surface() const { return *mSurface; }
  std::shared_ptr<const PolycubeSurface> sharedSurface() const { return mSurface; }
  int texelsPerSquarelet() const { return mTexels; }
  int levelCount() const { return int(mLevels.size()); }
  std::uint32_t tilesPerRow() const { return mTilesPerRow; }
  /// All levels, stacked: RGBA8.
  const Image<std::uint8_t>& atlas() const { return mAtlas; }
  std::size_t byteSize() const { return mAtlas.byteSize(); }

  /// Texels per squarelet side at `level`, and the atlas row where the level starts.
  int levelTexels(int level) const { return mLevels[std::size_t(level)].texels; }
  int levelRow(int level) const { return mLevels[std::size_t(level)].row; }

  /// The mip level whose texels match a footprint of `cubes` (lattice units) on the surface: a
  /// cube side holds 2 S texels at level 0. Not clamped.
  float lodOf(double cubes) const {
    return float(std::log2(std::max(cubes * 2.0 * mTexels, 1e-30)));
  }

  /// The atlas position (texel units, centres at + 1/2) of squarelet coordinates `st` of `tile`
  /// at `level`: M followed by the tile's border offset.
  Vec2d atlasPosition(std::uint32_t tile, const Vec2d& st, int level) const {
    const Level& l = mLevels[std::size_t(level)];
    const int size = l.texels + 2;
    return {double(tile % mTilesPerRow) * size + 1 + st.x * l.texels,
            double(l.row) + double(tile / mTilesPerRow) * size + 1 + st.y * l.texels};
  }

  /// Texel (i, j) of a tile at a level, i and j from -1 (border) to S_k (border).
  Vec4f fetch(std::uint32_t tile, int i, int j, int level) const {
    const Vec2i a = texelIndex(tile, i, j, level);
    return mAtlas.fetch(a.x, a.y);
  }

  /// T2 at a squarelet point, filtered; `lod` matters to Trilinear only.
  Vec4f sample(const SquareletPoint& point, TextureFilter filter, float lod = 0) const {
    const std::uint32_t tile = mSurface->lut().at(point.vertex).tileOf(point.squarelet);
    const Vec2d st = glm::clamp(point.st, Vec2d(0.0), Vec2d(1.0));
    if (filter == TextureFilter::Nearest) {
      const int i = std::min(int(st.x * mTexels), mTexels - 1), j = std::min(int(st.y * mTexels), mTexels - 1);
      return fetch(tile, i, j, 0);
    }
    if (filter == TextureFilter::Bilinear) return bilinear(tile, st, 0);
    const float clamped = std::clamp(lod, 0.0f, float(levelCount() - 1));
    const int lower = int(std::floor(clamped));
    const int upper = std::min(lower + 1, levelCount() - 1);
    const Vec4f a = bilinear(tile, st, lower);
    if (upper == lower) return a;
    return glm::mix(a, bilinear(tile, st, upper), clamped - float(lower));
  }

  /// T2 at a point near the surface (lattice coordinates): P, then M, then the filter. Nothing
  /// where P cannot take the point (more than half a cube off the surface).
  std::optional<Vec4f> sampleNear(const Vec3d& p, TextureFilter filter, float lod = 0) const {
    const std::optional<Vec3d> q = mSurface->project(p);
    if (!q) return std::nullopt;
    const std::optional<SquareletPoint> s = mSurface->lut().locate(*q, 1e-6);
    if (!s) return std::nullopt;
    return sample(*s, filter, lod);
  }

 private:
  PolycubeTexture() = default;

  struct Level {
    int texels = 0;  ///< S_k
    int row = 0;     ///< first atlas row
  };

  Vec2i texelIndex(std::uint32_t tile, int i, int j, int level) const {
    const Level& l = mLevels[std::size_t(level)];
    const int size = l.texels + 2;
    return {int(tile % mTilesPerRow) * size + 1 + i, l.row + int(tile / mTilesPerRow) * size + 1 + j};
  }

  Vec4f bilinear(std::uint32_t tile, const Vec2d& st, int level) const {
    const Vec2d a = atlasPosition(tile, st, level);
    return mAtlas.sample(Vec2f(float(a.x / mAtlas.width()), float(a.y / mAtlas.height())));
  }

  void store(std::uint32_t tile, int i, int j, int level, const Vec4f& value) {
    const Vec2i a = texelIndex(tile, i, j, level);
    for (int c = 0; c < 4; ++c) mAtlas.at(a.x, a.y, c) = floatToTexel<std::uint8_t>(value[c]);
  }

  /// One squarelet of the surface: its vertex, index and tile.
  struct SquareletRef {
    Vec3i vertex;
    int squarelet;
    std::uint32_t tile;
  };
  std::vector<SquareletRef> listSquarelets() const;
  /// Sets the levels and tiles per row for these options; returns the atlas's size.
  Vec2i layOut(const TextureOptions& options);
  void bakeLevelZero(const std::vector<SquareletRef>& squarelets, const SurfaceSignal& signal);
  void reduceLevel(const std::vector<SquareletRef>& squarelets, int level);
  void fillBorders(const std::vector<SquareletRef>& squarelets, int level);
  /// Where squarelet coordinates (s, t) outside [0, 1] lie on the surface when the squarelet is
  /// continued across its edge: straight on across a face's centre line, unfolded across a
  /// lattice edge onto the face the surface turns to there.
  Vec3d unfold(const SquareletRef& ref, double s, double t) const;
  /// The border texel diagonally across the vertex (see the file comment).
  Vec4f vertexCorner(const SquareletRef& ref, int level) const;
  /// The texel of `level` whose centre is the surface point q.
  Vec4f texelAt(const Vec3d& q, int level) const;

  std::shared_ptr<const PolycubeSurface> mSurface;
  int mTexels = 16;
  std::uint32_t mTilesPerRow = 1;
  std::vector<Level> mLevels;
  Image<std::uint8_t> mAtlas;
};

// ---- Signals ----

/// Dark lines `cellsPerCube` to a cube, `lineCubes` wide, on light faces tinted by the face's
/// axis: the paper's grid pattern, which shows distortion and seams at a glance. Lines narrower
/// than two texels alias; gridSignalFor picks both for a texture's resolution.
inline SurfaceSignal gridSignal(double cellsPerCube = 4, double lineCubes = 1.0 / 16) {
  return [=](const Vec3d& p, const Vec3d& n) {
    const int axis = std::abs(n.x) > 0.5 ? 0 : std::abs(n.y) > 0.5 ? 1 : 2;
    bool line = false;
    for (int a = 0; a < 3; ++a) {
      if (a == axis) continue;
      const double f = p[a] * cellsPerCube;
      line = line || std::abs(f - std::round(f)) < 0.5 * lineCubes * cellsPerCube;
    }
    static constexpr float kTint[3][3] = {{1.0f, 0.86f, 0.8f}, {0.82f, 1.0f, 0.84f}, {0.84f, 0.88f, 1.0f}};
    const Vec3f base = line ? Vec3f(0.12f) : Vec3f(kTint[axis][0], kTint[axis][1], kTint[axis][2]);
    return Vec4f(base, 1.0f);
  };
}

/// The grid for S texels per squarelet (2 S per cube): lines two texels wide, cells of at least
/// eight texels, at most four cells per cube.
inline SurfaceSignal gridSignalFor(int texelsPerSquarelet) {
  const double texel = 0.5 / std::max(1, texelsPerSquarelet);
  return gridSignal(std::clamp(1.0 / (8 * texel), 1.0, 4.0), 2 * texel);
}

/// A smooth colour field, 0.5 + 0.5 sin(2 pi p_a / period) per channel on three skewed axes: no
/// edges of its own, so any jump a renderer shows is a seam. Its gradient is at most
/// 1.03 pi / period per cube and channel (the axes' largest length is 1.03): the seam tests' bound.
inline SurfaceSignal smoothSignal(double period = 2.0) {
  return [=](const Vec3d& p, const Vec3d&) {
    static constexpr double kAxes[3][3] = {{0.8, 0.5, 0.33}, {-0.3, 0.9, 0.3}, {0.45, -0.4, 0.8}};
    Vec4f c(1.0f);
    for (int k = 0; k < 3; ++k) {
      const double x = kAxes[k][0] * p.x + kAxes[k][1] * p.y + kAxes[k][2] * p.z;
      c[k] = float(0.5 + 0.5 * std::sin(2.0 * 3.14159265358979323846 * x / period));
    }
    return c;
  };
}

}  // namespace cellrelief::polycube

#include "cellrelief/polycube/polycube_texture.ipp"
