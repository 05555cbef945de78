// SPDX-License-Identifier: MIT
/// @file polycube_texture.ipp
/// Bodies of PolycubeTexture (polycube_texture.h): layout, baking, mip levels and borders.
#pragma once

namespace cellrelief::polycube {

inline PolycubeTexture::PolycubeTexture(std::shared_ptr<const PolycubeSurface> surface, const SurfaceSignal& signal,
                                        const TextureOptions& options)
    : mSurface(std::move(surface)) {
  if (!mSurface) throw Error(ErrorKind::InvalidArgument, "polycube texture: no surface");
  if (!signal) throw Error(ErrorKind::InvalidArgument, "polycube texture: no signal to bake");
  const Vec2i size = layOut(options);
  mAtlas = Image<std::uint8_t>(size.x, size.y, 4);
  const std::vector<SquareletRef> squarelets = listSquarelets();
  bakeLevelZero(squarelets, signal);
  fillBorders(squarelets, 0);
  for (int level = 1; level < levelCount(); ++level) {
    reduceLevel(squarelets, level);
    fillBorders(squarelets, level);
  }
}

inline PolycubeTexture PolycubeTexture::fromAtlas(std::shared_ptr<const PolycubeSurface> surface,
                                                  Image<std::uint8_t> atlas, int texels) {
  if (!surface) throw Error(ErrorKind::InvalidArgument, "polycube texture: no surface");
  if (atlas.isEmpty() || atlas.channels() != 4)
    throw Error(ErrorKind::InvalidInput, "polycube texture: T2 must be an RGBA image of 8 bits per channel");
  PolycubeTexture t;
  t.mSurface = std::move(surface);
  for (int s = 1; s <= 256; s *= 2) {
    if (texels != 0 && s != texels) continue;
    TextureOptions options{s};
    options.maxAtlasSize = 1 << 30;
    if (t.layOut(options) == Vec2i(atlas.width(), atlas.height())) {
      t.mAtlas = std::move(atlas);
      return t;
    }
  }
  throw Error(ErrorKind::InvalidInput, "polycube texture: a " + std::to_string(atlas.width()) + " x " +
                                           std::to_string(atlas.height()) + " image is not T2 of this polycube (" +
                                           std::to_string(t.mSurface->lut().tileCount()) +
                                           " squarelets) at " +
                                           (texels != 0 ? "S = " + std::to_string(texels) : std::string("any S from 1 to 256")));
}

inline std::vector<PolycubeTexture::SquareletRef> PolycubeTexture::listSquarelets() const {
  const PolycubeLut& lut = mSurface->lut();
  std::vector<SquareletRef> out;
  out.reserve(lut.tileCount());
  const Vec3i size = lut.size();
  for (int z = 0; z < size.z; ++z)
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const Vec3i vertex = lut.origin() + Vec3i(x, y, z);
        const LutEntry& e = lut.at(vertex);
        if (e.empty()) continue;
        for (int s = 0; s < 12; ++s)
          if (e.squarelets() & (1u << s)) out.push_back({vertex, s, e.tileOf(s)});
      }
  return out;
}

inline Vec2i PolycubeTexture::layOut(const TextureOptions& options) {
  const int s = options.texelsPerSquarelet;
  if (s < 1 || s > 256 || (s & (s - 1)) != 0)
    throw Error(ErrorKind::InvalidArgument, "polycube texture: texels per squarelet must be a power of two from 1 to 256, not " +
                                                std::to_string(s));
  mTexels = s;
  const std::uint32_t tiles = mSurface->lut().tileCount();
  mTilesPerRow = std::max<std::uint32_t>(1, std::uint32_t(std::ceil(std::sqrt(double(tiles)))));
  const std::uint32_t tileRows = (tiles + mTilesPerRow - 1) / mTilesPerRow;
  mLevels.clear();
  long long row = 0;
  for (int texels = s;; texels /= 2) {
    mLevels.push_back({texels, int(std::min<long long>(row, 1ll << 30))});
    row += (long long)tileRows * (texels + 2);
    if (texels == 1) break;
  }
  const long long width = (long long)mTilesPerRow * (s + 2);
  if (width > options.maxAtlasSize || row > options.maxAtlasSize)
    throw Error(ErrorKind::ResourceLimit, "polycube texture: " + std::to_string(tiles) + " squarelets of " +
                                              std::to_string(s) + " texels need a " + std::to_string(width) + " x " +
                                              std::to_string(row) + " atlas, more than " +
                                              std::to_string(options.maxAtlasSize) + " a side; use fewer texels per squarelet");
  return {int(width), int(row)};
}

inline void PolycubeTexture::bakeLevelZero(const std::vector<SquareletRef>& squarelets, const SurfaceSignal& signal) {
  const PolycubeLut& lut = mSurface->lut();
  parallelFor(0, squarelets.size(), [&](std::size_t k) {
    const SquareletRef& ref = squarelets[k];
    const SquareletFrame frame(ref.squarelet);
    const bool lowerSolid = (lut.at(ref.vertex).configuration >> frame.lowerOctant()) & 1;
    Vec3d normal(0.0);
    normal[frame.axis] = lowerSolid ? 1.0 : -1.0;
    for (int j = 0; j < mTexels; ++j)
      for (int i = 0; i < mTexels; ++i) {
        const Vec3d p = Vec3d(ref.vertex) + frame.offset((i + 0.5) / mTexels, (j + 0.5) / mTexels);
        store(ref.tile, i, j, 0, glm::clamp(signal(p, normal), Vec4f(0.0f), Vec4f(1.0f)));
      }
  }, 16);
}

inline void PolycubeTexture::reduceLevel(const std::vector<SquareletRef>& squarelets, int level) {
  const int texels = levelTexels(level);
  parallelFor(0, squarelets.size(), [&](std::size_t k) {
    const std::uint32_t tile = squarelets[k].tile;
    for (int j = 0; j < texels; ++j)
      for (int i = 0; i < texels; ++i) {
        const Vec4f sum = fetch(tile, 2 * i, 2 * j, level - 1) + fetch(tile, 2 * i + 1, 2 * j, level - 1) +
                          fetch(tile, 2 * i, 2 * j + 1, level - 1) + fetch(tile, 2 * i + 1, 2 * j + 1, level - 1);
        store(tile, i, j, level, 0.25f * sum);
      }
  }, 64);
}

inline void PolycubeTexture::fillBorders(const std::vector<SquareletRef>& squarelets, int level) {
  const int texels = levelTexels(level);
  // Reads only interior texels and writes only its own tile's border: safe in parallel.
  parallelFor(0, squarelets.size(), [&](std::size_t k) {
    const SquareletRef& ref = squarelets[k];
    const auto fill = [&](int i, int j) {
      const double s = (i + 0.5) / texels, t = (j + 0.5) / texels;
      store(ref.tile, i, j, level, texelAt(unfold(ref, s, t), level));
    };
    for (int i = 0; i <= texels; ++i) {
      fill(i, -1);
      fill(i, texels);
    }
    for (int j = 0; j < texels; ++j) {
      fill(-1, j);
      fill(texels, j);
    }
    fill(-1, texels);
  }, 64);
  // The corners at the vertices read the borders just filled.
  parallelFor(0, squarelets.size(), [&](std::size_t k) {
    store(squarelets[k].tile, -1, -1, level, vertexCorner(squarelets[k], level));
  }, 64);
}

inline Vec4f PolycubeTexture::vertexCorner(const SquareletRef& ref, int level) const {
  // A bilinear read at the vertex averages four texels: own (0, 0), the two border texels beside
  // the corner (the neighbours' own (0, 0)) and the corner. With corner = 4 V - those three, every
  // squarelet at the vertex reads V there, and the edges through the vertex stay continuous (each
  // side's row next to the vertex then averages to the same value). V is the mean of the
  // squarelets' own texels, moved into the range where no squarelet's corner leaves [0, 1]; when
  // that range is empty (a sharp signal at a vertex of five or six faces) corners are clamped.
  const auto threeNear = [&](std::uint32_t tile) {
    return fetch(tile, 0, 0, level) + fetch(tile, -1, 0, level) + fetch(tile, 0, -1, level);
  };
  const LutEntry& e = mSurface->lut().at(ref.vertex);
  Vec4f mean(0.0f), lowest(0.0f), highest(1.0f);
  int count = 0;
  for (int s = 0; s < 12; ++s)
    if (e.squarelets() & (1u << s)) {
      const std::uint32_t tile = e.tileOf(s);
      mean += fetch(tile, 0, 0, level);
      const Vec4f three = threeNear(tile);
      lowest = glm::max(lowest, 0.25f * three);
      highest = glm::min(highest, 0.25f * (three + Vec4f(1.0f)));
      ++count;
    }
  mean /= float(count);
  Vec4f v = mean;
  for (int c = 0; c < 4; ++c)
    if (lowest[c] <= highest[c]) v[c] = std::clamp(mean[c], lowest[c], highest[c]);
  return glm::clamp(4.0f * v - threeNear(ref.tile), Vec4f(0.0f), Vec4f(1.0f));
}

inline Vec3d PolycubeTexture::unfold(const SquareletRef& ref, double s, double t) const {
  const SquareletFrame f(ref.squarelet);
  const Vec3d vertex(ref.vertex);
  if (s >= 0 && t >= 0) return vertex + f.offset(s, t);  // in the plane, across a centre line at most
  // Across the lattice edge through the vertex where the negative coordinate is 0.
  const bool acrossLo = s < 0;
  const int across = acrossLo ? f.lo : f.hi, along = acrossLo ? f.hi : f.lo;
  const int acrossSign = acrossLo ? f.loSign : f.hiSign, alongSign = acrossLo ? f.hiSign : f.loSign;
  const double depth = -0.5 * (acrossLo ? s : t);  // cubes past the edge
  const double position = 0.5 * (acrossLo ? t : s);
  // The four cubes around the edge are octants of the vertex on the squarelet's side of `along`:
  // A and B on the squarelet's side of the edge (above and below its plane), C and D beyond it.
  const std::uint8_t configuration = mSurface->lut().at(ref.vertex).configuration;
  const auto solid = [&](int acrossSide, int axisSide) {
    const int octant = ((acrossSide * acrossSign > 0) << across) | ((alongSign > 0) << along) | ((axisSide > 0) << f.axis);
    return ((configuration >> octant) & 1) != 0;
  };
  const bool a = solid(1, 1), c = solid(-1, 1), d = solid(-1, -1);  // B = solid(1, -1) differs from A
  Vec3d p = vertex;
  p[along] += alongSign * position;
  if (c != d)
    p[across] -= acrossSign * depth;  // the plane goes on (a manifold edge has two faces: A|B and one more)
  else if (a != c)
    p[f.axis] += depth;  // the surface turns up, between A and C
  else
    p[f.axis] -= depth;  // the surface turns down, between B and D (C = D = A here, so B differs from D)
  return p;
}

inline Vec4f PolycubeTexture::texelAt(const Vec3d& q, int level) const {
  const std::optional<SquareletPoint> s = mSurface->lut().locate(q, 1e-9);
  if (!s)
    throw Error(ErrorKind::InvalidInput, "polycube texture: a border texel's neighbour (" + std::to_string(q.x) + ", " +
                                             std::to_string(q.y) + ", " + std::to_string(q.z) +
                                             ") is not on the surface; is the polycube manifold?");
  const int texels = levelTexels(level);
  const int i = std::clamp(int(std::floor(s->st.x * texels)), 0, texels - 1);
  const int j = std::clamp(int(std::floor(s->st.y * texels)), 0, texels - 1);
  return fetch(mSurface->lut().at(s->vertex).tileOf(s->squarelet), i, j, level);
}

}  // namespace cellrelief::polycube
