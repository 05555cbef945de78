// SPDX-License-Identifier: MIT
/// @file projection.h
/// The projection P of PolyCube-Maps: a point of a dual cell (the 3D texture position of a
/// fragment, near the polycube's surface) onto the surface inside that cell.
///
/// Coordinates are the cell's own, relative to its vertex: the cell is [-1/2, 1/2]^3 and the
/// squarelets lie in the coordinate planes. P is written once per basic case, in the case's
/// canonical frame; `project` moves a point into that frame (the inverse of the vertex's
/// transform), projects it, and moves the result back.
///
/// Why these projections: P must be continuous across cell faces, and the two cells that share a
/// face know only their own configurations. So on every cell face the surface crosses, P keeps
/// the point in the face and depends only on the face's own 2D configuration (the four cubes the
/// face cuts):
/// - a straight line through the face: orthogonal projection onto it;
/// - a corner (one quadrant of the face solid, or three): central projection from the face's
///   corner in the odd quadrant. The L is star-shaped from there, and the face's edges through
///   that corner are projection lines, as the straight-line rule of the next face needs.
/// Each case's P below restricts to these rules on its faces (tested for every configuration).
/// P is continuous wherever it is meant to be used, within half a cube of the surface: its
/// centres and axes lie at least that far away.
///
/// - 4a (flat, solid z < 0): orthogonal projection onto z = 0.
/// - 4b (edge, solid y < 0 and z < 0): axial projection from the cell edge y = z = -1/2.
/// - 3 (corner, solid octant 0): central projection from the cell corner (-1/2, -1/2, -1/2).
///   All three are central projections from the point c with c_a = -1/2 on the case's active axes
///   and c_a = p_a on the others, onto the boundary of the box [-1/2, 0] on the active axes.
/// - 5 (an L of three cubes, solid z < 0 except x > 0 and y > 0): designed here, the paper gives
///   no formula. The axis is the vertical cell edge x = y = 1/2 inside the notch. A vertical
///   half-plane from that axis cuts the surface in a 2D corner (the top z = 0 beyond the notch,
///   the notch's wall below), and P is that corner's rule in each half-plane, from the point where
///   the half-plane meets the cell's bottom edge. With r = max(1/2 - x, 1/2 - y) the half-plane
///   coordinate (the notch's wall at r = 1/2, the cell's far faces at r = 1), this is the 2D
///   central projection in (2r - 1, z) from (1, -1/2). It reduces to the corner rule on the faces
///   x = 1/2, y = 1/2 (half-planes themselves) and z = -1/2, and to orthogonal projection on the
///   faces x = -1/2, y = -1/2 (the half-planes' far edges).
/// - 6a (a tetrapod of cubes: octant 0 and its three neighbours 1, 2, 4), designed here, the
///   paper leaves it out. Each arm cube (say octant 1, along +x) gets a fan like P5's about its
///   far edge (y = z = -1/2, a cell edge the surface does not cross): in every half-plane from
///   that edge the surface is a concave corner (the arm's wall, then the plane x = 0), and P is
///   its central projection from where the half-plane meets the cell face x = 1/2. The core cube
///   (octant 0) takes the fan of its largest coordinate's arm (the fans agree where two are
///   largest: both reach the axis between them). The other four octants are the image of these
///   under p -> -p, which maps 6a's solid onto its empty part: P(p) = -P(-p) there. Tested like
///   the others: faces' own rules, onto the surface, identity on it, the same Lipschitz bound.
/// - 6b (a skew path of cubes: octants 0, 1, 3, 7), designed here, the paper leaves it out. The
///   solid is the union of {y < 0, z < 0} and {y > 0, x > 0}, and the surface a saddle of two
///   convex and two concave edges. No fan about one axis fits its faces; what they share is this:
///   on every face each projection line joins a point of the solid spine (the three cell edges
///   inside the solid, a path from (-1/2, -1/2, -1/2) along x, then y, then z to (1/2, 1/2,
///   1/2), parameter s in [0, 3]) to one of the empty spine. So a solid point moves along the ray
///   away from a spine point c(s(p)) until it meets the surface. On the three faces through the
///   path's start the line's s is one formula (sL, the face z = -1/2's central projection swept
///   along z), on the three through its end another (sR, the face x = 1/2's swept along x): the
///   end cubes (octants 0 and 7) take sL and sR, the middle two (octants 1 and 3) blend them by
///   their squared distances to the two groups of faces (the two agree where those faces meet
///   within reach). The rotation (x, y, z) -> (z, -y, x) maps the solid onto the empty part, so
///   there P(p) = R P(R p). P lands on the surface, is each face's own rule and is continuous
///   within reach; it stretches more than the other cases (a Lipschitz bound of about 50 against
///   13): near the middle cubes' diagonal (t, 0, -t) points meet the surface near the vertex at a
///   grazing angle, and near the spine edge x = 1/2, z = -1/2 the two faces' lines part fast.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "cellrelief/core/error.h"
#include "cellrelief/polycube/vertex_configuration.h"

namespace cellrelief::polycube {

namespace detail {

/// Central projection from c (c_a = -1/2 on the active axes, p_a elsewhere) onto the boundary of
/// the solid box [-1/2, 0] on the active axes: cases 3, 4a and 4b.
inline Vec3d projectFromBoxCorner(const Vec3d& p, const bool active[3]) {
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    if (active[a] && p[a] > -0.5) t = std::min(t, 0.5 / (p[a] + 0.5));
  if (!std::isfinite(t)) return p;  // the centre itself: half a cube from the surface
  Vec3d q = p;
  for (int a = 0; a < 3; ++a)
    if (active[a]) q[a] = -0.5 + t * (p[a] + 0.5);
  return q;
}

/// Case 5 in its canonical frame (solid octants 0, 1, 2).
inline Vec3d projectCase5(const Vec3d& p) {
  const Vec2d w(p.x - 0.5, p.y - 0.5);  // from the axis x = y = 1/2
  const double r = std::max(-w.x, -w.y);
  if (r <= 0) return {0.5, 0.5, 0.0};  // on the axis: half a cube from the surface
  const double sigma = 2 * r - 1, z = p.z;
  if (sigma >= 1 && z <= -0.5) return p;  // the half-plane's centre: half a cube from the surface
  double sigmaImage, zImage;
  if (sigma >= -2 * z) {  // the ray from (1, -1/2) reaches the top first
    const double t = 0.5 / (z + 0.5);
    sigmaImage = 1 + t * (sigma - 1);
    zImage = 0;
  } else {  // the notch's wall
    const double t = 1 / (1 - sigma);
    sigmaImage = 0;
    zImage = -0.5 + t * (z + 0.5);
  }
  const double rImage = 0.5 * (sigmaImage + 1);
  return {0.5 + w.x * (rImage / r), 0.5 + w.y * (rImage / r), zImage};
}

/// Case 6a's fan for the arm along `axis`: in the half-plane from the arm's far edge (the other
/// coordinates at -1/2), with s = 2 max(p_b, p_c) + 1 - 1 from that edge (0 at the arm's walls)
/// and h = p_axis, the central projection from (1, 1/2) onto the concave corner
/// {s = 0, h >= 0} u {h = 0, s >= 0}.
inline Vec3d projectArmFan(int axis, const Vec3d& p) {
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  const double r = std::max(p[b] + 0.5, p[c] + 0.5);
  const double sigma = 2 * r - 1, h = p[axis];
  if (r <= 0 || sigma >= 1) return p;  // on the edge or the far corner line: half a cube away
  const double tWall = 1 / (1 - sigma);  // the ray from (1, 1/2) reaches s = 0
  const double hWall = 0.5 + tWall * (h - 0.5);
  double sigmaImage = 0, hImage = hWall;
  if (hWall < 0) {  // it reaches h = 0 first
    sigmaImage = 1 + (0.5 / (0.5 - h)) * (sigma - 1);
    hImage = 0;
  }
  const double scale = 0.5 * (sigmaImage + 1) / r;
  Vec3d q;
  q[axis] = hImage;
  q[b] = -0.5 + (p[b] + 0.5) * scale;
  q[c] = -0.5 + (p[c] + 0.5) * scale;
  return q;
}

/// Case 6a in its canonical frame (solid octants 0, 1, 2, 4).
inline Vec3d projectCase6a(const Vec3d& p) {
  const auto largest = [](const Vec3d& v) { return v.x >= v.y && v.x >= v.z ? 0 : v.y >= v.z ? 1 : 2; };
  const int positive = (p.x > 0) + (p.y > 0) + (p.z > 0);
  if (positive <= 1) return projectArmFan(largest(p), p);
  return -projectArmFan(largest(-p), -p);
}

/// Case 6b's solid spine: the cell edges inside the solid that the surface does not cross, from
/// (-1/2, -1/2, -1/2) along x, then y, then z to (1/2, 1/2, 1/2), at s in [0, 3].
inline Vec3d case6bSpinePoint(double s) {
  s = std::clamp(s, 0.0, 3.0);
  if (s <= 1) return {s - 0.5, -0.5, -0.5};
  if (s <= 2) return {0.5, s - 1.5, -0.5};
  return {0.5, 0.5, s - 2.5};
}

/// The spine parameter of p's projection line (solid octants only). sL is exact on the faces
/// x, y, z = -1/2: the face z = -1/2's line from its empty corner (-1/2, 1/2) through (x, y) meets
/// the spine there, and on the other two faces the same formula gives their lines. sR is its
/// image under the symmetry (x, y, z) -> (-z, -y, -x), exact on the faces at +1/2.
inline double case6bSpineParameter(const Vec3d& p) {
  const double sL = p.x + p.y <= 0 ? (p.x + 0.5) / (0.5 - p.y) : 2 - (0.5 - p.y) / (p.x + 0.5);
  const double sR = p.y + p.z <= 0 ? 1 + (p.y + 0.5) / (0.5 - p.z) : 3 - (0.5 - p.z) / (p.y + 0.5);
  if (p.x <= 0) return sL;  // octant 0
  if (p.z >= 0) return sR;  // octant 7
  // Octants 1 and 3: distances to the faces where sL holds (x = 0 below y = 0, y = -1/2,
  // z = -1/2) and to those where sR holds (x = 1/2, y = 1/2, z = 0 above y = 0). Squared, the
  // weight stays near the nearer group's formula, which matters near the spine where a small
  // change of the spine point turns the long ray a lot.
  const double a = std::min({std::hypot(p.x, std::max(p.y, 0.0)), p.y + 0.5, p.z + 0.5});
  const double b = std::min({0.5 - p.x, 0.5 - p.y, std::hypot(p.z, std::min(p.y, 0.0))});
  if (a + b <= 0) return 1.5;
  const double w = a * a / (a * a + b * b);
  return (1 - w) * sL + w * sR;
}

/// The first point of case 6b's surface on the ray p + t d, t >= 0; the surface's nearest point
/// if the ray leaves the cell first (not within reach of the surface).
inline Vec3d case6bFirstSurfaceHit(const Vec3d& p, const Vec3d& d) {
  const std::uint16_t squarelets = kVertexConfigurations[kCanonicalOctants[static_cast<int>(VertexCase::k6b)]].squarelets;
  constexpr double kSlack = 1e-12;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 12; ++i) {
    if (!(squarelets & (1u << i))) continue;
    const SquareletBounds box = squareletBounds(i);
    if (glm::clamp(p, box.min, box.max) == p) return p;  // on the surface: P is the identity
    if (d[box.axis] == 0) continue;
    const double t = -p[box.axis] / d[box.axis];
    if (t < 0 || t >= best) continue;
    const Vec3d x = p + t * d;
    bool inside = true;
    for (int k = 0; k < 3; ++k)
      if (k != box.axis && (x[k] < box.min[k] - kSlack || x[k] > box.max[k] + kSlack)) inside = false;
    if (inside) best = t;
  }
  if (std::isfinite(best)) return glm::clamp(p + best * d, Vec3d(-0.5), Vec3d(0.5));
  Vec3d nearest = p;  // a miss, beyond reach: the surface's nearest point
  double nearestDistance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 12; ++i) {
    if (!(squarelets & (1u << i))) continue;
    const SquareletBounds box = squareletBounds(i);
    const Vec3d clamped = glm::clamp(p, box.min, box.max);
    const double distance = glm::length(p - clamped);
    if (distance < nearestDistance) nearestDistance = distance, nearest = clamped;
  }
  return nearest;
}

/// Case 6b in its canonical frame (solid octants 0, 1, 3, 7).
inline Vec3d projectCase6b(const Vec3d& p) {
  const auto inSolid = [](const Vec3d& q) {
    const int octant = (q.x > 0 ? 1 : 0) | (q.y > 0 ? 2 : 0) | (q.z > 0 ? 4 : 0);
    return ((kCanonicalOctants[static_cast<int>(VertexCase::k6b)] >> octant) & 1) != 0;
  };
  const auto projectSolid = [](const Vec3d& q) {
    return case6bFirstSurfaceHit(q, q - case6bSpinePoint(case6bSpineParameter(q)));
  };
  const auto rotate = [](const Vec3d& q) { return Vec3d(q.z, -q.y, q.x); };  // solid <-> empty, R = R^-1
  return inSolid(p) ? projectSolid(p) : rotate(projectSolid(rotate(p)));
}

}  // namespace detail

/// P of one case, in the case's canonical frame.
inline Vec3d projectCanonical(VertexCase c, const Vec3d& p) {
  static constexpr bool kActive[3][3] = {{true, true, true}, {false, false, true}, {false, true, true}};
  switch (c) {
    case VertexCase::k3: return detail::projectFromBoxCorner(p, kActive[0]);
    case VertexCase::k4a: return detail::projectFromBoxCorner(p, kActive[1]);
    case VertexCase::k4b: return detail::projectFromBoxCorner(p, kActive[2]);
    case VertexCase::k5: return detail::projectCase5(p);
    case VertexCase::k6a: return detail::projectCase6a(p);
    case VertexCase::k6b: return detail::projectCase6b(p);
  }
  throw Error(ErrorKind::InvalidArgument, "polycube projection: no case " + std::to_string(int(c)));
}

/// P for a vertex of this configuration: `d` and the result relative to the vertex, in cubes.
inline Vec3d project(std::uint8_t configuration, const Vec3d& d) {
  const VertexConfigurationInfo& info = kVertexConfigurations[configuration];
  if (!info.surface || !info.manifold)
    throw Error(ErrorKind::InvalidArgument, "polycube projection: configuration " + std::to_string(configuration) +
                                                " has no manifold surface");
  return applyTransform(info.transform, projectCanonical(info.vertexCase, applyInverseTransform(info.transform, d)));
}

}  // namespace cellrelief::polycube
