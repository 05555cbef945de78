// SPDX-License-Identifier: MIT
/// @file shader_preamble.h
/// What the GPU backends prepend to the one GLSL source (backends/shaders/relief_trace.comp):
/// the traversal constants, written from the C++ values the CPU tracer uses
/// (trace/trace_options.h, relief/relief_model.h, gpu_layout.h), so the two cannot drift; and
/// the variant: the projection types, maps and features a scene uses, so that a scene pays only
/// for what it has (a shader without the branches, loops and bindings it would never take).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include "cellrelief/core/ray.h"
#include "cellrelief/gpu/gpu_layout.h"
#include "cellrelief/gpu/shader_sources.h"
#include "cellrelief/render/frame.h"
#include "cellrelief/trace/trace_options.h"

namespace cellrelief::gpu {

/// A shader variant: what is compiled in. `general()` has everything (any scene, any options).
struct ShaderVariant {
  bool parallel = true, planar = true, perspective = true, axial = true;
  bool octahedralNormals = true, rgbaNormals = true, colors = true;
  bool skip = true, shadows = true, reflections = true;
  unsigned channels = render::kAllChannels;
  bool gather = true;  ///< read the 2 x 2 samples with one textureGather (measured: 12% faster on llvmpipe, same image) instead of 4 fetches

  static ShaderVariant general() { return {}; }
  /// Only what this scene and these options use.
  static ShaderVariant specialized(const SceneFeatures& f, bool skipEmptySpace, bool shadows,
                                   bool reflections, unsigned channels) {
    ShaderVariant v;
    v.parallel = f.parallel;
    v.planar = f.planar;
    v.perspective = f.perspective;
    v.axial = f.axial;
    v.octahedralNormals = f.octahedralNormals;
    v.rgbaNormals = f.rgbaNormals;
    v.colors = f.colors;
    v.skip = skipEmptySpace && f.pyramid && (f.parallel || f.planar);
    v.channels = channels;
    v.shadows = shadows && (channels & render::kColor);
    v.reflections = reflections && (channels & render::kColor);
    return v;
  }
  bool operator==(const ShaderVariant&) const = default;
  /// A short name for logs and benchmarks, e.g. "P-S-A:oct:skip:shadows".
  std::string name() const {
    std::string s;
    s += parallel ? "p" : "-";
    s += planar ? "l" : "-";
    s += perspective ? "s" : "-";
    s += axial ? "a" : "-";
    if (octahedralNormals) s += ":oct";
    if (rgbaNormals) s += ":rgba";
    if (colors) s += ":color";
    if (skip) s += ":skip";
    if (shadows) s += ":shadows";
    if (reflections) s += ":mirror";
    if (gather) s += ":gather";
    return s;
  }
};

/// The compute workgroup in pixels. Measured on llvmpipe (armadillo, 400 x 400): 8 x 8 0.35 s,
/// 16 x 16 0.34 s, 4 x 16 0.54 s, 2 x 32 0.95 s: it runs 8 consecutive x invocations as one
/// 256-bit vector, so a group narrower than 8 leaves lanes empty.
inline constexpr int kGroupWidth = 8, kGroupHeight = 8;

/// Directional lights the shader's uniform block holds.
inline constexpr int kMaxLights = 8;

namespace detail {
inline std::string glslFloat(double v) {
  char text[48];
  std::snprintf(text, sizeof text, "(%.9e)", v);
  return text;
}
inline std::string define(const char* name, const std::string& value) {
  return std::string("#define ") + name + " " + value + "\n";
}
inline std::string define(const char* name, int value) { return define(name, std::to_string(value)); }
inline std::string defineUint(const char* name, std::uint32_t value) {
  return define(name, std::to_string(value) + "u");
}
}  // namespace detail

/// The constants both sides use, as GLSL #defines.
inline std::string traversalConstants() {
  using detail::define;
  using detail::glslFloat;
  namespace c = trace::constants;
  std::string s;
  s += define("CR_EMPTY_FIELD", glslFloat(c::kEmptyField));
  s += define("CR_NEAR_FACE_SAMPLES", glslFloat(c::kNearFaceSamples));
  s += define("CR_FOOTPRINT_PROBES", c::kFootprintProbes);
  s += define("CR_SKIP_PROGRESS", glslFloat(c::kSkipProgress));
  s += define("CR_NUDGE_ULPS", glslFloat(c::kNudgeUlps));
  s += define("CR_FLOAT_EPSILON", glslFloat(std::numeric_limits<float>::epsilon()));
  s += define("CR_ROOT_BISECTIONS", c::kRootBisections);
  s += define("CR_QUADRATIC_EPSILON", glslFloat(c::kQuadraticEpsilon));
  s += define("CR_SHADE_SEARCH_RADIUS", c::kShadeSearchRadius);
  s += define("CR_SURFACE_OFFSET_SAMPLES", glslFloat(c::kSurfaceOffsetSamples));
  s += define("CR_GAMMA3", glslFloat(roundingGamma<float>(3)));
  s += detail::defineUint("CR_CENTRE_INSIDE_BIT", relief::CellRecord::kCentreInside);
  s += define("CR_MAX_PYRAMID_LEVELS", kMaxPyramidLevels);
  s += define("CR_PROJ_PARALLEL", int(projection::ProjectionType::Parallel));
  s += define("CR_PROJ_PLANAR", int(projection::ProjectionType::Planar));
  s += define("CR_PROJ_PERSPECTIVE", int(projection::ProjectionType::Perspective));
  s += define("CR_PROJ_AXIAL", int(projection::ProjectionType::Axial));
  s += define("CR_NORMALS_NONE", int(relief::NormalFormat::None));
  s += define("CR_NORMALS_OCT", int(relief::NormalFormat::Octahedral16));
  s += define("CR_NORMALS_RGBA", int(relief::NormalFormat::Rgba8));
  s += define("CR_COLORS_RGBA", int(relief::ColorFormat::Rgba8));
  s += define("CR_MAX_LIGHTS", kMaxLights);
  s += define("CR_GROUP_WIDTH", kGroupWidth);
  s += define("CR_GROUP_HEIGHT", kGroupHeight);
  return s;
}

/// The variant's switches as GLSL #defines.
inline std::string variantDefines(const ShaderVariant& v) {
  std::string s;
  auto flag = [&](bool on, const char* name) {
    if (on) s += std::string("#define ") + name + "\n";
  };
  flag(v.parallel, "CR_PARALLEL");
  flag(v.planar, "CR_PLANAR");
  flag(v.perspective, "CR_PERSPECTIVE");
  flag(v.axial, "CR_AXIAL");
  flag(v.octahedralNormals, "CR_OCT_NORMALS");
  flag(v.rgbaNormals, "CR_RGBA_NORMALS");
  flag(v.colors, "CR_COLORS");
  flag(v.skip && (v.parallel || v.planar), "CR_SKIP");
  flag(v.shadows, "CR_SHADOWS");
  flag(v.reflections, "CR_REFLECTIONS");
  flag(v.gather, "CR_GATHER");
  flag(v.channels & render::kColor, "CR_OUT_COLOR");
  flag(v.channels & render::kDepth, "CR_OUT_DEPTH");
  flag(v.channels & render::kNormal, "CR_OUT_NORMAL");
  flag(v.channels & render::kMask, "CR_OUT_MASK");
  flag(v.channels & render::kCell, "CR_OUT_CELL");
  flag(v.channels & render::kSteps, "CR_OUT_STEPS");
  return s;
}

/// The shader body: the embedded source, or for shader development the file named by
/// CELLRELIEF_SHADER_OVERRIDE (read at each compile, so an edit needs no rebuild).
inline std::string reliefTraceBody() {
  const char* path = std::getenv("CELLRELIEF_SHADER_OVERRIDE");
  if (!path || !*path) return std::string(kReliefTraceComp);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::FileNotFound, path, "CELLRELIEF_SHADER_OVERRIDE names a file that cannot be read");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The whole traversal shader for a variant: version, API switch, constants, variant, body. A
/// compute shader, or with `fragment` the fragment shader of the rasterized entry.
inline std::string reliefTraceShader(const ShaderVariant& v, bool vulkan, bool fragment = false) {
  std::string s = "#version 450\n";
  if (vulkan) s += "#define CR_VULKAN\n";
  if (fragment) s += "#define CR_FRAGMENT\n";
  s += traversalConstants();
  s += variantDefines(v);
  s += "#line 1\n";
  s += reliefTraceBody();
  return s;
}

}  // namespace cellrelief::gpu
