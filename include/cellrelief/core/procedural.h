// SPDX-License-Identifier: MIT
/// @file procedural.h
/// Meshes the library makes itself: analytic shapes for exact tests (sphere, torus) and the demo
/// model, a torus displaced by multi-octave gradient noise so that it carries real fine detail
/// (ridges smaller than a cell) without shipping any data.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief {

/// Splits every triangle into four at its edges, `levels` times: `place(a, b)` gives the new vertex
/// between positions a and b (shared by the two triangles of the edge). Corners keep their order.
template <class Place>
void splitTrianglesInFour(TriangleMesh& m, int levels, Place&& place) {
  for (int s = 0; s < levels; ++s) {
    std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, inserted] = midpoints.try_emplace(key, std::uint32_t(m.positions.size()));
      if (inserted) m.positions.push_back(place(m.positions[a], m.positions[b]));
      return it->second;
    };
    std::vector<Vec3u> next;
    next.reserve(m.triangles.size() * 4);
    for (const Vec3u& t : m.triangles) {
      const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                          ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
}

/// Geodesic sphere: an icosahedron whose faces are split in four `subdivisions` times and whose
/// vertices are pushed onto the sphere; 20 * 4^s triangles, all nearly equilateral.
inline TriangleMesh makeIcosphere(int subdivisions, float radius = 1.0f) {
  if (subdivisions < 0 || subdivisions > 9)
    throw Error(ErrorKind::InvalidArgument,
                "icosphere subdivisions must be 0..9, got " + std::to_string(subdivisions));
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  TriangleMesh m;
  m.positions = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3f& p : m.positions) p = glm::normalize(p);
  splitTrianglesInFour(m, subdivisions, [](const Vec3f& a, const Vec3f& b) { return glm::normalize(a + b); });
  m.normals = m.positions;
  for (Vec3f& p : m.positions) p *= radius;
  m.sourcePolygons = m.triangles.size();
  return m;
}

/// Torus around the z axis: major radius R, minor radius r, `ringSegments` x `tubeSegments` quads
/// split into two triangles each.
inline TriangleMesh makeTorus(float majorRadius, float minorRadius, int ringSegments,
                              int tubeSegments) {
  if (ringSegments < 3 || tubeSegments < 3 || !(minorRadius > 0) || !(majorRadius > minorRadius))
    throw Error(ErrorKind::InvalidArgument,
                "torus needs R > r > 0 and at least 3 segments each way");
  TriangleMesh m;
  const float twoPi = 2.0f * std::numbers::pi_v<float>;
  for (int i = 0; i < ringSegments; ++i) {
    const float u = twoPi * float(i) / float(ringSegments);
    for (int j = 0; j < tubeSegments; ++j) {
      const float v = twoPi * float(j) / float(tubeSegments);
      const Vec3f n(std::cos(u) * std::cos(v), std::sin(u) * std::cos(v), std::sin(v));
      m.positions.push_back(Vec3f(majorRadius * std::cos(u), majorRadius * std::sin(u), 0) +
                            minorRadius * n);
      m.normals.push_back(n);
    }
  }
  auto id = [&](int i, int j) {
    return std::uint32_t((i % ringSegments) * tubeSegments + (j % tubeSegments));
  };
  for (int i = 0; i < ringSegments; ++i)
    for (int j = 0; j < tubeSegments; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  m.sourcePolygons = m.triangles.size();
  return m;
}

/// 3D gradient noise (Perlin's improved noise with a hashed lattice), range about [-1, 1].
class GradientNoise {
 public:
  explicit GradientNoise(std::uint32_t seed = 1) {
    for (int i = 0; i < 256; ++i) mPerm[i] = static_cast<std::uint8_t>(i);
    std::uint32_t state = seed * 747796405u + 2891336453u;
    for (int i = 255; i > 0; --i) {  // Fisher-Yates with a PCG-style step: reproducible
      state = state * 747796405u + 2891336453u;
      const int j = static_cast<int>((state >> 8) % std::uint32_t(i + 1));
      std::swap(mPerm[i], mPerm[j]);
    }
    for (int i = 0; i < 256; ++i) mPerm[256 + i] = mPerm[i];
  }

  float operator()(Vec3f p) const {
    const Vec3f f = glm::floor(p);
    const int X = static_cast<int>(f.x) & 255, Y = static_cast<int>(f.y) & 255,
              Z = static_cast<int>(f.z) & 255;
    const Vec3f d = p - f;
    const Vec3f w = d * d * d * (d * (d * 6.0f - 15.0f) + 10.0f);
    auto h = [&](int x, int y, int z) { return mPerm[mPerm[mPerm[x] + y] + z]; };
    auto grad = [](int hash, float x, float y, float z) {
      const int k = hash & 15;
      const float u = k < 8 ? x : y, v = k < 4 ? y : (k == 12 || k == 14 ? x : z);
      return ((k & 1) ? -u : u) + ((k & 2) ? -v : v);
    };
    const float n000 = grad(h(X, Y, Z), d.x, d.y, d.z);
    const float n100 = grad(h(X + 1, Y, Z), d.x - 1, d.y, d.z);
    const float n010 = grad(h(X, Y + 1, Z), d.x, d.y - 1, d.z);
    const float n110 = grad(h(X + 1, Y + 1, Z), d.x - 1, d.y - 1, d.z);
    const float n001 = grad(h(X, Y, Z + 1), d.x, d.y, d.z - 1);
    const float n101 = grad(h(X + 1, Y, Z + 1), d.x - 1, d.y, d.z - 1);
    const float n011 = grad(h(X, Y + 1, Z + 1), d.x, d.y - 1, d.z - 1);
    const float n111 = grad(h(X + 1, Y + 1, Z + 1), d.x - 1, d.y - 1, d.z - 1);
    const float x00 = glm::mix(n000, n100, w.x), x10 = glm::mix(n010, n110, w.x);
    const float x01 = glm::mix(n001, n101, w.x), x11 = glm::mix(n011, n111, w.x);
    return glm::mix(glm::mix(x00, x10, w.y), glm::mix(x01, x11, w.y), w.z);
  }

 private:
  std::uint8_t mPerm[512];
};

struct DisplacedSphereOptions {
  int subdivisions = 7;        ///< 20 * 4^7 = 327,680 triangles
  float radius = 1.0f;
  float amplitude = 0.12f;     ///< largest displacement, relative to the radius
  float baseFrequency = 2.0f;  ///< features per unit radius of the first octave
  int octaves = 7;             ///< each octave doubles the frequency: detail down to ~1/256
  std::uint32_t seed = 7;
};

namespace detail {
/// Displaces every vertex along its unit direction `directions[i]` by ridged multi-octave noise
/// sampled at `noisePoints[i]`; sets normals and height-following colors.
inline void displaceWithRidgedNoise(TriangleMesh& m, const std::vector<Vec3f>& directions,
                                    const std::vector<Vec3f>& noisePoints, float amplitude,
                                    float baseFrequency, int octaves, std::uint32_t seed) {
  const GradientNoise noise(seed);
  std::vector<float> heights(m.positions.size());
  parallelFor(0, m.positions.size(), [&](std::size_t i) {
    const Vec3f p = noisePoints[i];
    float sum = 0, amp = 1, freq = baseFrequency, norm = 0;
    for (int k = 0; k < octaves; ++k) {
      const float ridge = 1.0f - std::abs(noise(p * freq + Vec3f(float(k) * 17.3f)));
      sum += amp * ridge * ridge;
      norm += amp;
      amp *= 0.5f;
      freq *= 2.0f;
    }
    heights[i] = sum / norm;  // in [0, 1]
    m.positions[i] += directions[i] * (amplitude * (heights[i] - 0.5f));
  });
  m.normals = computeVertexNormals(m);
  m.colors.resize(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const float h = glm::clamp(heights[i], 0.0f, 1.0f);
    const Vec3f low(0.23f, 0.36f, 0.55f), mid(0.78f, 0.70f, 0.52f), high(0.96f, 0.95f, 0.92f);
    const Vec3f c = h < 0.5f ? glm::mix(low, mid, h * 2.0f) : glm::mix(mid, high, h * 2.0f - 1.0f);
    m.colors[i] = Color8(glm::round(c * 255.0f), 255);
  }
}
}  // namespace detail

/// A sphere displaced along its normals by ridged multi-octave noise (sharp crests, fine grooves),
/// with vertex normals and colors that follow the height.
inline TriangleMesh makeDisplacedSphere(const DisplacedSphereOptions& o = {}) {
  TriangleMesh m = makeIcosphere(o.subdivisions, 1.0f);
  const std::vector<Vec3f> directions = m.positions;
  for (Vec3f& p : m.positions) p *= o.radius;
  detail::displaceWithRidgedNoise(m, directions, directions, o.amplitude * o.radius,
                                  o.baseFrequency, o.octaves, o.seed);
  return m;
}

struct DisplacedTorusOptions {
  float majorRadius = 1.0f;
  float minorRadius = 0.4f;
  int ringSegments = 512;   ///< 512 x 320 x 2 = 327,680 triangles
  int tubeSegments = 320;
  float amplitude = 0.08f;  ///< largest displacement, relative to the major radius
  float baseFrequency = 2.5f;
  int octaves = 7;
  std::uint32_t seed = 7;
};

/// The built-in demo model: a torus (not star-shaped, genus 1, so the cell complex has work to
/// do) displaced along its normals by ridged multi-octave noise.
inline TriangleMesh makeDisplacedTorus(const DisplacedTorusOptions& o = {}) {
  TriangleMesh m = makeTorus(o.majorRadius, o.minorRadius, o.ringSegments, o.tubeSegments);
  const std::vector<Vec3f> directions = m.normals;
  detail::displaceWithRidgedNoise(m, directions, m.positions, o.amplitude * o.majorRadius,
                                  o.baseFrequency, o.octaves, o.seed);
  return m;
}

}  // namespace cellrelief
