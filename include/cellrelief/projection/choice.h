// SPDX-License-Identifier: MIT
/// @file choice.h
/// Which projection each base case uses, with which parameters (Apaza & Andujar, 3.2), and the
/// run-time `CellProjection` that dispatches to the four templated projections.
///
/// Canonical parameters (the configuration table in cells/configuration.h gives each case's
/// canonical external faces; the cell is [0,1]^3):
///
/// | case | projection  | parameter (canonical) | domain faces |
/// |---|---|---|---|
/// | 0  | perspective | centre: the cell centre | all six (no face is external) |
/// | 1  | parallel    | the external face's normal (+z) | +z |
/// | 2a | planar      | the plane z = 1/2 | -z, +z |
/// | 2b | axial       | the cell edge x = y = 0 (through its midpoint), along z | +x, +y |
/// | 3a | axial       | the line x = 1/2, y = 0 through two edge midpoints, along z | -x, +x, +y |
/// | 3b | perspective | centre: the vertex (0, 0, 0) shared by the internal faces | +x, +y, +z |
/// | 4a | perspective | centre: the midpoint (0, 0, 1/2) of the edge shared by the internal faces | +x, +y, -z, +z |
/// | 4b | axial       | the line through the midpoints of the internal faces -z, +z | -x, +x, -y, +y |
/// | 5  | perspective | centre: the midpoint of the internal face (1/2, 1/2, 0) | all but -z |
/// | 6  | perspective | centre: the cell centre | all six |
///
/// Each centre or axis lies on the internal faces (or in the cell), never on a domain face, so
/// every projection ray leaves the cell through a domain face. A configuration's parameters are the
/// canonical ones turned by its rotation.
///
/// Beyond the paper: `CentreOfProjection::SurfaceCentroid` moves the centre (or axis) towards the
/// centroid of the surface inside the cell, as the paper suggests, but only along the directions in
/// which it is free (the coordinates where the canonical parameter is 1/2): moving it off the
/// internal faces would let rays reach them. The centroid is clamped to [0.05, 0.95] so the centre
/// never lands on a face.
#pragma once

#include <cstdint>
#include <optional>

#include "cellrelief/cells/configuration.h"
#include "cellrelief/projection/projections.h"

namespace cellrelief::projection {

enum class ProjectionType : std::uint8_t { Parallel, Planar, Perspective, Axial };
inline constexpr const char* kProjectionTypeNames[] = {"parallel", "planar", "perspective", "axial"};
inline const char* toString(ProjectionType t) { return kProjectionTypeNames[static_cast<int>(t)]; }

/// Where a cell's centre (or axis) of projection goes along its free coordinates:
/// - CellCentre: the paper's canonical point;
/// - SurfaceCentroid: the centroid of the surface in the cell (clamped, see below);
/// - FewestCrossings: the point of a lattice from which the fewest projection lines meet the surface
///   more than once (relief/centre_search.h): a line holds one distance, so a second crossing is lost and
///   the side past it misread (a handle through an interior cell reads as filled).
enum class CentreOfProjection : std::uint8_t { CellCentre, SurfaceCentroid, FewestCrossings };
inline constexpr const char* kCentreOfProjectionNames[] = {"cell", "centroid", "fewest-crossings"};
inline const char* toString(CentreOfProjection c) { return kCentreOfProjectionNames[static_cast<int>(c)]; }

/// The canonical projection of a base case: type, the face or axis it uses, and its point.
struct CanonicalProjection {
  ProjectionType type;
  int faceOrAxis;  ///< parallel: the face; planar and axial: the axis; perspective: unused
  Vec3d point;     ///< perspective: the centre; axial: a point of the axis line
};

inline constexpr CanonicalProjection kCanonicalProjections[10] = {
    {ProjectionType::Perspective, -1, {0.5, 0.5, 0.5}},  // 0
    {ProjectionType::Parallel, 5, {0.5, 0.5, 0.5}},      // 1
    {ProjectionType::Planar, 2, {0.5, 0.5, 0.5}},        // 2a
    {ProjectionType::Axial, 2, {0.0, 0.0, 0.5}},         // 2b
    {ProjectionType::Axial, 2, {0.5, 0.0, 0.5}},         // 3a
    {ProjectionType::Perspective, -1, {0.0, 0.0, 0.0}},  // 3b
    {ProjectionType::Perspective, -1, {0.0, 0.0, 0.5}},  // 4a
    {ProjectionType::Axial, 2, {0.5, 0.5, 0.5}},         // 4b
    {ProjectionType::Perspective, -1, {0.5, 0.5, 0.0}},  // 5
    {ProjectionType::Perspective, -1, {0.5, 0.5, 0.5}},  // 6
};

/// The projection of one grey cell, chosen at run time; dispatches to the templated projections.
/// Traversal code that knows the type statically uses those directly.
template <Real T>
struct CellProjection {
  ProjectionType type = ProjectionType::Perspective;
  int faceOrAxis = -1;
  Vec3<T> point{T(0.5)};
  std::uint8_t faces = 0b111111;  ///< domain faces

  std::uint8_t domainFaces() const { return faces; }

  template <class F>
  decltype(auto) visit(F&& f) const {
    switch (type) {
      case ProjectionType::Parallel: return f(ParallelProjection<T>{faceOrAxis});
      case ProjectionType::Planar: return f(PlanarProjection<T>{faceOrAxis});
      case ProjectionType::Axial: return f(AxialProjection<T>{faceOrAxis, point, faces});
      case ProjectionType::Perspective: break;
    }
    return f(PerspectiveProjection<T>{point, faces});
  }
  FacePoint<T> project(const Vec3<T>& p) const {
    return visit([&](const auto& proj) { return proj.project(p); });
  }
  Vec3<T> unproject(int face, const Vec2<T>& uv, T distance) const {
    return visit([&](const auto& proj) { return proj.unproject(face, uv, distance); });
  }
  Vec3<T> lineEnd(int face, const Vec3<T>& onFace) const {
    return visit([&](const auto& proj) { return proj.lineEnd(face, onFace); });
  }
};

/// The projection for a configuration. `centroid` (unit-cell coordinates) is used only with
/// CentreOfProjection::SurfaceCentroid and FewestCrossings (the candidate point).
template <Real T>
CellProjection<T> chooseProjection(std::uint8_t configuration,
                                   CentreOfProjection centre = CentreOfProjection::CellCentre,
                                   std::optional<Vec3<T>> centroid = std::nullopt) {
  const cells::ConfigurationInfo info = cells::kConfigurationTable[configuration & 63];
  const CanonicalProjection& canon = kCanonicalProjections[static_cast<int>(info.baseCase)];
  const cells::CubeRotation& rot = cells::kRotations[info.rotation];
  CellProjection<T> out;
  out.type = canon.type;
  out.faces = cells::domainFacesOf(configuration & 63);
  Vec3<T> canonicalPoint = Vec3<T>(canon.point);
  if (centre != CentreOfProjection::CellCentre && centroid &&
      (canon.type == ProjectionType::Perspective || canon.type == ProjectionType::Axial)) {
    // Move along the free canonical coordinates only (those at 1/2), in the canonical frame; an
    // axis moved along itself is the same line, so its own coordinate stays.
    const Vec3<T> c = rot.inverse().applyToPoint(glm::clamp(*centroid, T(0.05), T(0.95)));
    for (int a = 0; a < 3; ++a)
      if (canon.point[a] == 0.5 && !(canon.type == ProjectionType::Axial && a == canon.faceOrAxis))
        canonicalPoint[a] = c[a];
  }
  out.point = rot.applyToPoint(canonicalPoint);
  switch (canon.type) {
    case ProjectionType::Parallel: out.faceOrAxis = rot.applyToFace(canon.faceOrAxis); break;
    case ProjectionType::Planar:
    case ProjectionType::Axial:
      out.faceOrAxis = faceAxis(rot.applyToFace(cells::makeFace(canon.faceOrAxis, 1)));
      break;
    case ProjectionType::Perspective: break;
  }
  return out;
}

}  // namespace cellrelief::projection
