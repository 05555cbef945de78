// SPDX-License-Identifier: MIT
/// @file distortion.h
/// How far a map from a triangle mesh to its texture positions is from an isometry, as the
/// PolyCube-Maps paper's Table 1 reports it. Per triangle, the map is the affine one from the mesh
/// triangle to its texture triangle (both in 3D), with singular values s1 >= s2, after scaling
/// the texture so that its total area equals the mesh's (distortion does not depend on scale):
/// - area distortion: the area-weighted mean of (s1 s2 + 1/(s1 s2)) / 2, 1 when areas are kept;
/// - angle distortion: the area-weighted mean of (s1/s2 + s2/s1) / 2, 1 when angles are kept;
/// - stretch efficiency (Praun & Hoppe 2003): 1 / L2^2, where L2 is Sander et al.'s stretch of
///   the inverse map (texture to mesh), the root mean square over the mesh's area of
///   sqrt((1/s1^2 + 1/s2^2) / 2); 1 for an isometry, below 1 where the texture undersamples, and
///   the fraction of its texels a signal sampled uniformly on the mesh makes use of;
/// - flipped: triangles whose texture triangle faces into the polycube (or has no area); they are
///   left out of the three means.
/// Texture triangles are flat: a triangle that straddles a polycube edge cuts its corner, which
/// is small for triangles small against a cube (the paper measures the same way).
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief::polycube {

struct Distortion {
  double area = 1, angle = 1, stretchEfficiency = 1;
  std::size_t flipped = 0;
};

/// A mesh triangle as the distortion reads it: its area and the inverse of its edge matrix in a
/// 2D frame of its own plane. Degenerate triangles get zero area and are skipped.
struct TriangleFrame {
  double area = 0;
  double inverse[2][2] = {{0, 0}, {0, 0}};

  TriangleFrame() = default;
  TriangleFrame(const Vec3d& x0, const Vec3d& x1, const Vec3d& x2) {
    const Vec3d e1 = x1 - x0, e2 = x2 - x0;
    const double length1 = glm::length(e1);
    const double twiceArea = glm::length(glm::cross(e1, e2));
    if (!(length1 > 0) || !(twiceArea > 1e-14 * length1 * length1) || !std::isfinite(twiceArea)) return;
    // Edge matrix [p1 p2] with p1 = (|e1|, 0), p2 = (e2.b1, e2.b2): upper triangular.
    const double p2x = glm::dot(e2, e1) / length1, p2y = twiceArea / length1;
    area = 0.5 * twiceArea;
    inverse[0][0] = 1 / length1;
    inverse[0][1] = -p2x / (length1 * p2y);
    inverse[1][0] = 0;
    inverse[1][1] = 1 / p2y;
  }
  bool degenerate() const { return area == 0; }
};

/// The two numbers every measure needs from one triangle's map: s1^2 + s2^2 (the squared
/// Frobenius norm of its Jacobian) and the texture triangle's area, signed by whether it faces
/// `outward` (the sum of the surface normals at its corners).
struct TriangleStretch {
  double frobenius2 = 0;
  double signedArea = 0;
};

/// One triangle's affine map from the mesh to the texture: the columns of its Jacobian J (3 x 2,
/// on the frame's 2D coordinates) and the texture triangle's unnormalized normal f1 x f2.
struct TriangleJacobian {
  Vec3d column0{0.0}, column1{0.0}, cross{0.0};

  TriangleJacobian(const TriangleFrame& frame, const Vec3d& u0, const Vec3d& u1, const Vec3d& u2) {
    const Vec3d f1 = u1 - u0, f2 = u2 - u0;
    column0 = f1 * frame.inverse[0][0] + f2 * frame.inverse[1][0];
    column1 = f1 * frame.inverse[0][1] + f2 * frame.inverse[1][1];
    cross = glm::cross(f1, f2);
  }
  double frobenius2() const { return glm::dot(column0, column0) + glm::dot(column1, column1); }
  /// The texture triangle's area, negative when it does not face `outward`.
  double signedArea(const Vec3d& outward) const {
    const double area = 0.5 * glm::length(cross);
    return glm::dot(cross, outward) > 0 ? area : -area;
  }
};

inline TriangleStretch triangleStretch(const TriangleFrame& frame, const Vec3d& u0, const Vec3d& u1, const Vec3d& u2,
                                       const Vec3d& outward) {
  const TriangleJacobian j(frame, u0, u1, u2);
  return {j.frobenius2(), j.signedArea(outward)};
}

/// A texture triangle counts as flat, with the flipped ones, when its area is below this
/// fraction of its share (its mesh area times the map's texture area per mesh area): its area
/// distortion would exceed 1/2 x 10^10, and its vertices are one point or one line in doubles.
inline constexpr double kFlatShare = 1e-10;

/// Whether a triangle of mesh area `meshArea` is flipped or flat at `scale2` texture area per
/// unit of mesh area.
inline bool flippedOrFlat(double signedArea, double meshArea, double scale2) {
  return !(signedArea > kFlatShare * meshArea * scale2);
}

/// The measures over a whole map; `outward(i)` gives triangle i's outward direction.
template <class Outward>
Distortion measureDistortion(std::span<const TriangleFrame> frames, std::span<const Vec3u> triangles,
                             std::span<const Vec3d> texture, Outward&& outward) {
  if (frames.size() != triangles.size())
    throw Error(ErrorKind::InvalidArgument, "distortion: one frame per triangle is needed");
  std::vector<TriangleStretch> stretch(triangles.size());
  double meshArea = 0, textureArea = 0;
  Distortion d;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (frames[i].degenerate()) continue;
    const Vec3u& t = triangles[i];
    stretch[i] = triangleStretch(frames[i], texture[t[0]], texture[t[1]], texture[t[2]], outward(i));
    if (!(stretch[i].signedArea > 0)) continue;
    meshArea += frames[i].area;
    textureArea += stretch[i].signedArea;
  }
  if (!(meshArea > 0)) {
    for (std::size_t i = 0; i < triangles.size(); ++i) d.flipped += frames[i].degenerate() ? 0 : 1;
    d.area = d.angle = d.stretchEfficiency = 0;
    return d;
  }
  const double scale2 = textureArea / meshArea;  // texture area per unit of mesh area
  double keptArea = 0;  // of the triangles neither flipped nor flat: the means' weight
  double area = 0, angle = 0, stretch2 = 0;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    if (frames[i].degenerate()) continue;
    if (flippedOrFlat(stretch[i].signedArea, frames[i].area, scale2)) {
      ++d.flipped;
      continue;
    }
    const double m = frames[i].area;
    keptArea += m;
    const double s1s2 = stretch[i].signedArea / (m * scale2);   // after scaling to equal areas
    const double sum2 = stretch[i].frobenius2 / scale2;          // s1^2 + s2^2, scaled likewise
    area += m * 0.5 * (s1s2 + 1 / s1s2);
    angle += m * 0.5 * sum2 / s1s2;
    // The inverse map's singular values are 1/s1, 1/s2: (1/s1^2 + 1/s2^2) / 2 over this area.
    stretch2 += m * 0.5 * sum2 / (s1s2 * s1s2);
  }
  d.area = area / keptArea;
  d.angle = angle / keptArea;
  d.stretchEfficiency = keptArea / stretch2;
  return d;
}

/// The measures of a planar map given per triangle corner (3 per triangle, as a mesh cut into
/// a disk has them): the baselines' maps. Their orientation is the one most of the area has.
inline Distortion measurePlanarDistortion(const TriangleMesh& mesh, std::span<const Vec2d> corners) {
  if (corners.size() != 3 * mesh.triangles.size())
    throw Error(ErrorKind::InvalidArgument, "distortion: three texture corners per triangle are needed");
  std::vector<TriangleFrame> frames;
  std::vector<Vec3u> triangles;
  std::vector<Vec3d> texture;
  frames.reserve(mesh.triangles.size());
  double signedArea = 0;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Vec3u& t = mesh.triangles[f];
    frames.emplace_back(Vec3d(mesh.positions[t[0]]), Vec3d(mesh.positions[t[1]]), Vec3d(mesh.positions[t[2]]));
    triangles.push_back(Vec3u(std::uint32_t(3 * f), std::uint32_t(3 * f + 1), std::uint32_t(3 * f + 2)));
    for (int k = 0; k < 3; ++k) texture.push_back(Vec3d(corners[3 * f + k], 0.0));
    const Vec2d a = corners[3 * f + 1] - corners[3 * f], b = corners[3 * f + 2] - corners[3 * f];
    signedArea += a.x * b.y - a.y * b.x;
  }
  const Vec3d up(0, 0, signedArea < 0 ? -1.0 : 1.0);
  return measureDistortion(frames, triangles, texture, [&](std::size_t) { return up; });
}

}  // namespace cellrelief::polycube
