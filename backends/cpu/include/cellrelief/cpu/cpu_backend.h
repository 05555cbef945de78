// SPDX-License-Identifier: MIT
/// @file cpu_backend.h
/// The reference renderer and the embedded default: the traversal headers (trace/relief_tracer.h,
/// trace/geotex_tracer.h, trace/polycube_tracer.h, trace/parallax_tracer.h) run over TBB tiles of 16 x 16 pixels, in float as a GPU runs them. The GPU backends implement
/// the same algorithm from the same constants, and their images are compared against this one.
///
/// Shading is deliberately plain so that backends can match it exactly: the hit's color (the
/// model's or chart's color map, a polycube mesh's T2, a relief surface's colour map at
/// (u, v) + I(u, v), or a neutral grey) times ambient plus Lambert over the directional lights,
/// each gated by a shadow ray; optional mirror bounces mixed in by RenderOptions::reflectivity;
/// display gamma 2.2. The normal buffer holds the shading normal turned towards the viewer.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "cellrelief/render/backend.h"
#include "cellrelief/trace/geotex_tracer.h"
#include "cellrelief/trace/parallax_tracer.h"
#include "cellrelief/trace/polycube_tracer.h"
#include "cellrelief/trace/relief_tracer.h"

namespace cellrelief::cpu {

class CpuBackend final : public render::Backend {
 public:
  using Tracer = trace::ReliefTracer<float>;
  static constexpr int kTileSize = 16;

  render::BackendKind kind() const override { return render::BackendKind::Cpu; }

  std::string description() const override {
    return "CPU reference (TBB, " + std::to_string(std::thread::hardware_concurrency()) +
           " hardware threads)";
  }

  void upload(const render::Scene& scene) override {
    std::vector<std::unique_ptr<trace::PolycubeTracer>> meshTracers;
    for (const auto& m : scene.polycubeMeshes) meshTracers.push_back(std::make_unique<trace::PolycubeTracer>(m));
    std::vector<std::unique_ptr<trace::ParallaxTracer>> surfaceTracers;
    for (const auto& s : scene.reliefSurfaces) surfaceTracers.push_back(std::make_unique<trace::ParallaxTracer>(*s));
    std::vector<std::unique_ptr<trace::GeoTexTracer<float>>> chartTracers;
    for (const auto& m : scene.geotexModels) chartTracers.push_back(std::make_unique<trace::GeoTexTracer<float>>(*m));
    mScene = scene;
    mMeshTracers = std::move(meshTracers);
    mSurfaceTracers = std::move(surfaceTracers);
    mChartTracers = std::move(chartTracers);
    mTraceOptions.reset();
    mTracers.clear();
  }

  void render(const render::Camera& camera, const render::RenderOptions& options) override {
    buildTracers(options.trace);
    mFrame.resize(options.width, options.height, options.channels);
    const int tilesX = (options.width + kTileSize - 1) / kTileSize;
    const int tilesY = (options.height + kTileSize - 1) / kTileSize;
    auto renderTiles = [&] {
      tbb::parallel_for(tbb::blocked_range2d<int>(0, tilesY, 1, 0, tilesX, 1),
                        [&](const tbb::blocked_range2d<int>& r) {
                          for (int ty = r.rows().begin(); ty != r.rows().end(); ++ty)
                            for (int tx = r.cols().begin(); tx != r.cols().end(); ++tx)
                              renderTile(camera, options, tx, ty);
                        });
    };
    if (options.threads > 0) {
      tbb::task_arena arena(int(options.threads));
      arena.execute(renderTiles);
    } else {
      renderTiles();
    }
  }

  void readBack(render::Frame& frame) override { frame = mFrame; }

  std::size_t sceneBytes() const override {
    std::size_t bytes = 0;
    for (const auto& m : mScene.models) bytes += m->byteSize();
    for (const auto& m : mScene.geotexModels) bytes += m->byteSize();
    for (const auto& s : mScene.reliefSurfaces) bytes += s->byteSize();
    for (const auto& t : mTracers) bytes += t->accelerationBytes();
    for (const auto& t : mChartTracers) bytes += t->accelerationBytes();
    std::set<const polycube::PolycubeTexture*> textures;  // meshes may share one T2
    for (const auto& t : mMeshTracers) {
      bytes += t->accelerationBytes();
      const polycube::PolycubeTexture& t2 = *t->mesh().t2;
      if (textures.insert(&t2).second)
        bytes += t2.byteSize() + t2.surface().lut().entries().size() * sizeof(polycube::LutEntry);
    }
    return bytes;
  }

  /// The nearest hit over the scene's models, geometry textures, polycube meshes and relief
  /// surfaces (world space), for secondary rays and tests. A mesh, chart or surface hit fills
  /// hit.t, position and normal (hit.cell stays -1).
  struct SceneHit {
    Tracer::Hit hit;
    Vec3f base{0};  ///< the base colour, 0..1
    int model = -1;
    int mesh = -1;
    int geotex = -1;
    int surface = -1;
    trace::ParallaxHit surfaceHit{};  ///< a relief surface's hit, with the frame it was traced in
    std::uint32_t steps = 0;  ///< over every model's search, hit or miss
    bool valid() const { return model >= 0 || mesh >= 0 || geotex >= 0 || surface >= 0; }
  };
  /// `spread`: the ray's cone in world units per unit of distance, for texture filtering.
  SceneHit intersect(const Rayf& ray, float spread = 0) const {
    SceneHit best;
    std::uint32_t steps = 0;
    const auto clipped = [&] {
      Rayf r = ray;
      if (best.valid()) r.tmax = best.hit.t;
      return r;
    };
    for (std::size_t i = 0; i < mTracers.size(); ++i) {
      Tracer::Hit h = mTracers[i]->intersect(clipped());
      steps += h.steps;
      if (h.valid() && (!best.valid() || h.t < best.hit.t)) best = {h, Vec3f(h.color) / 255.0f, int(i), -1};
    }
    for (std::size_t i = 0; i < mMeshTracers.size(); ++i) {
      const trace::PolycubeTracer::Hit h = mMeshTracers[i]->intersect(clipped(), spread);
      if (!h.valid() || (best.valid() && h.t >= best.hit.t)) continue;
      best = SceneHit{};
      best.hit.t = h.t;
      best.hit.position = h.position;
      best.hit.normal = h.normal;
      best.base = h.color;
      best.mesh = int(i);
    }
    for (std::size_t i = 0; i < mChartTracers.size(); ++i) {
      trace::GeoTexTraceStats stats;
      const Hitf h = mChartTracers[i]->intersect(clipped(), &stats);
      steps += std::uint32_t(stats.samples + stats.nodes);
      if (!h.valid() || (best.valid() && h.t >= best.hit.t)) continue;
      best = SceneHit{};
      best.hit.t = h.t;
      best.hit.position = ray.at(h.t);
      best.hit.normal = h.geometricNormal;
      best.base = mChartTracers[i]->colorAt(h);
      best.geotex = int(i);
    }
    for (std::size_t i = 0; i < mSurfaceTracers.size(); ++i) {
      const trace::ParallaxTracer& tracer = *mSurfaceTracers[i];
      const trace::ParallaxHit h = tracer.intersect(clipped());
      steps += h.samples;
      if (!h.valid() || (best.valid() && h.t >= best.hit.t)) continue;
      best = SceneHit{};
      best.hit.t = h.t;
      best.hit.position = ray.at(h.t);
      best.hit.normal = tracer.normalAt(h);
      best.base = tracer.colorAt(h);
      best.surface = int(i);
      best.surfaceHit = h;
    }
    best.steps = steps;
    return best;
  }
  bool occluded(const Rayf& ray) const {
    for (const auto& t : mTracers)
      if (t->occluded(ray)) return true;
    for (const auto& t : mMeshTracers)
      if (t->occluded(ray)) return true;
    for (const auto& t : mChartTracers)
      if (t->occluded(ray)) return true;
    for (const auto& t : mSurfaceTracers)
      if (t->occluded(ray)) return true;
    return false;
  }

  /// Builds the relief models' tracers (and their empty-space pyramids) for these options; a
  /// no-op when the scene and options are unchanged since the last call. render() calls it.
  void buildTracers(const trace::TraceOptions& options) {
    if (mTraceOptions && *mTraceOptions == options) return;
    mTracers.clear();
    for (const auto& m : mScene.models) mTracers.push_back(std::make_unique<Tracer>(*m, options));
    // Geometry textures skip as relief models do (--no-skip turns both off); their tracers, built
    // at upload, only change their search.
    for (const auto& t : mChartTracers) {
      trace::GeoTexTraceOptions search = t->options();
      search.skipSteps = options.skipEmptySpace;
      t->setOptions(search);
    }
    mTraceOptions = options;
  }

 private:
  /// A secondary ray starts this far off the surface (world units): two sample spacings of the
  /// model it left, past the reach of its own reconstruction error.
  float surfaceOffset(const SceneHit& sh) const {
    if (sh.mesh >= 0) return mMeshTracers[std::size_t(sh.mesh)]->surfaceOffset();
    if (sh.geotex >= 0) return mChartTracers[std::size_t(sh.geotex)]->surfaceOffset();
    if (sh.surface >= 0) return mSurfaceTracers[std::size_t(sh.surface)]->surfaceOffset();
    const relief::ReliefModel& m = *mScene.models[std::size_t(sh.model)];
    return float(double(trace::constants::kSurfaceOffsetSamples) * m.cellSizeWS / std::max(1, m.texels - 1));
  }

  /// `spread`: the primary ray's cone, which a mirror ray keeps (a flat mirror's reflection).
  Vec3f shade(const Rayf& ray, const SceneHit& sh, Vec3f normal, const render::RenderOptions& options, int depth,
              float spread) const {
    const Vec3f base = sh.base;
    const Vec3f p = sh.hit.position;
    const float offset = surfaceOffset(sh);
    Vec3f light = mScene.ambient;
    for (const render::DirectionalLight& l : mScene.lights) {
      const Vec3f towards = glm::normalize(l.direction);
      const float lambert = glm::dot(normal, towards);
      if (lambert <= 0) continue;
      if (options.shadows && sh.surface >= 0 &&
          mSurfaceTracers[std::size_t(sh.surface)]->selfShadowed(sh.surfaceHit, normal, towards, offset))
        continue;
      if (options.shadows && occluded(Rayf(p + offset * normal, towards))) continue;
      light += l.color * (l.intensity * lambert);
    }
    Vec3f c = base * light;
    if (depth < options.reflectionBounces) {
      const Vec3f dir = glm::reflect(glm::normalize(ray.direction), normal);
      const Rayf mirror(p + offset * normal, dir);
      const SceneHit next = intersect(mirror, spread);
      Vec3f reflected = Vec3f(mScene.background);
      if (next.valid()) reflected = shade(mirror, next, facing(next.hit.normal, dir), options, depth + 1, spread);
      c = glm::mix(c, reflected, options.reflectivity);
    }
    return c;
  }

  /// One pixel's angle (the image plane's height over its pixels, at distance 1): the cone of a
  /// primary ray, for texture filtering.
  static float pixelSpread(const render::Camera::FloatFrame& frame) {
    return 2.0f * glm::length(frame.up) / float(frame.height);
  }

  /// The normal turned towards where the ray came from.
  static Vec3f facing(const Vec3f& n, const Vec3f& direction) {
    return glm::dot(n, direction) > 0 ? -n : n;
  }

  void renderTile(const render::Camera& camera, const render::RenderOptions& options, int tx,
                  int ty) {
    const int x1 = std::min(options.width, (tx + 1) * kTileSize);
    const int y1 = std::min(options.height, (ty + 1) * kTileSize);
    const render::Camera::FloatFrame frame = camera.floatFrame(options.width, options.height);
    const float spread = pixelSpread(frame);
    for (int y = ty * kTileSize; y < y1; ++y)
      for (int x = tx * kTileSize; x < x1; ++x) {
        const Rayf ray = frame.ray(x, y);
        const SceneHit sh = intersect(ray, spread);
        if (mFrame.has(render::kSteps)) mFrame.steps.at(x, y, 0) = float(sh.steps);
        if (!sh.valid()) {
          if (mFrame.has(render::kColor))
            for (int c = 0; c < 4; ++c)
              mFrame.color.at(x, y, c) = std::uint8_t(std::lround(255.0f * mScene.background[c]));
          continue;
        }
        const Vec3f n = facing(sh.hit.normal, ray.direction);
        if (mFrame.has(render::kDepth)) mFrame.depth.at(x, y, 0) = sh.hit.t;
        if (mFrame.has(render::kMask)) mFrame.mask.at(x, y, 0) = 1;
        if (mFrame.has(render::kCell)) mFrame.cell.at(x, y, 0) = float(sh.hit.cell);
        if (mFrame.has(render::kNormal))
          for (int c = 0; c < 3; ++c) mFrame.normal.at(x, y, c) = n[c];
        if (mFrame.has(render::kColor)) {
          const Vec3f c = glm::clamp(shade(ray, sh, n, options, 0, spread), Vec3f(0), Vec3f(1));
          for (int k = 0; k < 3; ++k)
            mFrame.color.at(x, y, k) = std::uint8_t(std::lround(255.0f * std::pow(c[k], 1.0f / 2.2f)));
          mFrame.color.at(x, y, 3) = 255;
        }
      }
  }

  render::Scene mScene;
  std::vector<std::unique_ptr<Tracer>> mTracers;
  std::vector<std::unique_ptr<trace::PolycubeTracer>> mMeshTracers;
  std::vector<std::unique_ptr<trace::GeoTexTracer<float>>> mChartTracers;
  std::vector<std::unique_ptr<trace::ParallaxTracer>> mSurfaceTracers;
  std::optional<trace::TraceOptions> mTraceOptions;
  render::Frame mFrame;
};

}  // namespace cellrelief::cpu
