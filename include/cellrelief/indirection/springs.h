// SPDX-License-Identifier: MIT
/// @file springs.h
/// The spring optimizer of McGuire & Whitson, *Indirection Mapping for Quasi-Conformal Relief
/// Texturing* (I3D 2008), sections 3.2-3.5: a (g+1)^2 grid of vertices in the base plane, each
/// joined to its eight neighbours by springs whose lengths are measured *on the relief surface*, is
/// relaxed until the total force stops changing; coarse grids first (g = 16, doubled up to g).
///
/// Reading of the paper, where its printed formulas do not survive:
/// - Rest lengths. The printed "1/(g sqrt 2)" (diagonal) and "1/g^2 |(x,y) - (a,b)|" are garbled:
///   the first is shorter than an axis spring and the second has the wrong power of g. A spring
///   joining the vertices of grid indices (x, y) and (a, b) should rest at the texture-space distance
///   of its ends, |(x, y) - (a, b)| / g: 1/g for the four axis springs (they keep scale) and
///   sqrt(2)/g for the four diagonals (they keep the right angles of the cells, which axis springs
///   alone do not resist shearing). `restScale` multiplies them (1 = the paper).
/// - Force "of order k = 6": f(L) = stiffness * ((L/L0)^k - 1) / k. For k = 1 this is Hooke's law
///   with stiffness per unit of relative stretch; for k = 6 long springs pull much harder than short
///   ones push, which spreads the stretch of steep slopes over their neighbourhood and keeps cells
///   from collapsing. The direction is that of the 3D chord between the ends; only its in-plane
///   (u, v) components move a vertex, and the vertex is then "snapped" back on the surface (its
///   height is re-read at the new (u, v)).
/// - Step rule (equation 5): each vertex moves by F / K, its in-plane force over the sum K of the
///   spring stiffnesses dF/dL at it (a Jacobi-Newton step; for Hooke springs at rest it is F/(8k)),
///   then clamped to a third of the smallest base-plane height of the triangles around it. That
///   clamp is what guarantees that no triangle flips: if no vertex of a triangle moves more than a
///   third of its smallest height, the triangle keeps its orientation.
/// - Surface distance (equation 6): the straight segment between the ends in (u, v) is walked in n
///   steps and the lengths of the 3D chords between successive surface points summed. The step is a
///   quarter of a height-map texel, n clamped to 2..10 (`integrationStepTexels`, `min/maxSteps`).
/// - Each spring is computed once per iteration (four per vertex: right, up, up-right, up-left) into
///   its own array, and a second pass gathers the forces per vertex: no two threads write the same
///   word, so the TBB loops need no atomics and the result does not depend on the thread count.
/// - Boundary: corners fixed, edge vertices slide along their edge, so the map covers the square.
/// - Convergence: the total in-plane force F_t; a level is done when |F_t - F_t-1| < tolerance F_t
///   for `patience` iterations in a row (or F_t vanishes, or `maxIterations` is reached).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "cellrelief/core/parallel.h"
#include "cellrelief/indirection/grid.h"
#include "cellrelief/indirection/optimizer.h"
#include "cellrelief/indirection/relief_map.h"

namespace cellrelief::indirection {

/// Which part of a spring's 3D force moves a vertex (see the file comment).
enum class SpringForce {
  InPlane,  ///< the paper: the (u, v) components of the 3D force
  Tangent,  ///< the force's work along the surface, F_uv + F_z grad z: the spring energy's gradient
};

struct SpringOptions {
  SpringForce force = SpringForce::InPlane;
  int gridSize = 256;             ///< the target g
  int startGridSize = 16;         ///< the first level of the multi-scale schedule
  float stiffness = 1.0f;         ///< per unit of relative stretch
  int forceOrder = 6;             ///< k in f = stiffness ((L/L0)^k - 1) / k
  float restScale = 1.0f;         ///< rest length = restScale |(x,y) - (a,b)| / g
  float integrationStepTexels = 0.25f;  ///< step of the surface-length integral, in texels
  int minSteps = 2, maxSteps = 10;      ///< clamp of the number of integration steps
  float maxStepFraction = 1.0f / 3.0f;  ///< of the smallest incident triangle height
  float relaxation = 1.0f;        ///< over-relaxation factor of the step F/K (1: the plain step)
  double tolerance = 1e-3;        ///< relative change of the total force that ends the last level
  double coarseTolerance = 1e-2;  ///< the same for the coarse levels (they only initialize)
  int patience = 3;               ///< iterations in a row below the tolerance
  int maxIterations = 2000;       ///< per level
  int reportEvery = 10;           ///< iterations between progress callbacks
};

struct SpringReport {
  int iterations = 0;         ///< all levels together
  int finalIterations = 0;    ///< on the last level
  double seconds = 0;         ///< callbacks excluded
  double totalForce = 0;      ///< at the end
  bool converged = false;     ///< the last level met the tolerance (not the iteration cap)
};

/// The rest length of the spring between grid indices (x, y) and (x + di, y + dj) at resolution g:
/// restScale |(di, dj)| / g (1/g for axis springs, sqrt(2)/g for diagonals; see the file comment).
inline float springRestLength(int di, int dj, int g, float restScale = 1.0f) {
  return restScale * std::sqrt(float(di * di + dj * dj)) / float(g);
}

namespace detail {

/// The arrays of one level, kept between iterations.
class SpringLevel {
 public:
  /// The buffers of a level of g x g cells; bind() says which relief and grid a step works on.
  SpringLevel(const SpringOptions& o, int g) : mOptions(o), mG(g), mSide(g + 1) {
    const std::size_t n = std::size_t(mSide) * std::size_t(mSide);
    mHeight.resize(n);
    mSlopeX.resize(n);
    mSlopeY.resize(n);
    mNewU.resize(n);
    mNewV.resize(n);
    for (int s = 0; s < 4; ++s) {
      mForceXOnA[s].assign(n, 0.0f);
      mForceYOnA[s].assign(n, 0.0f);
      mStiffnessA[s].assign(n, 0.0f);
      mForceXOnB[s].assign(n, 0.0f);
      mForceYOnB[s].assign(n, 0.0f);
      mStiffnessB[s].assign(n, 0.0f);
    }
    mCellMinHeight.assign(std::size_t(mG) * mG, 0.0f);
    mRowForce.assign(mSide, 0.0);
    mRowBad.assign(mSide, 0);
    for (int s = 0; s < 4; ++s) mRest[s] = springRestLength(kDi[s], kDj[s], mG, o.restScale);
  }

  /// The relief and the grid (of this level's size) that step() relaxes; both must outlive the steps.
  void bind(const ReliefMap& relief, Grid& grid) {
    if (grid.g() != mG)
      throw Error(ErrorKind::InvalidArgument, "springs: a level of g = " + std::to_string(mG) +
                                                  " bound to a grid of g = " + std::to_string(grid.g()));
    mRelief = &relief;
    mGrid = &grid;
    mInvStep = 1.0f / (mOptions.integrationStepTexels * relief.texelSize());
  }

  /// The four forward springs of a vertex: right, up, up-right, up-left.
  static constexpr int kDi[4] = {1, 0, 1, -1}, kDj[4] = {0, 1, 1, 1};

  /// One relaxation step; returns the total in-plane force before the step.
  double step() {
    const int side = mSide, g = mG;
    const float* u = mGrid->u().data();
    const float* v = mGrid->v().data();
    // Pass 1: heights at the vertices (the snap) and the smallest triangle height of each cell.
    parallelForRange(0, std::size_t(side), [&](std::size_t rowBegin, std::size_t rowEnd) {
      for (int j = int(rowBegin); j != int(rowEnd); ++j) {
        for (int i = 0; i < side; ++i) {
          const std::size_t k = std::size_t(j) * side + i;
          mHeight[k] = mRelief->heightAt(u[k], v[k]);
          const Vec2f grad = mRelief->gradientAt(u[k], v[k]);
          mSlopeX[k] = grad.x;
          mSlopeY[k] = grad.y;
        }
        if (j == g) continue;
        for (int i = 0; i < g; ++i) mCellMinHeight[std::size_t(j) * g + i] = cellMinHeight(i, j);
      }
    }, 8);
    // Pass 2: the four forward springs of every vertex, each computed once.
    if (mOptions.force == SpringForce::InPlane)
      computeSprings<SpringForce::InPlane>(u, v);
    else
      computeSprings<SpringForce::Tangent>(u, v);
    // Pass 3: gather per vertex, project on the boundary, step, clamp.
    const float maxFraction = mOptions.maxStepFraction, omega = mOptions.relaxation;
    parallelForRange(0, std::size_t(side), [&](std::size_t rowBegin, std::size_t rowEnd) {
          for (int j = int(rowBegin); j != int(rowEnd); ++j) {
            double sum = 0;  // per row, summed in order below: the same total on any thread count
            for (int i = 0; i < side; ++i) {
              const std::size_t k = std::size_t(j) * side + i;
              float fx = 0, fy = 0, vertexStiffness = 0;
              for (int s = 0; s < 4; ++s) {
                if (i + kDi[s] >= 0 && i + kDi[s] <= g && j + kDj[s] <= g) {  // forward: pulls a
                  fx += mForceXOnA[s][k];
                  fy += mForceYOnA[s][k];
                  vertexStiffness += mStiffnessA[s][k];
                }
                const int ai = i - kDi[s], aj = j - kDj[s];
                if (ai >= 0 && ai <= g && aj >= 0) {  // backward: equal and opposite on b
                  const std::size_t a = std::size_t(aj) * side + ai;
                  fx += mForceXOnB[s][a];
                  fy += mForceYOnB[s][a];
                  vertexStiffness += mStiffnessB[s][a];
                }
              }
              if (i == 0 || i == g) fx = 0;
              if (j == 0 || j == g) fy = 0;
              const float f = std::sqrt(fx * fx + fy * fy);
              sum += f;
              float dx = vertexStiffness > 0 ? omega * fx / vertexStiffness : 0;
              float dy = vertexStiffness > 0 ? omega * fy / vertexStiffness : 0;
              float limit = HUGE_VALF;
              for (int cj = j - 1; cj <= j; ++cj)
                for (int ci = i - 1; ci <= i; ++ci)
                  if (ci >= 0 && ci < g && cj >= 0 && cj < g)
                    limit = std::min(limit, mCellMinHeight[std::size_t(cj) * g + ci]);
              limit *= maxFraction;
              const float d = std::sqrt(dx * dx + dy * dy);
              if (d > limit) {
                const float shrink = limit > 0 ? limit / d : 0.0f;
                dx *= shrink;
                dy *= shrink;
              }
              mNewU[k] = u[k] + dx;
              mNewV[k] = v[k] + dy;
            }
            mRowForce[j] = sum;
          }
        }, 4);
    double total = 0;
    for (double f : mRowForce) total += f;
    mGrid->u().swap(mNewU);
    mGrid->v().swap(mNewV);
    undoCollapsingSteps();
    return total;
  }

 private:
  /// The step clamp keeps triangles from flipping in exact arithmetic, but on near-vertical walls
  /// cells are squeezed towards zero width and rounding could still fold one. A triangle whose new
  /// area would be non-positive, or would shrink below kMinAreaRatio of an identity cell's, has the steps of
  /// its vertices undone (repeated until none is left; the old grid had none).
  /// The smallest triangle a step may leave, relative to the identity's. Far enough from float
  /// rounding that refining to 2g (which quarters areas) cannot fold a triangle either.
  static constexpr float kMinAreaRatio = 1e-2f;

  void undoCollapsingSteps() {
    const int g = mG, side = mSide;
    const float minArea2 = kMinAreaRatio / (float(g) * float(g));
    const float* u = mGrid->u().data();  // the new positions (swapped in)
    const float* v = mGrid->v().data();
    const float* ou = mNewU.data();     // the old ones
    const float* ov = mNewV.data();
    mBad.assign(std::size_t(g) * g, 0);
    for (int round = 0; round < 16; ++round) {
      parallelForRange(0, std::size_t(g), [&](std::size_t rowBegin, std::size_t rowEnd) {
        for (int j = int(rowBegin); j != int(rowEnd); ++j) {
          std::uint8_t any = 0;
          for (int i = 0; i < g; ++i) {
            std::uint8_t bad = 0;
            for (const auto& tri : kCellTriangles) {
              std::size_t k[3];
              for (int c = 0; c < 3; ++c) k[c] = std::size_t(j + tri[c][1]) * side + i + tri[c][0];
              const float a = signedArea2({u[k[0]], v[k[0]]}, {u[k[1]], v[k[1]]}, {u[k[2]], v[k[2]]});
              if (a > minArea2) continue;
              const float b = signedArea2({ou[k[0]], ov[k[0]]}, {ou[k[1]], ov[k[1]]}, {ou[k[2]], ov[k[2]]});
              if (!(a > 0) || a < b) bad = 1;
            }
            mBad[std::size_t(j) * g + i] = bad;
            any |= bad;
          }
          mRowBad[j] = any;
        }
      }, 4);
      if (std::none_of(mRowBad.begin(), mRowBad.begin() + g, [](std::uint8_t b) { return b; }))
        return;
      parallelForRange(0, std::size_t(side), [&](std::size_t rowBegin, std::size_t rowEnd) {
        for (int j = int(rowBegin); j != int(rowEnd); ++j)
          for (int i = 0; i < side; ++i) {
            bool bad = false;
            for (int cj = j - 1; cj <= j; ++cj)
              for (int ci = i - 1; ci <= i; ++ci)
                if (ci >= 0 && ci < g && cj >= 0 && cj < g && mBad[std::size_t(cj) * g + ci]) bad = true;
            if (!bad) continue;
            const std::size_t k = std::size_t(j) * side + i;
            mGrid->u()[k] = ou[k];
            mGrid->v()[k] = ov[k];
          }
      }, 4);
    }
  }

  /// Twice the area over the longest edge, the smallest height, of the cell's two triangles.
  float cellMinHeight(int i, int j) const {
    float h = HUGE_VALF;
    for (const auto& tri : kCellTriangles) {
      const Vec2f p0 = mGrid->vertex(i + tri[0][0], j + tri[0][1]);
      const Vec2f p1 = mGrid->vertex(i + tri[1][0], j + tri[1][1]);
      const Vec2f p2 = mGrid->vertex(i + tri[2][0], j + tri[2][1]);
      const float a2 = signedArea2(p0, p1, p2);
      const float e = std::max({glm::length(p1 - p0), glm::length(p2 - p1), glm::length(p0 - p2)});
      h = std::min(h, e > 0 ? std::max(a2, 0.0f) / e : 0.0f);
    }
    return h;
  }

  /// The spring from a to b: the in-plane force on a, and how fast that force changes when a (ka)
  /// or b (kb) moves in the plane: the spring stiffness dF/dL times (dL/d(in-plane move))^2, bounded
  /// by (|in-plane part of the chord| + |vertical part| |slope at the end|)^2. The slope term matters:
  /// on a slope s an in-plane move lengthens the spring up to sqrt(1 + s^2) times faster, and a step
  /// that ignored it would overshoot and oscillate on steep reliefs.
  template <SpringForce Force>
  void computeSprings(const float* u, const float* v) {
    const int side = mSide, g = mG;
    parallelForRange(0, std::size_t(side), [&](std::size_t rowBegin, std::size_t rowEnd) {
      for (int j = int(rowBegin); j != int(rowEnd); ++j)
        for (int i = 0; i < side; ++i) {
          const std::size_t a = std::size_t(j) * side + i;
          for (int s = 0; s < 4; ++s) {
            const int bi = i + kDi[s], bj = j + kDj[s];
            if (bi < 0 || bi > g || bj > g) continue;
            const std::size_t b = std::size_t(bj) * side + bi;
            spring<Force>(a, b, mRest[s], s, u, v);
          }
        }
    }, 4);
  }

  /// The force policy is a template parameter: chosen once per step, not per spring.
  template <SpringForce Force>
  void spring(std::size_t a, std::size_t b, float rest, int s, const float* u, const float* v) {
    const float ua = u[a], va = v[a], za = mHeight[a], ub = u[b], vb = v[b], zb = mHeight[b];
    const float du = ub - ua, dv = vb - va;
    const float l2sq = du * du + dv * dv, l2 = std::sqrt(l2sq);
    const int n = std::clamp(int(std::ceil(l2 * mInvStep)), mOptions.minSteps, mOptions.maxSteps);
    const float inv = 1.0f / float(n), stepSq = l2sq * inv * inv;
    float length = 0, pz = za;
    for (int step = 1; step < n; ++step) {
      const float t = float(step) * inv;
      const float z = mRelief->heightAt(ua + t * du, va + t * dv);
      length += std::sqrt(stepSq + (z - pz) * (z - pz));
      pz = z;
    }
    length += std::sqrt(stepSq + (zb - pz) * (zb - pz));
    const float chord = std::sqrt(l2sq + (zb - za) * (zb - za));
    const float e = length / rest;
    const int p = mOptions.forceOrder;
    float ep1 = 1.0f;  // e^(p-1) by multiplication: std::pow was a third of the iteration time
    for (int k = 1; k < p; ++k) ep1 *= e;
    const float f = mOptions.stiffness * (ep1 * e - 1.0f) / float(p);
    const float scale = chord > 0 ? f / chord : 0.0f, dz = zb - za;
    // The 3D force on a is scale (du, dv, dz); on b its opposite.
    if constexpr (Force == SpringForce::InPlane) {
      mForceXOnA[s][a] = scale * du;
      mForceYOnA[s][a] = scale * dv;
      mForceXOnB[s][a] = -scale * du;
      mForceYOnB[s][a] = -scale * dv;
    } else {  // the work of the 3D force along the surface: F_xy + F_z grad z at each end
      mForceXOnA[s][a] = scale * (du + dz * mSlopeX[a]);
      mForceYOnA[s][a] = scale * (dv + dz * mSlopeY[a]);
      mForceXOnB[s][a] = -scale * (du + dz * mSlopeX[b]);
      mForceYOnB[s][a] = -scale * (dv + dz * mSlopeY[b]);
    }
    const float k = mOptions.stiffness * std::max(ep1, 1.0f) / rest;
    const float inPlane = chord > 0 ? l2 / chord : 1.0f;
    const float vertical = chord > 0 ? std::abs(dz) / chord : 0.0f;
    const float sa = std::sqrt(mSlopeX[a] * mSlopeX[a] + mSlopeY[a] * mSlopeY[a]);
    const float sb = std::sqrt(mSlopeX[b] * mSlopeX[b] + mSlopeY[b] * mSlopeY[b]);
    mStiffnessA[s][a] = k * (inPlane + vertical * sa) * (inPlane + vertical * sa);
    mStiffnessB[s][a] = k * (inPlane + vertical * sb) * (inPlane + vertical * sb);
  }

  SpringOptions mOptions;
  const ReliefMap* mRelief = nullptr;
  Grid* mGrid = nullptr;
  int mG, mSide;
  float mRest[4];
  float mInvStep;
  std::vector<float> mHeight, mSlopeX, mSlopeY, mNewU, mNewV, mCellMinHeight;
  std::vector<double> mRowForce;
  std::vector<std::uint8_t> mBad, mRowBad;
  std::vector<float> mForceXOnA[4], mForceYOnA[4], mForceXOnB[4], mForceYOnB[4], mStiffnessA[4], mStiffnessB[4];
};

inline void checkSpringOptions(const SpringOptions& o) {
  checkGridSize(o.gridSize);
  auto bad = [](const std::string& what) { throw Error(ErrorKind::InvalidArgument, what); };
  if (o.startGridSize < 2) bad("springs: start grid size must be at least 2");
  if (!(o.stiffness > 0) || !std::isfinite(o.stiffness)) bad("springs: stiffness must be > 0");
  if (o.forceOrder < 1 || o.forceOrder > 12) bad("springs: force order must be 1 to 12");
  if (!(o.restScale > 0) || !std::isfinite(o.restScale)) bad("springs: rest scale must be > 0");
  if (!(o.integrationStepTexels > 0)) bad("springs: integration step must be > 0");
  if (o.minSteps < 1 || o.maxSteps < o.minSteps) bad("springs: need 1 <= minSteps <= maxSteps");
  if (!(o.maxStepFraction > 0) || o.maxStepFraction > 0.5f)
    bad("springs: maxStepFraction must be in (0, 0.5]");
  if (!(o.tolerance > 0) || !(o.coarseTolerance > 0)) bad("springs: tolerance must be > 0");
  if (!(o.relaxation > 0) || o.relaxation >= 2) bad("springs: relaxation must be in (0, 2)");
  if (o.maxIterations < 1 || o.patience < 1 || o.reportEvery < 1)
    bad("springs: iteration counts must be >= 1");
}

}  // namespace detail

/// The spring network as a stateful solver (geometry-central's function + solver pair): each
/// level's buffers stay allocated between solves, so repeated runs at one set of options (a map
/// re-solved after an edit, maps of one size in a batch) allocate nothing after the first.
class SpringSolver {
 public:
  /// Throws Error for options out of range.
  explicit SpringSolver(SpringOptions options = {}) : mOptions(std::move(options)) {
    detail::checkSpringOptions(mOptions);
  }
  const SpringOptions& options() const { return mOptions; }

  /// Relaxes the network multi-scale from the identity and returns M at options().gridSize.
  /// `progress` (optional) sees the grid every `reportEvery` iterations and at the end of each level.
  Grid solve(const ReliefMap& relief, const ProgressCallback& progress = {}, SpringReport* report = nullptr) {
    OptimizerClock clock;
    SpringReport rep;
    const std::vector<int> levels = multiScaleSchedule(mOptions.gridSize, mOptions.startGridSize);
    Grid grid(levels.front());
    for (std::size_t l = 0; l < levels.size(); ++l) {
      if (l > 0) grid = grid.resampled(levels[l]);
      const bool last = l + 1 == levels.size();
      detail::SpringLevel& level = levelOf(grid.g());
      level.bind(relief, grid);
      relaxLevel(level, grid, last, clock, progress, rep);
    }
    rep.seconds = clock.seconds();
    if (report) *report = rep;
    return grid;
  }

 private:
  detail::SpringLevel& levelOf(int g) {
    auto it = mLevels.find(g);
    if (it == mLevels.end()) it = mLevels.emplace(g, std::make_unique<detail::SpringLevel>(mOptions, g)).first;
    return *it->second;
  }

  /// Steps one level until its force is negligible or stops changing.
  void relaxLevel(detail::SpringLevel& level, const Grid& grid, bool last, OptimizerClock& clock,
                  const ProgressCallback& progress, SpringReport& rep) const {
    double previous = -1, force = 0;
    int calm = 0, it = 0;
    bool converged = false;
    for (; it < mOptions.maxIterations; ++it) {
      force = level.step();
      if (!std::isfinite(force))
        throw Error(ErrorKind::InvalidInput, "springs: the force became non-finite at g = " +
                                                 std::to_string(grid.g()));
      const double nVerts = double(grid.vertexCount());
      if (force <= 1e-9 * nVerts * mOptions.stiffness) {
        converged = true;
        ++it;
        break;
      }
      const double tolerance = last ? mOptions.tolerance : mOptions.coarseTolerance;
      calm = previous >= 0 && std::abs(force - previous) < tolerance * force ? calm + 1 : 0;
      previous = force;
      if (calm >= mOptions.patience) {
        converged = true;
        ++it;
        break;
      }
      if (progress && (it + 1) % mOptions.reportEvery == 0)
        clock.excluding(progress, grid, Progress{grid.g(), it + 1, clock.seconds(), force, last, false});
    }
    rep.iterations += it;
    if (last) {
      rep.finalIterations = it;
      rep.converged = converged;
      rep.totalForce = force;
    }
    clock.excluding(progress, grid, Progress{grid.g(), it, clock.seconds(), force, last, true});
  }

  SpringOptions mOptions;
  std::map<int, std::unique_ptr<detail::SpringLevel>> mLevels;
};

/// Relaxes the spring network multi-scale and returns the map M at resolution options.gridSize
/// (a SpringSolver used once). Throws Error for options out of range.
inline Grid relaxSprings(const ReliefMap& relief, const SpringOptions& options = {},
                         const ProgressCallback& progress = {}, SpringReport* report = nullptr) {
  return SpringSolver(options).solve(relief, progress, report);
}

}  // namespace cellrelief::indirection
