// SPDX-License-Identifier: MIT
// T2: baking reproduces the signal at texel centres, mip levels combine texels of one squarelet
// only, and filtered reads are continuous across every kind of squarelet border (a face's centre
// lines, flat lattice edges, convex and concave bends) at every level.
#include <random>
#include <set>

#include <gtest/gtest.h>

#include <cellrelief/polycube/polycube_texture.h>

#include "random_polycubes.h"

namespace cellrelief::polycube {
namespace {

constexpr float kQuantum = 1.0f / 255.0f;

/// Polycubes with flat, convex and concave edges and every case, 6b included.
std::vector<std::shared_ptr<const PolycubeSurface>> testSurfaces() {
  std::vector<std::shared_ptr<const PolycubeSurface>> out;
  for (Polycube& p : fixtures::shapedPolycubes()) out.push_back(std::make_shared<PolycubeSurface>(std::move(p)));
  std::size_t saddles = 0;
  for (Polycube& p : fixtures::randomManifoldPolycubes(6, 23)) {
    saddles += verticesOfCase(p, VertexCase::k6b).size();
    out.push_back(std::make_shared<PolycubeSurface>(std::move(p)));
  }
  EXPECT_GT(saddles, 0u) << "the random polycubes should reach case 6b";
  return out;
}

float maxDifference(const Vec4f& a, const Vec4f& b) {
  const Vec4f d = glm::abs(a - b);
  return std::max(std::max(d.x, d.y), std::max(d.z, d.w));
}

/// Every squarelet of the surface that holds the surface point q, with q's coordinates in it.
std::vector<SquareletPoint> squareletsHolding(const PolycubeSurface& surface, const Vec3d& q, double tolerance = 1e-9) {
  std::vector<SquareletPoint> out;
  const Vec3i nearest(glm::floor(q + Vec3d(0.5)));
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const Vec3i v = nearest + Vec3i(dx, dy, dz);
        const LutEntry& e = surface.lut().at(v);
        if (e.empty()) continue;
        for (int s = 0; s < 12; ++s) {
          if (!(e.squarelets() & (1u << s))) continue;
          const SquareletFrame f(s);
          const Vec3d d = q - Vec3d(v);
          const double sx = 2 * d[f.lo] * f.loSign, tx = 2 * d[f.hi] * f.hiSign;
          if (std::abs(d[f.axis]) <= tolerance && sx >= -tolerance && sx <= 1 + tolerance && tx >= -tolerance &&
              tx <= 1 + tolerance)
            out.push_back({v, s, Vec2d(std::clamp(sx, 0.0, 1.0), std::clamp(tx, 0.0, 1.0))});
        }
      }
  return out;
}

TEST(PolycubeTexture, LayoutHasEveryLevelAndRefusesBadSizes) {
  const auto surface = testSurfaces()[0];
  const PolycubeTexture t(surface, smoothSignal(), {8});
  EXPECT_EQ(t.levelCount(), 4);  // 8, 4, 2, 1
  EXPECT_EQ(t.levelTexels(3), 1);
  EXPECT_EQ(t.atlas().width(), int(t.tilesPerRow()) * 10);
  // M then the tile's offset: a squarelet's points stay inside its own tile's interior at every
  // level, and no two tiles of any levels overlap.
  std::set<std::pair<int, int>> texelsUsed;
  for (std::uint32_t tile = 0; tile < surface->lut().tileCount(); ++tile)
    for (int level = 0; level < t.levelCount(); ++level) {
      const int texels = t.levelTexels(level);
      const Vec2d lo = t.atlasPosition(tile, Vec2d(0.0), level), hi = t.atlasPosition(tile, Vec2d(1.0), level);
      EXPECT_EQ(hi - lo, Vec2d(texels));
      EXPECT_GE(lo.x, 1.0);
      EXPECT_GE(lo.y, 1.0);
      EXPECT_LE(hi.x + 1, t.atlas().width());
      EXPECT_LE(hi.y + 1, t.atlas().height());
      for (int j = -1; j <= texels; ++j)
        for (int i = -1; i <= texels; ++i)
          EXPECT_TRUE(texelsUsed.insert({int(lo.x) + i, int(lo.y) + j}).second) << "tiles overlap";
    }
  EXPECT_THROW(PolycubeTexture(surface, smoothSignal(), {12}), Error);
  EXPECT_THROW(PolycubeTexture(surface, smoothSignal(), {0}), Error);
  EXPECT_THROW(PolycubeTexture(surface, smoothSignal(), {512}), Error);
  EXPECT_THROW(PolycubeTexture(surface, SurfaceSignal{}, {8}), Error);
  TextureOptions tiny{64};
  tiny.maxAtlasSize = 256;
  try {
    PolycubeTexture(surface, smoothSignal(), tiny);
    ADD_FAILURE() << "an atlas over the limit was made";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::ResourceLimit);
    EXPECT_NE(std::string(e.what()).find("fewer texels"), std::string::npos) << e.what();
  }
}

TEST(PolycubeTexture, TexelsHoldTheSignalAtTheirCentresAndMipsStayInTheirSquarelet) {
  for (const auto& surface : testSurfaces()) {
    const SurfaceSignal signal = smoothSignal(1.5);
    const PolycubeTexture t(surface, signal, {8});
    const PolycubeLut& lut = surface->lut();
    for (const LutEntry& e : lut.entries()) {
      if (e.empty()) continue;
      for (int s = 0; s < 12; ++s) {
        if (!(e.squarelets() & (1u << s))) continue;
        const std::uint32_t tile = e.tileOf(s);
        for (int level = 1; level < t.levelCount(); ++level) {
          const int texels = t.levelTexels(level);
          for (int j = 0; j < texels; ++j)
            for (int i = 0; i < texels; ++i) {
              const Vec4f mean = 0.25f * (t.fetch(tile, 2 * i, 2 * j, level - 1) + t.fetch(tile, 2 * i + 1, 2 * j, level - 1) +
                                          t.fetch(tile, 2 * i, 2 * j + 1, level - 1) +
                                          t.fetch(tile, 2 * i + 1, 2 * j + 1, level - 1));
              ASSERT_LE(maxDifference(t.fetch(tile, i, j, level), mean), kQuantum) << "level " << level;
            }
        }
      }
    }
    // Level 0 texel centres, reached through M from surface points.
    std::mt19937 random(3);
    for (const Vec3i& v : surface->polycube().surfaceVertices()) {
      const LutEntry& e = lut.at(v);
      for (int s = 0; s < 12; ++s) {
        if (!(e.squarelets() & (1u << s))) continue;
        const SquareletFrame f(s);
        const int i = int(random() % 8), j = int(random() % 8);
        const Vec3d p = Vec3d(v) + f.offset((i + 0.5) / 8, (j + 0.5) / 8);
        Vec3d normal(0.0);
        normal[f.axis] = ((e.configuration >> f.lowerOctant()) & 1) ? 1.0 : -1.0;
        EXPECT_LE(maxDifference(t.fetch(e.tileOf(s), i, j, 0), signal(p, normal)), 0.51f * kQuantum);
        const std::optional<Vec4f> nearest = t.sampleNear(p, TextureFilter::Nearest);
        ASSERT_TRUE(nearest);
        EXPECT_LE(maxDifference(*nearest, signal(p, normal)), 0.51f * kQuantum);
      }
    }
  }
}

/// Border points of every face (its centre lines and lattice edges) read from every squarelet
/// that holds them, at each lod. Counts the points and the reads across bent edges.
void expectNoJumps(double period, std::initializer_list<float> lods, std::size_t& borders, std::size_t& bent) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const auto& surface : testSurfaces()) {
    const PolycubeTexture t(surface, smoothSignal(period), {8});
    // Points on the borders: the centre lines and the lattice edges of every face.
    for (const Vec3i& c : surface->polycube().cubes())
      for (int face = 0; face < 6; ++face) {
        Vec3i n = c;
        n[face >> 1] += (face & 1) ? 1 : -1;
        if (surface->polycube().contains(n)) continue;
        const int axis = face >> 1, a = (axis + 1) % 3, b = (axis + 2) % 3;
        for (double line : {0.0, 0.5, 1.0}) {
          Vec3d q(c);
          q[axis] += (face & 1) ? 1.0 : 0.0;
          q[a] += line;
          q[b] += unit(random);
          const std::vector<SquareletPoint> holders = squareletsHolding(*surface, q);
          ASSERT_GE(holders.size(), 2u) << "a border point in fewer than two squarelets";
          ++borders;
          for (const SquareletPoint& h : holders) bent += SquareletFrame(h.squarelet).axis != SquareletFrame(holders[0].squarelet).axis;
          for (float lod : lods) {
            const Vec4f reference = t.sample(holders[0], TextureFilter::Trilinear, lod);
            for (std::size_t k = 1; k < holders.size(); ++k)
              EXPECT_LE(maxDifference(t.sample(holders[k], TextureFilter::Trilinear, lod), reference), 2 * kQuantum)
                  << "a jump across a squarelet border at lod " << lod << ", point (" << q.x << ", " << q.y << ", "
                  << q.z << ")";
          }
        }
      }
  }
}

TEST(PolycubeTexture, FilteredReadsAgreeAcrossEverySquareletBorderAtEveryLevel) {
  std::size_t borders = 0, bent = 0;
  // A signal of 1.5 cubes' period has 12 texels to a period at level 1 and is tested down to
  // there; at coarser levels, where a period spans a few texels, its corners at five- and six-face
  // vertices would need values outside [0, 1] (polycube_texture.h), so those levels are tested
  // with a smoother signal.
  expectNoJumps(1.5, {0.0f, 0.5f, 1.0f}, borders, bent);
  expectNoJumps(6.0, {0.0f, 1.5f, 2.0f, 2.5f, 3.0f}, borders, bent);
  EXPECT_GT(borders, 1000u);
  EXPECT_GT(bent, 100u) << "the surfaces should have bent edges";
}

TEST(PolycubeTexture, BilinearReadsFollowTheSignalWithinItsGradientTimesATexel) {
  const double period = 2.0;
  // |d/dx| of 0.5 + 0.5 sin(2 pi a.p / period) is at most pi |a| / period per cube, |a| <= 1.03.
  const double gradient = 3.14159265358979 * 1.03 / period;
  std::mt19937 random(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const auto& surface : testSurfaces()) {
    const SurfaceSignal signal = smoothSignal(period);
    const PolycubeTexture t(surface, signal, {16});
    const double texel = 0.5 / 16;  // cubes
    for (const Vec3i& c : surface->polycube().cubes())
      for (int face = 0; face < 6; ++face) {
        Vec3i n = c;
        n[face >> 1] += (face & 1) ? 1 : -1;
        if (surface->polycube().contains(n)) continue;
        const int axis = face >> 1;
        Vec3d q(c);
        q[axis] += (face & 1) ? 1.0 : 0.0;
        q[(axis + 1) % 3] += unit(random);
        q[(axis + 2) % 3] += unit(random);
        Vec3d normal(0.0);
        normal[axis] = (face & 1) ? 1.0 : -1.0;
        const std::optional<Vec4f> v = t.sampleNear(q, TextureFilter::Bilinear);
        ASSERT_TRUE(v);
        EXPECT_LE(maxDifference(*v, signal(q, normal)), float(gradient * texel + 2 * kQuantum));
      }
  }
}

}  // namespace
}  // namespace cellrelief::polycube
