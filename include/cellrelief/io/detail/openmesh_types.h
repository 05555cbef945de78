// SPDX-License-Identifier: MIT
/// @file openmesh_types.h
/// The OpenMesh handle and vector types the importer and exporter both speak.
#pragma once

#include <OpenMesh/Core/Geometry/VectorT.hh>
#include <OpenMesh/Core/Mesh/Attributes.hh>
#include <OpenMesh/Core/Mesh/Handles.hh>

namespace cellrelief::io::detail {
/// Inherited (privately) by the importer and exporter, which override OpenMesh's virtuals.
struct OpenMeshTypes {
  using VertexHandle = OpenMesh::VertexHandle;
  using FaceHandle = OpenMesh::FaceHandle;
  using HalfedgeHandle = OpenMesh::HalfedgeHandle;
  using EdgeHandle = OpenMesh::EdgeHandle;
  using Vec2f = OpenMesh::Vec2f;
  using Vec3f = OpenMesh::Vec3f;
  using Vec3d = OpenMesh::Vec3d;
  using Vec4f = OpenMesh::Vec4f;
  using Vec3uc = OpenMesh::Vec3uc;
  using Vec4uc = OpenMesh::Vec4uc;
  using Vec3ui = OpenMesh::Vec3ui;
  using Vec4ui = OpenMesh::Vec4ui;
  using Status = OpenMesh::Attributes::StatusInfo;
};
}  // namespace cellrelief::io::detail
