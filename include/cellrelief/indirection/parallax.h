// SPDX-License-Identifier: MIT
/// @file parallax.h
/// Parallax occlusion mapping with an indirection map, on the CPU (section 4 of McGuire & Whitson):
/// a relief-mapped quad [0,1]^2 x {0} whose relief rises to s * H(u, v), seen by a pinhole camera.
/// Each pixel's ray is marched linearly through the slab 0 <= z <= s from where it enters to where
/// it leaves, and the first crossing below the surface refined by bisection. The colour is fetched at
/// (u, v) + I(u, v) instead of (u, v): one texture fetch more than plain POM.
///
/// It lives in this module, not in backends/cpu, because that backend renders cell complexes and the
/// indirection map only needs a heightfield quad; a backend can call renderParallax per tile. Rows
/// are rendered in parallel with TBB.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "cellrelief/core/image.h"
#include "cellrelief/indirection/indirection_map.h"
#include "cellrelief/indirection/relief_map.h"

namespace cellrelief::indirection {

struct ParallaxView {
  int width = 640, height = 480;
  Vec3f eye{0.5f, -0.55f, 0.75f};  ///< camera position (the quad spans [0,1]^2 at z = 0)
  Vec3f target{0.5f, 0.45f, 0.0f};
  float fovY = 45.0f;              ///< degrees
  int linearSteps = 64;            ///< linear march samples through the slab
  int refineSteps = 8;             ///< bisection steps after the first crossing
  Vec3f lightDir{-0.4f, -0.5f, 0.77f};
  Vec3f background{0.15f, 0.17f, 0.2f};
};

/// A colour at texture coordinate (s, t).
using TextureFunction = std::function<Vec3f(Vec2f)>;

/// A checkerboard of n x n squares, the standard way to show texture stretch.
inline TextureFunction checkerboard(int n = 16) {
  return [n](Vec2f st) {
    const int a = int(std::floor(st.x * float(n))) + int(std::floor(st.y * float(n)));
    return (a & 1) ? Vec3f(0.92f, 0.9f, 0.85f) : Vec3f(0.2f, 0.35f, 0.6f);
  };
}

/// Renders the relief-mapped quad; `indirection` (2-channel float I, or null for plain POM).
inline Image<std::uint8_t> renderParallax(const ReliefMap& relief, const Image<float>* indirection,
                                          const TextureFunction& texture,
                                          const ParallaxView& view = {}) {
  Image<std::uint8_t> out(view.width, view.height, 3);
  const Vec3f forward = glm::normalize(view.target - view.eye);
  const Vec3f right = glm::normalize(glm::cross(forward, Vec3f(0, 0, 1)));
  const Vec3f up = glm::cross(right, forward);
  const float tanHalf = std::tan(glm::radians(view.fovY) * 0.5f);
  const float aspect = float(view.width) / float(view.height);
  const float top = relief.heightScale();
  const Vec3f light = glm::normalize(view.lightDir);
  tbb::parallel_for(tbb::blocked_range<int>(0, view.height), [&](const tbb::blocked_range<int>& r) {
    for (int py = r.begin(); py != r.end(); ++py)
      for (int px = 0; px < view.width; ++px) {
        const float sx = (2 * (px + 0.5f) / float(view.width) - 1) * tanHalf * aspect;
        const float sy = (1 - 2 * (py + 0.5f) / float(view.height)) * tanHalf;
        const Vec3f dir = glm::normalize(forward + sx * right + sy * up);
        Vec3f color = view.background;
        // Clip the ray to the slab [0,1]^2 x [0, top].
        float t0 = 0, t1 = 1e30f;
        const Vec3f lo(0, 0, 0), hi(1, 1, std::max(top, 1e-6f));
        bool hit = true;
        for (int a = 0; a < 3 && hit; ++a) {
          if (std::abs(dir[a]) < 1e-12f) {
            hit = view.eye[a] >= lo[a] && view.eye[a] <= hi[a];
            continue;
          }
          float ta = (lo[a] - view.eye[a]) / dir[a], tb = (hi[a] - view.eye[a]) / dir[a];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          hit = t0 <= t1;
        }
        if (hit) {
          hit = false;
          float prev = t0;
          for (int k = 1; k <= view.linearSteps; ++k) {
            const float t = t0 + (t1 - t0) * float(k) / float(view.linearSteps);
            const Vec3f p = view.eye + t * dir;
            if (p.z <= relief.heightAt(p.x, p.y)) {
              float a = prev, b = t;  // refine the crossing by bisection
              for (int s = 0; s < view.refineSteps; ++s) {
                const float m = 0.5f * (a + b);
                const Vec3f q = view.eye + m * dir;
                (q.z <= relief.heightAt(q.x, q.y) ? b : a) = m;
              }
              const Vec3f q = view.eye + b * dir;
              Vec2f st(q.x, q.y);
              if (indirection) st += sampleIndirection(*indirection, st);
              const Vec2f g = relief.gradientAt(q.x, q.y);
              const Vec3f n = glm::normalize(Vec3f(-g.x, -g.y, 1));
              const float shade = 0.25f + 0.75f * std::max(0.0f, glm::dot(n, light));
              color = texture(st) * shade;
              hit = true;
              break;
            }
            prev = t;
          }
        }
        for (int c = 0; c < 3; ++c)
          out.at(px, py, c) = std::uint8_t(std::clamp(color[c], 0.0f, 1.0f) * 255.0f + 0.5f);
      }
  });
  return out;
}

}  // namespace cellrelief::indirection
