// SPDX-License-Identifier: MIT
/// @file trace_options.h
/// The traversal's parameters and the constants its CPU and GPU implementations share, in a small
/// header of their own: render options and every backend include this, not the tracer (which
/// brings OpenVDB). The GPU backends write these values into the preamble of the one GLSL source
/// (backends/gpu/shader_preamble.h), so the CPU reference and the shaders cannot drift apart.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>

namespace cellrelief::trace {

struct TraceOptions {
  int minLinearSteps = 4;      ///< linear samples per cell for a ray along the projection direction
  int maxLinearSteps = 64;     ///< at most, for a ray grazing the face
  float stepsPerTexel = 1.5f;  ///< linear samples per texel the ray's projection crosses
  int binarySteps = 8;      ///< bisections after the linear search, then one secant step
  bool skipEmptySpace = true;  ///< min-pyramid skipping and exact texel tests in parallel/planar cells
  /// The same pyramid in perspective and axial cells (with skipEmptySpace; not in interior cells):
  /// nodes the ray provably stays in front of are skipped, the rest sampled per texel.
  bool skipCentralCells = true;
  bool operator==(const TraceOptions&) const = default;
};

/// A search policy decides how many linear samples a ray segment inside a cell gets.
/// Requirements: a static `linearSteps(options, footprintTexels)` returning the count (>= 2),
/// where footprintTexels is how many texels of the maps the segment's projection crosses.
template <class S>
concept SearchPolicy = requires(const TraceOptions& o, double footprint) {
  { S::linearSteps(o, footprint) } -> std::convertible_to<int>;
};

/// Footprint-balanced linear search: minLinearSteps plus stepsPerTexel for each texel crossed,
/// at most maxLinearSteps.
struct BalancedSearch {
  static int linearSteps(const TraceOptions& o, double footprintTexels) {
    const double steps = o.minLinearSteps + o.stepsPerTexel * footprintTexels;
    return std::clamp(int(std::ceil(steps)), 2, std::max(2, o.maxLinearSteps));
  }
};

/// The paper's plain search: maxLinearSteps samples in every cell, whatever the ray.
struct UniformSearch {
  static int linearSteps(const TraceOptions& o, double) { return std::max(2, o.maxLinearSteps); }
};

/// Constants of the traversal algorithm that every implementation (the CPU tracer, the GLSL
/// shader) must use alike. Their meaning is explained where the tracer uses them.
namespace constants {
/// |f| on a projection line without surface: beyond any real value (at most sqrt(3) in a cell).
inline constexpr float kEmptyField = 4.0f;
/// A field within this many sample spacings of zero counts as "near the surface" at a cell face.
inline constexpr float kNearFaceSamples = 2.0f;
/// Points of the segment (beyond its start) that measure its footprint on the maps.
inline constexpr int kFootprintProbes = 3;
/// Linear steps in a segment that misses its cell's reach (relief::CellReach), where the field
/// keeps one side: its exit, which carries the side on (and would still show a change of side
/// the reach had missed; a step in the middle, as the search policies' fewest, found none).
inline constexpr int kLinearStepsOutsideReach = 1;
/// The skip walk's floor on each advance, against rounding stalls (segment parameter units).
inline constexpr float kSkipProgress = 1e-6f;
/// The skip walk's nudge across node boundaries, in ulps of the coordinate.
inline constexpr float kNudgeUlps = 4.0f;
/// Field samples per texel cell that the skip walk of a central cell cannot skip.
inline constexpr int kCentralTexelSamples = 2;
/// Bisection steps when rounding defeats the closed-form root of the texel quadratic.
inline constexpr int kRootBisections = 40;
/// A quadratic coefficient below this fraction of the others' magnitude is treated as zero.
inline constexpr float kQuadraticEpsilon = 1e-12f;
/// Shading of a hit on an empty sample looks this many samples around for a filled one.
inline constexpr int kShadeSearchRadius = 2;
/// Secondary rays start this many sample spacings off the surface.
inline constexpr float kSurfaceOffsetSamples = 2.0f;
}  // namespace constants

}  // namespace cellrelief::trace
