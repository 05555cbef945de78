// SPDX-License-Identifier: MIT
/// @file projections.h
/// The four projections of a grey cell's surface onto its domain faces (Apaza & Andujar, 3.2), as
/// templated value types in float or double. All work in the unit cell [0,1]^3 (scale distances by
/// the cell size for world units).
///
/// `project(p)` gives the domain face a point projects onto, the face coordinates (u, v) of the
/// projected point P', and the distance |P - P'|; `unproject(face, uv, distance)` inverts it. Face
/// coordinates are world-aligned (x faces: (y, z); y faces: (z, x); z faces: (x, y)) so that two
/// cells sharing a face address it alike.
///
/// | projection  | parameter | P' |
/// |---|---|---|
/// | parallel    | a face f  | p moved along f's normal onto f |
/// | planar      | an axis a | p moved along a onto the nearer of the two a-faces (split by the plane through the centre) |
/// | perspective | a centre c | where the ray from c through p leaves the cell |
/// | axial       | an axis line L | where the ray from L through p, perpendicular to L, leaves the cell |
///
/// Degenerate loci and their documented behaviour:
/// - planar: a point on the mid-plane goes to the + face;
/// - perspective: the centre itself goes to the centre of the first domain face;
/// - axial: a point on the axis goes straight (along that face's normal) to the first domain face;
/// - a ray leaving through an edge or corner goes to the lowest-numbered face among those it
///   touches (all of which are domain faces, since projection rays never reach internal faces).
/// In every case unproject(project(p)) == p, up to rounding.
#pragma once

#include <concepts>
#include <cstdint>
#include <limits>

#include "cellrelief/cells/configuration.h"
#include "cellrelief/core/math.h"

namespace cellrelief::projection {

using cells::faceAxis;
using cells::faceSign;
using cells::kFaceCount;

template <Real T>
struct FacePoint {
  int face = -1;
  Vec2<T> uv{0};
  T distance = 0;
};

/// Axes of a face's (u, v): the next two axes after the face's own, cyclically.
constexpr int faceUAxis(int face) { return (faceAxis(face) + 1) % 3; }
constexpr int faceVAxis(int face) { return (faceAxis(face) + 2) % 3; }

template <Real T>
Vec2<T> faceUV(int face, const Vec3<T>& p) {
  const T c[3] = {p.x, p.y, p.z};  // indexed as an array: see facePoint
  return {c[faceUAxis(face)], c[faceVAxis(face)]};
}

/// The point of the unit cell's face with coordinates uv.
template <Real T>
Vec3<T> facePoint(int face, const Vec2<T>& uv) {
  // An array, not glm's operator[] (a switch per runtime index): the tracers call this per step
  // (1.3x the CPU tracer's primary rays through Igea's one perspective cell).
  T p[3];
  p[faceAxis(face)] = faceSign(face) > 0 ? T(1) : T(0);
  p[faceUAxis(face)] = uv.x;
  p[faceVAxis(face)] = uv.y;
  return Vec3<T>(p[0], p[1], p[2]);
}

template <Real T>
Vec3<T> faceNormalT(int face) {
  return Vec3<T>(cells::faceNormal(face));
}

template <Real T>
Vec3<T> faceCentre(int face) {
  return facePoint<T>(face, Vec2<T>(T(0.5)));
}

inline int firstFace(std::uint8_t mask) {
  for (int f = 0; f < kFaceCount; ++f)
    if (mask & (1u << f)) return f;
  return -1;
}

/// A projection of the unit cell onto a set of domain faces. Requirements: `Scalar` is float or
/// double; project() of any point of the closed unit cell gives a face in domainFaces(), (u, v) in
/// [0, 1]^2 and a distance >= 0; unproject() inverts project().
template <class P>
concept ProjectionPolicy = Real<typename P::Scalar> &&
    requires(const P& p, Vec3<typename P::Scalar> x, int f, Vec2<typename P::Scalar> uv,
             typename P::Scalar d) {
  { p.project(x) } -> std::same_as<FacePoint<typename P::Scalar>>;
  { p.unproject(f, uv, d) } -> std::same_as<Vec3<typename P::Scalar>>;
  { p.lineEnd(f, x) } -> std::same_as<Vec3<typename P::Scalar>>;
  { p.domainFaces() } -> std::convertible_to<std::uint8_t>;
};

namespace detail {
/// Where the ray o + t w (t >= 1 inside the cell) leaves [0,1]^3, skipping axes in `skipAxis`
/// and axes where w is zero. Ties go to the lowest axis.
template <Real T>
FacePoint<T> exitPoint(const Vec3<T>& origin, const Vec3<T>& w, const Vec3<T>& p, int skipAxis) {
  T best = std::numeric_limits<T>::infinity();
  int face = -1;
  for (int a = 0; a < 3; ++a) {
    if (a == skipAxis || w[a] == T(0)) continue;
    const T bound = w[a] > 0 ? T(1) : T(0);
    const T t = (bound - origin[a]) / w[a];
    if (t < best) {
      best = t;
      face = cells::makeFace(a, w[a] > 0 ? 1 : -1);
    }
  }
  Vec3<T> hit = origin + best * w;
  hit[faceAxis(face)] = faceSign(face) > 0 ? T(1) : T(0);  // exactly on the face
  for (int a = 0; a < 3; ++a) hit[a] = glm::clamp(hit[a], T(0), T(1));
  return {face, faceUV(face, hit), glm::length(hit - p)};
}
}  // namespace detail

/// Along the normal of one face.
template <Real T>
struct ParallelProjection {
  using Scalar = T;
  int face = 5;

  std::uint8_t domainFaces() const { return std::uint8_t(1u << face); }
  FacePoint<T> project(const Vec3<T>& p) const {
    const T target = faceSign(face) > 0 ? T(1) : T(0);
    return {face, faceUV(face, p), glm::abs(target - p[faceAxis(face)])};
  }
  Vec3<T> unproject(int f, const Vec2<T>& uv, T distance) const {
    return facePoint(f, uv) - distance * faceNormalT<T>(f);
  }
  /// The opposite face.
  Vec3<T> lineEnd(int f, const Vec3<T>& onFace) const { return onFace - faceNormalT<T>(f); }
};

/// Along an axis onto the nearer of its two faces: the plane through the centre splits the cell.
template <Real T>
struct PlanarProjection {
  using Scalar = T;
  int axis = 2;

  std::uint8_t domainFaces() const { return std::uint8_t(3u << (2 * axis)); }
  FacePoint<T> project(const Vec3<T>& p) const {
    const bool upper = p[axis] >= T(0.5);
    const int face = cells::makeFace(axis, upper ? 1 : -1);
    return {face, faceUV(face, p), upper ? T(1) - p[axis] : p[axis]};
  }
  Vec3<T> unproject(int f, const Vec2<T>& uv, T distance) const {
    return facePoint(f, uv) - distance * faceNormalT<T>(f);
  }
  /// The plane through the centre.
  Vec3<T> lineEnd(int f, const Vec3<T>& onFace) const { return onFace - T(0.5) * faceNormalT<T>(f); }
};

/// From a centre of projection through the point onto the face where the ray leaves the cell.
template <Real T>
struct PerspectiveProjection {
  using Scalar = T;
  Vec3<T> centre{T(0.5)};
  std::uint8_t faces = 0b111111;

  std::uint8_t domainFaces() const { return faces; }
  FacePoint<T> project(const Vec3<T>& p) const {
    const Vec3<T> w = p - centre;
    if (w == Vec3<T>(0)) {  // the centre itself
      const int f = firstFace(faces);
      return {f, faceUV(f, faceCentre<T>(f)), glm::length(faceCentre<T>(f) - p)};
    }
    return detail::exitPoint(centre, w, p, -1);
  }
  Vec3<T> unproject(int f, const Vec2<T>& uv, T distance) const {
    const Vec3<T> onFace = facePoint(f, uv);
    return onFace + distance * glm::normalize(centre - onFace);
  }
  /// The centre.
  Vec3<T> lineEnd(int, const Vec3<T>&) const { return centre; }
};

/// From an axis line, perpendicular to it, onto the face where the ray leaves the cell. Straight
/// segments map to curves (the paper's cases 2b, 3a, 4b).
template <Real T>
struct AxialProjection {
  using Scalar = T;
  int axis = 2;             ///< direction of the axis line
  Vec3<T> point{T(0.5)};    ///< a point of the axis line (its `axis` coordinate is irrelevant)
  std::uint8_t faces = 0b001111;

  std::uint8_t domainFaces() const { return faces; }
  Vec3<T> foot(const Vec3<T>& p) const {  // the nearest point of the axis line
    Vec3<T> q = point;
    q[axis] = p[axis];
    return q;
  }
  FacePoint<T> project(const Vec3<T>& p) const {
    const Vec3<T> q = foot(p);
    const Vec3<T> w = p - q;
    if (w == Vec3<T>(0)) {  // on the axis
      const int f = firstFace(faces);
      Vec3<T> onFace = p;
      onFace[faceAxis(f)] = faceSign(f) > 0 ? T(1) : T(0);
      return {f, faceUV(f, onFace), glm::length(onFace - p)};
    }
    return detail::exitPoint(q, w, p, axis);
  }
  Vec3<T> unproject(int f, const Vec2<T>& uv, T distance) const {
    const Vec3<T> onFace = facePoint(f, uv);
    return onFace + distance * glm::normalize(foot(onFace) - onFace);
  }
  /// The foot of the perpendicular on the axis line.
  Vec3<T> lineEnd(int, const Vec3<T>& onFace) const { return foot(onFace); }
};

static_assert(ProjectionPolicy<ParallelProjection<float>>);
static_assert(ProjectionPolicy<PlanarProjection<double>>);
static_assert(ProjectionPolicy<PerspectiveProjection<float>>);
static_assert(ProjectionPolicy<AxialProjection<double>>);

}  // namespace cellrelief::projection
