// SPDX-License-Identifier: MIT
/// @file hit.h
/// The hit record, shaped like Embree's RTCHit (t, geometric normal, u/v, ids) so that results of
/// our traversal and of Embree verification rays compare field by field.
#pragma once

#include <cstdint>
#include <limits>
#include <type_traits>

#include "cellrelief/core/math.h"

namespace cellrelief {

inline constexpr std::uint32_t kInvalidId = std::numeric_limits<std::uint32_t>::max();

template <Real T>
struct Hit {
  T t = std::numeric_limits<T>::infinity();  ///< ray parameter; infinity when there is no hit
  Vec3<T> geometricNormal{0};                ///< unnormalized, like Embree's Ng
  T u = 0;                                   ///< barycentric (triangles) or face coordinate
  T v = 0;
  std::uint32_t primId = kInvalidId;  ///< triangle, or domain face, that was hit
  std::uint32_t geomId = kInvalidId;  ///< mesh or model within a scene
  std::uint32_t instId = kInvalidId;  ///< instance, when instancing is used

  bool valid() const { return geomId != kInvalidId; }
};

using Hitf = Hit<float>;
using Hitd = Hit<double>;

/// How far outside a triangle, in barycentric coordinates, a hit still counts. Möller-Trumbore
/// rounds the barycentrics of a point on an edge differently in the two triangles that share it,
/// so a ray through the edge (a projection line aimed at a cube's edge, say) can miss both; the
/// slack makes such rays hit one of them. It is far above the rounding of any triangle that is
/// not degenerate and far below anything a sample could resolve.
template <Real T>
inline constexpr T kBarycentricSlack = std::is_same_v<T, float> ? T(1e-5) : T(1e-9);

/// Möller-Trumbore ray/triangle test, for references and small analytic checks (the relief
/// traversal never intersects triangles). Updates `hit` and returns true when a nearer hit is found.
/// Watertight up to kBarycentricSlack: a ray through a shared edge or vertex hits a triangle.
template <Real T>
bool intersectTriangle(const Vec3<T>& origin, const Vec3<T>& direction, T tmin, const Vec3<T>& p0,
                       const Vec3<T>& p1, const Vec3<T>& p2, std::uint32_t primId,
                       std::uint32_t geomId, Hit<T>& hit) {
  const Vec3<T> e1 = p1 - p0;
  const Vec3<T> e2 = p2 - p0;
  const Vec3<T> pv = glm::cross(direction, e2);
  const T det = glm::dot(e1, pv);
  if (det == T(0)) return false;
  const T invDet = T(1) / det;
  const Vec3<T> tv = origin - p0;
  const T u = glm::dot(tv, pv) * invDet;
  constexpr T slack = kBarycentricSlack<T>;
  if (u < -slack || u > T(1) + slack) return false;
  const Vec3<T> qv = glm::cross(tv, e1);
  const T v = glm::dot(direction, qv) * invDet;
  if (v < -slack || u + v > T(1) + slack) return false;
  const T t = glm::dot(e2, qv) * invDet;
  if (t < tmin || t >= hit.t) return false;
  hit.t = t;
  hit.u = u;
  hit.v = v;
  hit.geometricNormal = glm::cross(e1, e2);
  hit.primId = primId;
  hit.geomId = geomId;
  return true;
}

}  // namespace cellrelief
