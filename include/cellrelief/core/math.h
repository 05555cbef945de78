// SPDX-License-Identifier: MIT
/// @file math.h
/// The library's math vocabulary on GLM. GLM is the only math type in public APIs ("Eigen-free
/// GLM"), so users pass their own glm vectors straight in. Geometry is templated on the scalar
/// (float for GPU-shaped data, double for references and verification) through `Real`.
#pragma once

#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace cellrelief {

/// A floating-point scalar the geometry templates accept: float or double (or long double).
template <class T>
concept Real = std::floating_point<T>;

template <Real T> using Vec2 = glm::vec<2, T, glm::defaultp>;
template <Real T> using Vec3 = glm::vec<3, T, glm::defaultp>;
template <Real T> using Vec4 = glm::vec<4, T, glm::defaultp>;

using Vec2f = glm::vec2;
using Vec3f = glm::vec3;
using Vec4f = glm::vec4;
using Vec2d = glm::dvec2;
using Vec3d = glm::dvec3;
using Vec4d = glm::dvec4;
using Vec2i = glm::ivec2;
using Vec3i = glm::ivec3;
using Vec3u = glm::uvec3;
using Color8 = glm::u8vec4;

/// True when every component is finite (no NaN, no infinity).
template <int N, class T, glm::qualifier Q>
inline bool isFinite(const glm::vec<N, T, Q>& v) {
  for (int i = 0; i < N; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

/// Index of the largest component (ties go to the lowest index).
template <class T, glm::qualifier Q>
inline int maxDimension(const glm::vec<3, T, Q>& v) {
  return v.x >= v.y ? (v.x >= v.z ? 0 : 2) : (v.y >= v.z ? 1 : 2);
}

}  // namespace cellrelief
