// SPDX-License-Identifier: MIT
/// @file polycube_tracer.h
/// Ray casting of a polycube-mapped mesh (polycube/textured_mesh.h), the reference the GPU
/// backends' shader is checked against: the core BVH finds the triangle, the hit's 3D texture
/// position is its corners' interpolated at the barycentrics, and P, M and T2's filter give the
/// texel, step by step as a fragment shader does.
///
/// Filtering needs the hit's footprint on the polycube. A ray carries a cone of `spread` world
/// units per unit of distance (one pixel's angle for a primary ray); at the hit that is
/// spread * t / |cos| world units across (the long axis of the ellipse, as a GPU's derivatives
/// measure it, with the cosine floored at kMinFootprintCosine), times the triangle's cubes per
/// world unit (the square root of its texture area over its world area).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "cellrelief/core/bvh.h"
#include "cellrelief/polycube/textured_mesh.h"

namespace cellrelief::trace {

namespace constants {
/// The footprint of a grazing ray grows as 1 / |cos|; this floor keeps it finite (about 78 degrees).
inline constexpr float kMinFootprintCosine = 0.2f;
/// Secondary rays leave a mesh this fraction of its bounding box's diagonal off the surface.
inline constexpr float kMeshSurfaceOffset = 1e-4f;
/// A hit's texture position after P lies in a squarelet's plane within this many cubes.
inline constexpr float kLocateTolerance = 1e-5f;
}  // namespace constants

class PolycubeTracer {
 public:
  struct Hit {
    float t = std::numeric_limits<float>::infinity();
    Vec3f position{0};
    Vec3f normal{0};           ///< unit shading normal: the vertex normals', or T2's
    Vec3f color{200.0f / 255};  ///< the base colour: T2's, or the mesh's neutral grey
    Vec3f texture{0};          ///< the 3D texture position after P (lattice coordinates)
    float lod = 0;             ///< the mip level the footprint selects (not clamped)
    std::uint32_t triangle = kInvalidId;
    bool valid() const { return triangle != kInvalidId; }
  };

  /// Validates the mesh (TexturedMesh::validate) and builds its BVH.
  explicit PolycubeTracer(std::shared_ptr<const polycube::TexturedMesh> mesh) : mMesh(std::move(mesh)) {
    if (!mMesh) throw Error(ErrorKind::InvalidArgument, "polycube tracer: no mesh");
    mMesh->validate();
    const TriangleMesh& m = mMesh->mesh;
    mNormals = m.normals.size() == m.positions.size() ? m.normals : computeVertexNormals(m);
    mBvh = TriangleBvh<float>(m.positions, m.triangles);
    mCubesPerWorld.resize(m.triangles.size());
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      const Vec3u& t = m.triangles[i];
      const float world = glm::length(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
      const float texture = glm::length(glm::cross(mMesh->texture[t[1]] - mMesh->texture[t[0]],
                                                   mMesh->texture[t[2]] - mMesh->texture[t[0]]));
      mCubesPerWorld[i] = world > 0 ? std::sqrt(texture / world) : 0.0f;
    }
    const Aabbf box = m.surfaceBounds();
    mSurfaceOffset = constants::kMeshSurfaceOffset * glm::length(box.max - box.min);
  }

  const polycube::TexturedMesh& mesh() const { return *mMesh; }
  /// What a GPU backend uploads of it: the BVH, the shading normals, each triangle's scale.
  const TriangleBvh<float>& bvh() const { return mBvh; }
  const Vec3f& vertexNormal(std::size_t v) const { return mNormals[v]; }
  float cubesPerWorld(std::size_t triangle) const { return mCubesPerWorld[triangle]; }
  float surfaceOffset() const { return mSurfaceOffset; }
  std::size_t accelerationBytes() const {
    return mBvh.nodeCount() * (sizeof(Aabbf) + 8) + mBvh.triangleCount() * (3 * sizeof(Vec3f) + 4) +
           mNormals.size() * sizeof(Vec3f) + mCubesPerWorld.size() * sizeof(float);
  }

  /// The nearest hit within [ray.tmin, ray.tmax), textured for a cone of `spread` world units per
  /// unit of distance.
  Hit intersect(const Rayf& ray, float spread) const {
    const Hitf h = mBvh.closestHit(ray);
    Hit hit;
    if (!h.valid()) return hit;
    const TriangleMesh& m = mMesh->mesh;
    const Vec3u& tri = m.triangles[h.primId];
    const float w0 = 1.0f - h.u - h.v, w1 = h.u, w2 = h.v;
    hit.t = h.t;
    hit.triangle = h.primId;
    hit.position = ray.origin + h.t * ray.direction;
    const Vec3f interpolated = w0 * mNormals[tri[0]] + w1 * mNormals[tri[1]] + w2 * mNormals[tri[2]];
    const float length = glm::length(interpolated);
    hit.normal = length > 0 ? interpolated / length : glm::normalize(h.geometricNormal);
    if (mMesh->use == polycube::TextureUse::None) return hit;
    const Vec3f texture = w0 * mMesh->texture[tri[0]] + w1 * mMesh->texture[tri[1]] + w2 * mMesh->texture[tri[2]];
    const float cosine = std::abs(glm::dot(glm::normalize(ray.direction), glm::normalize(h.geometricNormal)));
    const float footprint = spread * h.t * glm::length(ray.direction) / std::max(cosine, constants::kMinFootprintCosine);
    const polycube::PolycubeTexture& t2 = *mMesh->t2;
    hit.lod = t2.lodOf(double(footprint) * mCubesPerWorld[h.primId]);
    const std::optional<Vec3d> onSurface = t2.surface().project(Vec3d(texture));
    const std::optional<polycube::SquareletPoint> squarelet =
        onSurface ? t2.surface().lut().locate(*onSurface, constants::kLocateTolerance) : std::nullopt;
    if (!squarelet) return hit;  // validate() keeps corners within reach; kept grey if not
    hit.texture = Vec3f(*onSurface);
    const Vec4f texel = t2.sample(*squarelet, mMesh->filter, hit.lod);
    if (mMesh->use == polycube::TextureUse::Color) {
      hit.color = Vec3f(texel);
    } else {
      const Vec3f n = 2.0f * Vec3f(texel) - 1.0f;
      if (glm::length(n) > 0.1f) hit.normal = glm::normalize(n);
    }
    return hit;
  }

  bool occluded(const Rayf& ray) const { return mBvh.anyHit(ray); }

 private:
  std::shared_ptr<const polycube::TexturedMesh> mMesh;
  TriangleBvh<float> mBvh;
  std::vector<Vec3f> mNormals;
  std::vector<float> mCubesPerWorld;
  float mSurfaceOffset = 0;
};

}  // namespace cellrelief::trace
