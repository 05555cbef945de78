// SPDX-License-Identifier: MIT
/// @file gpu_frame.h
/// What the GPU backends share about a frame, API-neutral: the uniform blocks the shaders read
/// (the traversal's `Params`, the cell cover's `Cover`), the layout of the output words in the
/// frame buffer, the miss values the rasterized entry clears it to, and the unpacking of those
/// words into a render::Frame. OpenGL and Vulkan fill the same structs, so the two cannot differ
/// in what a frame means.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "cellrelief/gpu/gpu_layout.h"
#include "cellrelief/gpu/shader_preamble.h"
#include "cellrelief/render/camera.h"
#include "cellrelief/render/frame.h"
#include "cellrelief/render/render_options.h"
#include "cellrelief/render/scene.h"

namespace cellrelief::gpu {

/// How the traversal reaches the pixels: the paper's way, the grey cells and chart boxes rasterized
/// into the stencil and the traversal run in a fragment pass on the covered pixels only; a compute
/// pass over all of them; or the faster of the two on this device (the default). Both give the same
/// frame (docs/backends.md compares them).
///
/// Why a measured default: which is faster depends on the device, not only on the scene. On
/// llvmpipe and lavapipe the fragment pass runs 1.2x to 1.8x the compute pass (bench_backends); on
/// an NVIDIA H100, whose graphics pipeline runs on 2 of its 66 TPCs (NVIDIA's H100 whitepaper),
/// the compute pass ran 4x to 19x the fragment pass (bench_geotex's Fig. 7, docs/geotex.md); a
/// gaming GPU runs both on every SM.
enum class RayEntry {
  Compute,
  Rasterized,
  /// Each of the two timed once on the device's clock per shader variant and frame size (and
  /// scene: an upload starts afresh), the faster kept. Rasterized on a CPU device (llvmpipe,
  /// lavapipe: measured faster there, and no trials make their frames depend on timing) or where
  /// the device has no clock.
  Fastest
};

/// The switches both GPU backends offer (to measure what each choice costs, and for tests), and
/// the shader variant they select for a scene and options.
class TraversalControls {
 public:
  /// Render with the one shader that holds every projection, map and feature (to measure what
  /// the specialized variants save).
  void setGeneralShader(bool general) { mGeneral = general; }
  /// Read the 2 x 2 samples with one textureGather instead of four texel fetches.
  void setGather(bool gather) { mGather = gather; }
  /// The entry of the next frames (RayEntry). The rasterized entry needs the eye outside the
  /// scene's bounds; inside, it renders by compute.
  void setRayEntry(RayEntry entry) { mEntry = entry; }
  RayEntry rayEntry() const { return mEntry; }
  /// How the last render reached its pixels.
  RayEntry lastRayEntry() const { return mLastEntry; }
  /// Overrides the enlargement of the rasterized cells' boxes (cell units; negative shrinks them)
  /// and chart boxes (fractions of each box): for tests that check the stencil really limits the
  /// fragment pass.
  void setCoverDilation(std::optional<double> cells) { mCoverDilation = cells; }

 protected:
  ShaderVariant variantOf(const SceneFeatures& features, const render::RenderOptions& options) const {
    ShaderVariant v = mGeneral ? ShaderVariant::general()
                               : ShaderVariant::specialized(features, options.trace, options.shadows,
                                                            options.reflectionBounces > 0, options.channels);
    if (mGeneral) v.channels = render::kAllChannels;
    v.gather = mGather;
    return v;
  }

  /// Whether this frame takes the rasterized entry. `possible`: the scene, the view and the device
  /// allow it; `timed`: the device is a GPU with a clock (RayEntry::Fastest). A Fastest frame
  /// without a verdict yet is a trial, which entryTimed() scores.
  bool takeRasterized(const ShaderVariant& variant, const render::RenderOptions& options, bool possible, bool timed) {
    mTrial.reset();
    if (!possible) return false;
    if (mEntry != RayEntry::Fastest) return mEntry == RayEntry::Rasterized;
    if (!timed) return true;
    auto it = std::find_if(mEntryTimes.begin(), mEntryTimes.end(), [&](const EntryTimes& e) {
      return e.variant == variant && e.width == options.width && e.height == options.height;
    });
    if (it == mEntryTimes.end())
      it = mEntryTimes.insert(mEntryTimes.end(), EntryTimes{variant, options.width, options.height});
    if (it->rasterized > 0 && it->compute > 0) return it->rasterized <= it->compute;
    mTrial = std::size_t(it - mEntryTimes.begin());
    return !(it->rasterized > 0);  // rasterized first, then compute
  }

  /// The device time of the frame takeRasterized() last chose (read back); scores a trial.
  void entryTimed(bool rasterized, double seconds) {
    if (!mTrial || !(seconds > 0)) return;
    EntryTimes& e = mEntryTimes[*mTrial];
    (rasterized ? e.rasterized : e.compute) = seconds;
    mTrial.reset();
  }

  /// Drops the entries' times (a new scene is timed anew).
  void forgetEntryTimes() {
    mEntryTimes.clear();
    mTrial.reset();
  }

  bool mGeneral = false, mGather = true;
  RayEntry mEntry = RayEntry::Fastest, mLastEntry = RayEntry::Compute;
  std::optional<double> mCoverDilation;

 private:
  struct EntryTimes {
    ShaderVariant variant;
    int width = 0, height = 0;
    double rasterized = 0, compute = 0;  ///< device seconds of the trial frame; 0: not yet timed
  };
  std::vector<EntryTimes> mEntryTimes;
  std::optional<std::size_t> mTrial;
};

/// The std140 uniform block `Params` of relief_trace.comp.
struct FrameParams {
  float eye[4], forward[4], right[4], up[4], ambient[4], background[4];
  struct Light {
    float direction[4];
    float color[4];
  } lights[kMaxLights];
  std::int32_t size[4];    ///< width, height, models, lights
  std::int32_t steps[4];   ///< minLinear, maxLinear, binary, reflection bounces
  float tuning[4];         ///< stepsPerTexel, reflectivity
  std::int32_t flags[4];   ///< shadows, skip, color offset, depth offset
  std::int32_t offsets[4]; ///< normal, mask, cell and steps offsets
};

/// The block `Cover` of cell_cover.vert (a std140 uniform block in OpenGL, push constants in
/// Vulkan: 112 bytes, within the 128 every Vulkan device offers).
struct CoverParams {
  float viewProjection[16];  ///< column-major
  float originAndCellSize[4];  ///< cells: the grid's origin and cell size
  float dilation[4];           ///< cells: [0] in cell units; chart boxes: [1] world units + [2] x the box
  std::int32_t cellOffset[4];  ///< [0] the first cell, or the geometry-texture model; [1] 0 cells, 1 chart boxes
};
static_assert(sizeof(CoverParams) <= 128);

/// Where each channel's words lie in the frame buffer.
struct FrameLayout {
  int width = 0, height = 0;
  unsigned channels = 0;  ///< the channels the caller asked for
  unsigned written = 0;   ///< the channels the shader writes
  std::size_t color = 0, depth = 0, normal = 0, mask = 0, cell = 0, steps = 0, words = 0;
};

/// The layout of a frame whose shader writes the channels `written`; refused when it is beyond
/// one storage buffer of the device.
inline FrameLayout frameLayout(const render::RenderOptions& o, unsigned written, std::size_t maxStorageBytes) {
  FrameLayout l;
  l.width = o.width;
  l.height = o.height;
  l.channels = o.channels;
  l.written = written;
  const std::size_t pixels = std::size_t(o.width) * std::size_t(o.height);
  std::size_t at = 0;
  auto take = [&](unsigned channel, std::size_t perPixel, std::size_t& offset) {
    if (written & channel) offset = at, at += perPixel * pixels;
  };
  take(render::kColor, 1, l.color);
  take(render::kDepth, 1, l.depth);
  take(render::kNormal, 3, l.normal);
  take(render::kMask, 1, l.mask);
  take(render::kCell, 1, l.cell);
  take(render::kSteps, 1, l.steps);
  l.words = std::max<std::size_t>(at, 4);
  if (l.words * 4 > maxStorageBytes)
    throw Error(ErrorKind::ResourceLimit,
                "a " + std::to_string(o.width) + "x" + std::to_string(o.height) + " frame needs " +
                    detail::mib(l.words * 4) + " of output, beyond the device's storage buffer limit of " +
                    detail::mib(maxStorageBytes));
  return l;
}

/// The traversal's uniforms for a frame: Camera::primaryRay's basis computed once, the lights,
/// the trace options, the channel offsets.
inline FrameParams frameParams(const render::Scene& scene, const render::Camera& camera,
                               const render::RenderOptions& o, const FrameLayout& layout) {
  FrameParams p{};
  auto put = [](float* dst, const auto& v, float w = 0) {
    dst[0] = float(v.x), dst[1] = float(v.y), dst[2] = float(v.z), dst[3] = w;
  };
  const render::Camera::FloatFrame frame = camera.floatFrame(o.width, o.height);
  put(p.eye, frame.eye);
  put(p.forward, frame.forward);
  put(p.right, frame.right);
  put(p.up, frame.up);
  put(p.ambient, Vec3d(scene.ambient));
  for (int c = 0; c < 4; ++c) p.background[c] = scene.background[c];
  for (std::size_t i = 0; i < scene.lights.size() && i < std::size_t(kMaxLights); ++i) {
    const render::DirectionalLight& l = scene.lights[i];
    put(p.lights[i].direction, glm::normalize(Vec3d(l.direction)));
    put(p.lights[i].color, Vec3d(l.color * l.intensity));
  }
  p.size[0] = o.width;
  p.size[1] = o.height;
  p.size[2] = int(scene.models.size());
  p.size[3] = int(std::min<std::size_t>(scene.lights.size(), std::size_t(kMaxLights)));
  p.steps[0] = o.trace.minLinearSteps;
  p.steps[1] = o.trace.maxLinearSteps;
  p.steps[2] = o.trace.binarySteps;
  p.steps[3] = o.reflectionBounces;
  p.tuning[0] = o.trace.stepsPerTexel;
  p.tuning[1] = o.reflectivity;
  p.flags[0] = o.shadows ? 1 : 0;
  // Bit 0: skipping in parallel and planar cells; bit 1: in central ones too.
  p.flags[1] = (o.trace.skipEmptySpace ? 1 : 0) | (o.trace.skipEmptySpace && o.trace.skipCentralCells ? 2 : 0);
  p.flags[2] = int(layout.color);
  p.flags[3] = int(layout.depth);
  p.offsets[0] = int(layout.normal);
  p.offsets[1] = int(layout.mask);
  p.offsets[2] = int(layout.cell);
  p.offsets[3] = int(layout.steps);
  return p;
}

/// A scene the GPU backends can shade: at most kMaxLights lights (the uniform block's array).
inline void checkSceneSupported(const render::Scene& scene, const char* backend) {
  if (scene.lights.size() > std::size_t(kMaxLights))
    throw Error(ErrorKind::InvalidArgument, std::string(backend) + " shades at most " + std::to_string(kMaxLights) +
                                                " lights; the scene has " + std::to_string(scene.lights.size()));
}

/// Whether the rasterized entry (rays started where the cover of grey cells and chart boxes is
/// drawn) sees everything the compute entry does: when the eye lies outside the scene's bounds
/// (with a margin), every ray enters the grids and boxes from outside, where their rasterized
/// faces show it. A scene with polycube meshes or relief surfaces always takes the compute entry
/// (the cover would hide them).
inline bool rasterizedEntryServes(const render::Scene& scene, const render::Camera& camera) {
  if (!scene.polycubeMeshes.empty() || !scene.reliefSurfaces.empty()) return false;
  const Aabbd bounds = scene.boundsWS();
  const Vec3d margin(0.01 * bounds.diagonal());
  return glm::any(glm::lessThan(camera.eye, bounds.min - margin)) ||
         glm::any(glm::greaterThan(camera.eye, bounds.max + margin));
}

/// Clip space of the API: OpenGL's has y up and z in [-1, 1], Vulkan's y down and z in [0, 1].
enum class ClipSpace { OpenGL, Vulkan };

/// The camera as a projection whose pixel centres are Camera::primaryRay's, with near and far
/// planes around `bounds`; and the farthest depth of the bounds along the view.
struct CameraProjection {
  float viewProjection[16];  ///< column-major
  double farthest = 0;
};

inline CameraProjection cameraProjection(const render::Camera& camera, int width, int height, const Aabbd& bounds,
                                         ClipSpace clip = ClipSpace::OpenGL) {
  const render::Camera::Basis basis = camera.basis();
  const Vec3d &forward = basis.forward, &right = basis.right, &up = basis.up;
  const double tanHalf = basis.tanHalf;
  const double aspect = double(width) / double(height);
  double farthest = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3d corner((c & 1) ? bounds.max.x : bounds.min.x, (c & 2) ? bounds.max.y : bounds.min.y,
                       (c & 4) ? bounds.max.z : bounds.min.z);
    farthest = std::max(farthest, glm::dot(corner - camera.eye, forward));
  }
  const Vec3d closest = glm::clamp(camera.eye, bounds.min, bounds.max);
  const double nearPlane = std::max(1e-9 * bounds.diagonal(), 0.5 * glm::length(closest - camera.eye));
  const double farPlane = 2 * std::max(farthest, nearPlane) + bounds.diagonal();
  // Depth d maps to z = (a d - b) / d: -1 (OpenGL) or 0 (Vulkan) at the near plane, 1 at the far.
  const bool vulkan = clip == ClipSpace::Vulkan;
  const double a = vulkan ? farPlane / (farPlane - nearPlane) : (farPlane + nearPlane) / (farPlane - nearPlane);
  const double b = (vulkan ? 1 : 2) * farPlane * nearPlane / (farPlane - nearPlane);
  const Vec3d rows[4] = {right / (tanHalf * aspect), (vulkan ? -up : up) / tanHalf, a * forward, forward};
  const double offsets[4] = {-glm::dot(rows[0], camera.eye), -glm::dot(rows[1], camera.eye),
                             -glm::dot(rows[2], camera.eye) - b, -glm::dot(rows[3], camera.eye)};
  CameraProjection p{};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 3; ++c) p.viewProjection[c * 4 + r] = float(rows[r][c]);
    p.viewProjection[12 + r] = float(offsets[r]);
  }
  p.farthest = farthest;
  return p;
}

namespace detail {
/// What every cover draw starts from: the camera's projection in `params`, and the world size of a
/// pixel at the scene's farthest point (the unit of the covers' enlargement).
struct CoverFrame {
  CoverParams params{};
  double pixelWS = 0;
};
inline CoverFrame coverFrame(const render::Scene& scene, const render::Camera& camera, const render::RenderOptions& o,
                             ClipSpace clip) {
  const CameraProjection projection = cameraProjection(camera, o.width, o.height, scene.boundsWS(), clip);
  CoverFrame f;
  std::copy_n(projection.viewProjection, 16, f.params.viewProjection);
  f.pixelWS = 2 * camera.basis().tanHalf * std::max(projection.farthest, 0.0) / double(o.height);
  return f;
}
}  // namespace detail

/// The cover of one model for the rasterized entry: the camera's projection (cameraProjection),
/// and each cell's box enlarged by two pixels at the farthest point of the scene, so that no ray
/// that grazes a grey cell is lost to the rasterizer's rounding. `dilationCells` overrides the
/// enlargement (tests).
inline CoverParams coverParams(const render::Scene& scene, const GpuScene& gpuScene, const render::Camera& camera,
                               const render::RenderOptions& o, std::size_t model,
                               std::optional<double> dilationCells = std::nullopt,
                               ClipSpace clip = ClipSpace::OpenGL) {
  const detail::CoverFrame frame = detail::coverFrame(scene, camera, o, clip);
  CoverParams p = frame.params;
  const relief::ReliefModel& m = *scene.models[model];
  for (int c = 0; c < 3; ++c) p.originAndCellSize[c] = float(m.originWS[c]);
  p.originAndCellSize[3] = float(m.cellSizeWS);
  p.dilation[0] = float(dilationCells ? *dilationCells : std::max(1e-3, 2 * frame.pixelWS / m.cellSizeWS));
  p.cellOffset[0] = gpuScene.models[model].cellOffset;
  return p;
}

/// The cover of one geometry-texture model: its chart boxes (one instance each), enlarged like
/// the cells by two pixels at the scene's farthest point (in world units). `dilationBoxes`
/// overrides the enlargement, as a fraction of each box's own size per axis (tests: a negative
/// one shrinks the boxes).
inline CoverParams chartCoverParams(const render::Scene& scene, const render::Camera& camera,
                                    const render::RenderOptions& o, std::size_t geotexModel,
                                    std::optional<double> dilationBoxes = std::nullopt,
                                    ClipSpace clip = ClipSpace::OpenGL) {
  const detail::CoverFrame frame = detail::coverFrame(scene, camera, o, clip);
  CoverParams p = frame.params;
  const double floorWS = 1e-6 * scene.boundsWS().diagonal();  // a box seen edge-on still covers its pixels
  p.dilation[1] = dilationBoxes ? 0.0f : float(std::max(floorWS, 2 * frame.pixelWS));
  p.dilation[2] = dilationBoxes ? float(*dilationBoxes) : 0.0f;
  p.cellOffset[0] = std::int32_t(geotexModel);
  p.cellOffset[1] = 1;
  return p;
}

/// One run of equal words the frame buffer is cleared to.
struct WordFill {
  std::size_t offset = 0, words = 0;
  std::uint32_t value = 0;
};

/// The miss values of every written channel: what a ray that meets no grey cell writes (the
/// rasterized entry clears the frame to them; its fragment pass writes the covered pixels).
inline std::vector<WordFill> missFills(const FrameLayout& layout, const render::Scene& scene) {
  const std::size_t pixels = std::size_t(layout.width) * std::size_t(layout.height);
  std::uint32_t background = 0;
  for (int c = 0; c < 4; ++c)
    background |= std::uint32_t(std::floor(255.0f * std::clamp(scene.background[c], 0.0f, 1.0f) + 0.5f)) << (8 * c);
  const float inf = std::numeric_limits<float>::infinity(), minusOne = -1.0f;
  std::uint32_t infBits = 0, minusOneBits = 0;
  std::memcpy(&infBits, &inf, 4);
  std::memcpy(&minusOneBits, &minusOne, 4);
  std::vector<WordFill> fills;
  auto fill = [&](unsigned channel, std::size_t offset, std::size_t words, std::uint32_t value) {
    if (layout.written & channel) fills.push_back({offset, words, value});
  };
  fill(render::kColor, layout.color, pixels, background);
  fill(render::kDepth, layout.depth, pixels, infBits);
  fill(render::kNormal, layout.normal, 3 * pixels, 0u);
  fill(render::kMask, layout.mask, pixels, 0u);
  fill(render::kCell, layout.cell, pixels, minusOneBits);
  fill(render::kSteps, layout.steps, pixels, 0u);
  return fills;
}

/// The frame buffer's words as the channels the caller asked for.
inline void unpackFrame(const std::uint32_t* words, const FrameLayout& layout, render::Frame& frame) {
  const int w = layout.width, h = layout.height;
  frame.resize(w, h, layout.channels);
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  if (frame.has(render::kColor)) {
    auto out = frame.color.levelData();
    for (std::size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < 4; ++c) out[4 * i + std::size_t(c)] = std::uint8_t(words[layout.color + i] >> (8 * c));
  }
  if (frame.has(render::kDepth)) std::memcpy(frame.depth.levelData().data(), &words[layout.depth], pixels * 4);
  if (frame.has(render::kNormal)) std::memcpy(frame.normal.levelData().data(), &words[layout.normal], 3 * pixels * 4);
  if (frame.has(render::kMask)) {
    auto out = frame.mask.levelData();
    for (std::size_t i = 0; i < pixels; ++i) out[i] = std::uint8_t(words[layout.mask + i]);
  }
  if (frame.has(render::kCell)) std::memcpy(frame.cell.levelData().data(), &words[layout.cell], pixels * 4);
  if (frame.has(render::kSteps)) std::memcpy(frame.steps.levelData().data(), &words[layout.steps], pixels * 4);
}

}  // namespace cellrelief::gpu
