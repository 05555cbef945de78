// SPDX-License-Identifier: MIT
/// @file octahedral.h
/// Octahedral encoding of unit vectors into [0, 1]^2 (Cigolle et al. 2014): two channels per
/// normal with an error spread evenly over the sphere. In core because every representation that
/// stores normal maps (relief cells, geometry-texture charts) uses the same encoding as the shaders.
#pragma once

#include <algorithm>
#include <cmath>

#include "cellrelief/core/math.h"

namespace cellrelief {

inline Vec2f octahedralEncode(Vec3f n) {
  n /= (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  Vec2f e(n.x, n.y);
  if (n.z < 0) {
    e = (Vec2f(1) - glm::abs(Vec2f(n.y, n.x))) *
        Vec2f(n.x >= 0 ? 1.0f : -1.0f, n.y >= 0 ? 1.0f : -1.0f);
  }
  return e * 0.5f + 0.5f;
}

inline Vec3f octahedralDecode(Vec2f e) {
  e = e * 2.0f - 1.0f;
  Vec3f n(e.x, e.y, 1.0f - std::abs(e.x) - std::abs(e.y));
  const float t = std::max(-n.z, 0.0f);
  n.x += n.x >= 0 ? -t : t;
  n.y += n.y >= 0 ? -t : t;
  return glm::normalize(n);
}

}  // namespace cellrelief
