// SPDX-License-Identifier: MIT
/// @file embree_scene.h
/// Verification with Embree 3: ground-truth rays against the original triangle mesh. The relief
/// tracer is measured against these rays (hit/miss, depth, normal) and benchmarked against
/// rtcIntersect1 on the same rays and threads. Embree's own allocations are counted through its
/// memory monitor, so "mesh plus BVH" bytes are measured, not estimated.
#pragma once

#include <atomic>
#include <cmath>
#include <memory>
#include <string>

#include <embree3/rtcore.h>

#include "cellrelief/core/error.h"
#include "cellrelief/core/hit.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/ray.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/render/camera.h"
#include "cellrelief/render/frame.h"

namespace cellrelief::embree {

class EmbreeScene {
 public:
  /// Builds a high-quality BVH over the mesh (Embree copies the vertices and indices into its own
  /// buffers, which are counted in byteSize()).
  explicit EmbreeScene(const TriangleMesh& mesh) : mMesh(&mesh) {
    mDevice = rtcNewDevice("threads=0");
    if (!mDevice) throw Error(ErrorKind::Unsupported, "Embree: cannot create a device");
    rtcSetDeviceMemoryMonitorFunction(mDevice, &EmbreeScene::monitor, &mBytes);
    mScene = rtcNewScene(mDevice);
    rtcSetSceneBuildQuality(mScene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(mDevice, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      release();
      throw Error(ErrorKind::ResourceLimit, "Embree: cannot allocate the mesh buffers");
    }
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
      for (int c = 0; c < 3; ++c) vertices[3 * i + c] = mesh.positions[i][c];
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int c = 0; c < 3; ++c) indices[3 * i + c] = unsigned(mesh.triangles[i][c]);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(mScene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(mScene);
  }
  ~EmbreeScene() { release(); }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// rtcIntersect1: the nearest hit in [tmin, tmax], Embree's record converted to ours.
  Hitf intersect(const Rayf& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    setRay(rh.ray, ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(mScene, &context, &rh);
    Hitf hit;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
    hit.t = rh.ray.tfar;
    hit.geometricNormal = Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.primId = rh.hit.primID;
    hit.geomId = rh.hit.geomID;
    return hit;
  }

  /// rtcOccluded1: whether anything lies on the ray within [tmin, tmax].
  bool occluded(const Rayf& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    setRay(r, ray);
    rtcOccluded1(mScene, &context, &r);
    return r.tfar < 0;
  }

  /// Unit normal at a hit: the mesh's interpolated vertex normals when it has them, else the
  /// geometric normal.
  Vec3f normal(const Hitf& hit) const {
    const auto& tri = mMesh->triangles[hit.primId];
    if (!mMesh->normals.empty()) {
      const Vec3f n = (1 - hit.u - hit.v) * mMesh->normals[tri[0]] + hit.u * mMesh->normals[tri[1]] +
                      hit.v * mMesh->normals[tri[2]];
      if (glm::length(n) > 0) return glm::normalize(n);
    }
    return glm::normalize(hit.geometricNormal);
  }

  /// Bytes Embree holds (vertex and index buffers, BVH), from its memory monitor.
  std::size_t byteSize() const { return std::size_t(std::max<long long>(0, mBytes.load())); }

  /// Renders depth (distance along the unit primary ray), normal (turned towards the viewer) and
  /// mask for a camera: the reference frame the relief backends are compared with.
  render::Frame renderReference(const render::Camera& camera, int width, int height) const {
    render::Frame frame;
    frame.resize(width, height, render::kDepth | render::kNormal | render::kMask);
    parallelFor(0, std::size_t(width) * height, [&](std::size_t i) {
      const int x = int(i % width), y = int(i / width);
      const Rayd primary = camera.primaryRay(x, y, width, height);
      const Rayf ray(Vec3f(primary.origin), Vec3f(primary.direction));
      const Hitf hit = intersect(ray);
      if (!hit.valid()) return;
      Vec3f n = normal(hit);
      if (glm::dot(n, ray.direction) > 0) n = -n;
      frame.depth.at(x, y, 0) = hit.t;
      frame.mask.at(x, y, 0) = 1;
      for (int c = 0; c < 3; ++c) frame.normal.at(x, y, c) = n[c];
    }, 256);
    return frame;
  }

 private:
  static bool monitor(void* user, ssize_t bytes, bool) {
    static_cast<std::atomic<long long>*>(user)->fetch_add(bytes);
    return true;
  }
  static void setRay(RTCRay& r, const Rayf& ray) {
    r.org_x = ray.origin.x;
    r.org_y = ray.origin.y;
    r.org_z = ray.origin.z;
    r.dir_x = ray.direction.x;
    r.dir_y = ray.direction.y;
    r.dir_z = ray.direction.z;
    r.tnear = ray.tmin;
    r.tfar = ray.tmax;
    r.time = 0;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
  }
  void release() {
    if (mScene) rtcReleaseScene(mScene);
    if (mDevice) rtcReleaseDevice(mDevice);
    mScene = nullptr;
    mDevice = nullptr;
  }

  const TriangleMesh* mMesh = nullptr;
  RTCDevice mDevice = nullptr;
  RTCScene mScene = nullptr;
  std::atomic<long long> mBytes{0};
};

}  // namespace cellrelief::embree
