// SPDX-License-Identifier: MIT
/// @file shader_preamble.h
/// What the GPU backends prepend to the one GLSL source (backends/shaders/relief_trace.comp):
/// the traversal constants, written from the C++ values the CPU tracer uses
/// (trace/trace_options.h, relief/relief_model.h, gpu_layout.h), so the two cannot drift; and
/// the variant: the projection types, maps and features a scene uses, so that a scene pays only
/// for what it has (a shader without the branches, loops and bindings it would never take).
#pragma once

#include <array>
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
  bool skip = true, skipCentral = true, shadows = true, reflections = true;
  bool polycube = true;  ///< polycube-mapped meshes
  bool geotex = true;    ///< geometry-texture models
  bool parallax = true;  ///< relief surfaces (parallax occlusion mapping)
  unsigned channels = render::kAllChannels;
  bool gather = true;  ///< read the 2 x 2 samples with one textureGather (measured: 12% faster on llvmpipe, same image) instead of 4 fetches

  static ShaderVariant general() { return {}; }
  /// Only what this scene and these options use.
  static ShaderVariant specialized(const SceneFeatures& f, const trace::TraceOptions& trace, bool shadows,
                                   bool reflections, unsigned channels) {
    ShaderVariant v;
    v.parallel = f.parallel;
    v.planar = f.planar;
    v.perspective = f.perspective;
    v.axial = f.axial;
    v.octahedralNormals = f.octahedralNormals;
    v.rgbaNormals = f.rgbaNormals;
    v.colors = f.colors;
    v.skip = trace.skipEmptySpace && f.pyramid && (f.parallel || f.planar);
    v.skipCentral = trace.skipEmptySpace && trace.skipCentralCells && f.pyramid && (f.perspective || f.axial);
    v.channels = channels;
    v.shadows = shadows && (channels & render::kColor);
    v.reflections = reflections && (channels & render::kColor);
    v.polycube = f.polycube;
    v.geotex = f.geotex;
    v.parallax = f.parallax;
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
    if (skipCentral) s += ":skipc";
    if (shadows) s += ":shadows";
    if (reflections) s += ":mirror";
    if (polycube) s += ":polycube";
    if (geotex) s += ":geotex";
    if (parallax) s += ":parallax";
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
  s += define("CR_LINEAR_STEPS_OUTSIDE_REACH", c::kLinearStepsOutsideReach);
  s += define("CR_SKIP_PROGRESS", glslFloat(c::kSkipProgress));
  s += define("CR_CENTRAL_TEXEL_SAMPLES", c::kCentralTexelSamples);
  s += define("CR_NUDGE_ULPS", glslFloat(c::kNudgeUlps));
  s += define("CR_FLOAT_EPSILON", glslFloat(std::numeric_limits<float>::epsilon()));
  s += define("CR_ROOT_BISECTIONS", c::kRootBisections);
  s += define("CR_QUADRATIC_EPSILON", glslFloat(c::kQuadraticEpsilon));
  s += define("CR_SHADE_SEARCH_RADIUS", c::kShadeSearchRadius);
  s += define("CR_SURFACE_OFFSET_SAMPLES", glslFloat(c::kSurfaceOffsetSamples));
  s += define("CR_GAMMA3", glslFloat(roundingGamma<float>(3)));
  s += detail::defineUint("CR_CENTRE_INSIDE_BIT", relief::CellRecord::kCentreInside);
  s += detail::defineUint("CR_OPEN_SURFACE_BIT", relief::CellRecord::kOpenSurface);
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
  {
    namespace w = polycube_words;
    s += define("CR_PC_MESH_INFO_WORDS", w::kMeshInfoWords);
    s += define("CR_PC_NODE_WORDS", w::kNodeWords);
    s += define("CR_PC_TRIANGLE_WORDS", w::kTriangleWords);
    s += define("CR_PC_VERTEX_WORDS", w::kVertexWords);
    s += define("CR_PC_LUT_ENTRY_WORDS", w::kLutEntryWords);
    s += define("CR_PC_EMPTY_CASE", int(w::kEmptyCase));
    s += define("CR_PC_NODE_OFFSET", w::kNodeOffset);
    s += define("CR_PC_TRIANGLE_OFFSET", w::kTriangleOffset);
    s += define("CR_PC_VERTEX_OFFSET", w::kVertexOffset);
    s += define("CR_PC_LUT_OFFSET", w::kLutOffset);
    s += define("CR_PC_LUT_ORIGIN", w::kLutOrigin);
    s += define("CR_PC_LUT_SIZE", w::kLutSize);
    s += define("CR_PC_TEXELS", w::kTexels);
    s += define("CR_PC_LEVELS", w::kLevels);
    s += define("CR_PC_TILES_PER_ROW", w::kTilesPerRow);
    s += define("CR_PC_USE", w::kUse);
    s += define("CR_PC_FILTER", w::kFilter);
    s += define("CR_PC_SURFACE_OFFSET", w::kSurfaceOffset);
    s += define("CR_PC_LEVEL_ROW", w::kLevelRow);
    s += define("CR_PC_BARYCENTRIC_SLACK", glslFloat(kBarycentricSlack<float>));
    s += define("CR_PC_MIN_FOOTPRINT_COSINE", glslFloat(c::kMinFootprintCosine));
    s += define("CR_PC_LOCATE_TOLERANCE", glslFloat(c::kLocateTolerance));
  }
  {
    namespace w = geotex_words;
    const trace::GeoTexTraceOptions search;
    s += define("CR_GT_MODEL_INFO_WORDS", w::kModelInfoWords);
    s += define("CR_GT_CHART_WORDS", w::kChartWords);
    s += define("CR_GT_NODE_WORDS", w::kNodeWords);
    s += define("CR_GT_CHART_OFFSET", w::kChartOffset);
    s += define("CR_GT_NODE_OFFSET", w::kNodeOffset);
    s += define("CR_GT_PRIMITIVE_OFFSET", w::kPrimitiveOffset);
    s += define("CR_GT_HEIGHT_OFFSET", w::kHeightOffset);
    s += define("CR_GT_NORMAL_OFFSET", w::kNormalOffset);
    s += define("CR_GT_COLOR_OFFSET", w::kColorOffset);
    s += define("CR_GT_EMPTY_CODE", w::kEmptyCode);
    s += define("CR_GT_SURFACE_OFFSET", w::kSurfaceOffset);
    s += define("CR_GT_ORIGIN", w::kOrigin);
    s += define("CR_GT_ROW_X", w::kRowX);
    s += define("CR_GT_ROW_Y", w::kRowY);
    s += define("CR_GT_ROW_Z", w::kRowZ);
    s += define("CR_GT_BOX_SIZE", w::kBoxSize);
    s += define("CR_GT_HEIGHT_SCALE", w::kHeightScale);
    s += define("CR_GT_WIDTH", w::kWidth);
    s += define("CR_GT_HEIGHT", w::kHeight);
    s += define("CR_GT_FIRST_TEXEL", w::kFirstTexel);
    s += define("CR_GT_PYRAMID", w::kPyramid);
    s += define("CR_GT_STEPS_PER_TEXEL", glslFloat(search.linearStepsPerTexel));
    s += define("CR_GT_MIN_LINEAR_STEPS", search.minLinearSteps);
    s += define("CR_GT_BINARY_STEPS", search.binarySteps);
    s += define("CR_GT_NEUTRAL_GREY", glslFloat(trace::GeoTexTracer<float>::kNeutralGrey));
  }
  {
    namespace w = parallax_words;
    namespace p = trace::parallax_constants;
    s += define("CR_PX_SURFACE_WORDS", w::kSurfaceWords);
    s += define("CR_PX_ORIGIN", w::kOrigin);
    s += define("CR_PX_ROW_U", w::kRowU);
    s += define("CR_PX_ROW_V", w::kRowV);
    s += define("CR_PX_ROW_W", w::kRowW);
    s += define("CR_PX_TOP", w::kTop);
    s += define("CR_PX_HEIGHT_WIDTH", w::kHeightWidth);
    s += define("CR_PX_HEIGHT_HEIGHT", w::kHeightHeight);
    s += define("CR_PX_REPEAT", w::kRepeat);
    s += define("CR_PX_HEIGHT_OFFSET", w::kHeightOffset);
    s += define("CR_PX_INDIRECTION_OFFSET", w::kIndirectionOffset);
    s += define("CR_PX_COLOR_OFFSET", w::kColorOffset);
    s += define("CR_PX_NORMAL_OFFSET", w::kNormalOffset);
    s += define("CR_PX_CHECKER_SQUARES", w::kCheckerSquares);
    s += define("CR_PX_SURFACE_OFFSET", w::kSurfaceOffset);
    s += define("CR_PX_MESH_NODE_OFFSET", w::kMeshNodeOffset);
    s += define("CR_PX_MESH_TRIANGLE_OFFSET", w::kMeshTriangleOffset);
    s += define("CR_PX_NODE_WORDS", w::kNodeWords);
    s += define("CR_PX_CORNER_WORDS", w::kCornerWords);
    s += define("CR_PX_TRIANGLE_WORDS", w::kTriangleWords);
    s += define("CR_PX_MIN_FRAME_SPAN", glslFloat(p::kMinFrameSpan));
    s += define("CR_PX_STEPS_PER_TEXEL", glslFloat(p::kStepsPerTexel));
    s += define("CR_PX_MIN_LINEAR_STEPS", p::kMinLinearSteps);
    s += define("CR_PX_MAX_LINEAR_STEPS", p::kMaxLinearSteps);
    s += define("CR_PX_REFINE_STEPS", p::kRefineSteps);
    s += define("CR_PX_CHECKER_LIGHT", "vec3(" + glslFloat(p::kCheckerLight[0]) + ", " + glslFloat(p::kCheckerLight[1]) +
                                           ", " + glslFloat(p::kCheckerLight[2]) + ")");
    s += define("CR_PX_CHECKER_DARK", "vec3(" + glslFloat(p::kCheckerDark[0]) + ", " + glslFloat(p::kCheckerDark[1]) +
                                          ", " + glslFloat(p::kCheckerDark[2]) + ")");
  }
  return s;
}

/// The variant's switches, in the order of their Vulkan specialization constant ids (the SPIR-V
/// modules are built with this table, so an id means the same switch on both sides).
inline constexpr const char* kVariantSwitchNames[] = {
    "CR_PARALLEL",    "CR_PLANAR",       "CR_PERSPECTIVE", "CR_AXIAL",    "CR_OCT_NORMALS",
    "CR_RGBA_NORMALS", "CR_COLORS",      "CR_SKIP",        "CR_SHADOWS",  "CR_REFLECTIONS",
    "CR_GATHER",      "CR_OUT_COLOR",    "CR_OUT_DEPTH",   "CR_OUT_NORMAL", "CR_OUT_MASK",
    "CR_OUT_CELL",    "CR_OUT_STEPS",    "CR_SKIP_CENTRAL", "CR_POLYCUBE",  "CR_GEOTEX",
    "CR_PARALLAX"};
inline constexpr int kVariantSwitchCount = int(std::size(kVariantSwitchNames));

/// The value of each switch of kVariantSwitchNames for a variant.
inline std::array<bool, kVariantSwitchCount> variantSwitches(const ShaderVariant& v) {
  return {v.parallel,
          v.planar,
          v.perspective,
          v.axial,
          v.octahedralNormals,
          v.rgbaNormals,
          v.colors,
          v.skip && (v.parallel || v.planar),
          v.shadows,
          v.reflections,
          v.gather,
          (v.channels & render::kColor) != 0,
          (v.channels & render::kDepth) != 0,
          (v.channels & render::kNormal) != 0,
          (v.channels & render::kMask) != 0,
          (v.channels & render::kCell) != 0,
          (v.channels & render::kSteps) != 0,
          v.skipCentral && (v.perspective || v.axial),
          v.polycube,
          v.geotex,
          v.parallax};
}

/// The variant's switches as GLSL constants (OpenGL): `const bool CR_SKIP = false;`.
inline std::string variantConstants(const ShaderVariant& v) {
  const auto on = variantSwitches(v);
  std::string s;
  for (int i = 0; i < kVariantSwitchCount; ++i)
    s += std::string("const bool ") + kVariantSwitchNames[i] + (on[std::size_t(i)] ? " = true;\n" : " = false;\n");
  return s;
}

/// The switches as specialization constants (Vulkan), every one true by default (the general
/// shader); a pipeline sets them per variant.
inline std::string variantSpecializationConstants() {
  std::string s;
  for (int i = 0; i < kVariantSwitchCount; ++i)
    s += "layout(constant_id = " + std::to_string(i) + ") const bool " + kVariantSwitchNames[i] + " = true;\n";
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

/// The whole traversal shader for OpenGL: version, constants, the variant's switches, body. A
/// compute shader, or with `fragment` the fragment shader of the rasterized entry.
inline std::string reliefTraceShader(const ShaderVariant& v, bool fragment = false) {
  std::string s = "#version 450\n";
  if (fragment) s += "#define CR_FRAGMENT\n";
  s += traversalConstants();
  s += variantConstants(v);
  s += "#line 1\n";
  s += reliefTraceBody();
  return s;
}

/// The traversal shader the Vulkan backend's SPIR-V is compiled from at build time (by glslc,
/// through backends/vulkan/tools/write_vulkan_shaders.cpp): the embedded body, the variant as
/// specialization constants.
inline std::string reliefTraceShaderForVulkan(bool fragment) {
  std::string s = "#version 450\n#define CR_VULKAN\n";
  if (fragment) s += "#define CR_FRAGMENT\n";
  s += traversalConstants();
  s += variantSpecializationConstants();
  s += "#line 1\n";
  s += std::string(kReliefTraceComp);
  return s;
}

/// The cover of the rasterized entry (cell_cover.vert) with the traversal's constants, for
/// OpenGL at run time or (`vulkan`) for glslc at build time: it reads the same chart records.
inline std::string cellCoverShader(bool vulkan = false) {
  std::string s = vulkan ? "#version 450\n#define CR_VULKAN\n" : "#version 450\n";
  s += traversalConstants();
  s += "#line 1\n";
  s += std::string(kCellCoverVert);
  return s;
}

}  // namespace cellrelief::gpu
