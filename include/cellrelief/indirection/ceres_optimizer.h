// SPDX-License-Identifier: MIT
/// @file ceres_optimizer.h
/// The quasi-conformal parameterization as a nonlinear least-squares problem solved by Ceres: the
/// alternative to the springs. Own header and own target (cellrelief::indirection_ceres) because it
/// brings Ceres and, through it, Eigen; the rest of the module is GLM only. Built only when Ceres is
/// found (CELLRELIEF_HAS_Ceres); `ceresAvailable()` lets callers ask without including this file.
///
/// Energy (chosen over spring lengths and over per-cell ARAP): the conformal energy of the map from
/// texture space to the relief surface, the sum over the 2 g^2 triangles of
///     (|a|^2 + |b|^2) / 2 - |a x b|  =  |a + n x b|^2 / 2,
/// with a = dP/ds, b = dP/dt the columns of the triangle's Jacobian (the same triangles and
/// Jacobians as measureDistortion) and n = a x b / |a x b| the triangle's unit normal: three
/// residuals (a + n x b) / lambda per triangle (lambda^2: the relief's surface area). n x b is b
/// turned by 90 degrees in the triangle's plane, so the residual vanishes iff the triangle is
/// mapped conformally (a square goes to a square). Why this one:
/// - It is the quasi-conformal goal of the paper, with no weights to tune, and it is the part of
///   Sander's L2 stretch that a parameterization controls: L2^2 = 1 + E_conformal / area, so the
///   optimizer lowers the figure the comparison reports; the springs and Ceres are compared on the
///   same surface with the same measure.
/// - Tried first and dropped: a per-cell "ARAP to a square of side lambda / g" residual
///   (|a| - lambda, |b| - lambda, a.b) pulls rows of cells onto near-vertical walls and raised L2
///   stretch above the identity's on the box relief; the plain Dirichlet energy (|a|^2 + |b|^2) / 2
///   also rewards moving vertices off bumps (the corner-sampled area shrinks), which on the Sponza
///   lion raised L2 stretch; a spring energy in Ceres sees shear only through the diagonals.
/// Area distortion is not in the energy (a conformal map may scale); it is measured and reported.
///
/// Derivatives are analytic: the height of each vertex is linearized with the exact gradient of the
/// bilinear relief (ReliefMap::gradientAt) into first-order Ceres Jets. A step that would flip a
/// triangle in the base plane is rejected (the cost function returns false and the trust region
/// shrinks), so the result has no flipped cell by construction, like the springs' step clamp.
/// Boundary as for the springs: corners fixed, edge vertices slide (ceres::SubsetManifold).
/// Multi-scale: g = 16 solved, refined piecewise linearly to 2g, solved again, ... up to g.
/// Minimizer: line search with L-BFGS directions by default (a step that would fold a triangle
/// makes the line search shorten it); Levenberg-Marquardt as an option, whose linear solver is a
/// sparse normal Cholesky (SuiteSparse CHOLMOD, the right tool for the 2D-grid sparsity; Eigen's
/// sparse Cholesky when SuiteSparse is absent) or any other Ceres linear solver type.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <ceres/ceres.h>

#include "cellrelief/indirection/grid.h"
#include "cellrelief/indirection/optimizer.h"
#include "cellrelief/indirection/optimizer_table.h"
#include "cellrelief/indirection/relief_map.h"

namespace cellrelief::indirection {

struct CeresOptions {
  int gridSize = 256;
  int startGridSize = 16;
  int maxIterations = 100;              ///< per coarse level
  int maxFinalIterations = 400;         ///< on the last level
  double functionTolerance = 1e-6;      ///< relative cost change that ends the last level
  double coarseFunctionTolerance = 1e-4;  ///< coarse levels only initialize the next one
  int threads = 0;                      ///< 0: one per hardware thread
  bool dogleg = false;                  ///< trust region: dogleg instead of Levenberg-Marquardt
  double initialTrustRegionRadius = 1e4;  ///< Ceres' default; smaller starts more cautiously
  /// Line search along L-BFGS directions (the default) instead of Levenberg-Marquardt with a sparse
  /// Cholesky factorization per iteration. Measured on the Sponza bricks at g = 128: LM spends 90%
  /// of its time in the factorization and half its steps are rejected (a triangle would fold), so
  /// after 51 iterations it is at L2 1.032 in 22 s; L-BFGS is at 1.033 after 1.3 s and 1.015 after
  /// 8 s. Set false (and maxFinalIterations ~50) for the plain LM solve.
  bool lbfgs = true;
  ceres::LinearSolverType linearSolver = ceres::SPARSE_NORMAL_CHOLESKY;
  bool verbose = false;                 ///< Ceres' per-iteration log on stdout
};

struct CeresReport {
  int iterations = 0, finalIterations = 0;
  double seconds = 0, initialCost = 0, finalCost = 0;
  std::string summary;  ///< Ceres' full report of the last level (timings per phase)
};

namespace detail {

/// The conformal residual of one triangle, (a + n x b) / lambda (and a barrier against folds); parameter blocks are its three vertices (u, v).
/// `corner` orders the vertices so that a = (p1 - p0) g and b = (p2 - p1) g (lower triangle) or
/// a = (p1 - p2) g and b = (p2 - p0) g (upper triangle), as in measureDistortion.
/// What a level's residuals read that changes with the map: the (filtered) relief and 1 / lambda.
/// A CeresSolver rebinds it between solves; the residual blocks stay.
struct LevelRelief {
  ReliefMap relief;
  double invLambda = 1;
};

class TriangleMetricCost final : public ceres::SizedCostFunction<4, 2, 2, 2> {
 public:
  TriangleMetricCost(const LevelRelief& level, int upper, double g) : mLevel(level), mUpper(upper), mG(g) {}

  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    using J = ceres::Jet<double, 6>;
    const ReliefMap& mRelief = mLevel.relief;
    J u[3], v[3], z[3];
    for (int k = 0; k < 3; ++k) {
      const float fu = float(p[k][0]), fv = float(p[k][1]);
      const Vec2f grad = mRelief.gradientAt(fu, fv);
      u[k] = J(p[k][0], 2 * k);
      v[k] = J(p[k][1], 2 * k + 1);
      z[k] = J(mRelief.heightAt(fu, fv));
      z[k].v[2 * k] = grad.x;
      z[k].v[2 * k + 1] = grad.y;
    }
    // Reject a step that flips the triangle in the base plane.
    const double area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                         (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    if (!(area2 > 0)) return false;
    J a[3], b[3];
    if (!mUpper) {
      a[0] = (u[1] - u[0]) * mG, a[1] = (v[1] - v[0]) * mG, a[2] = (z[1] - z[0]) * mG;
      b[0] = (u[2] - u[1]) * mG, b[1] = (v[2] - v[1]) * mG, b[2] = (z[2] - z[1]) * mG;
    } else {
      a[0] = (u[1] - u[2]) * mG, a[1] = (v[1] - v[2]) * mG, a[2] = (z[1] - z[2]) * mG;
      b[0] = (u[2] - u[0]) * mG, b[1] = (v[2] - v[0]) * mG, b[2] = (z[2] - z[0]) * mG;
    }
    // In-plane area relative to the identity's; a log barrier below kBarrier keeps the linear model
    // of Levenberg-Marquardt away from folds (hard rejection alone stalls it at the wall).
    const J det = (a[0] * b[1] - a[1] * b[0]);
    J barrier(0.0);
    if (det.a < kBarrier) barrier = log(kBarrier / det) * kBarrierWeight;
    // a + n x b, n the unit normal: |a + n x b|^2 / 2 = (|a|^2 + |b|^2) / 2 - |a x b|.
    const J c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    const J cn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    const J n[3] = {c[0] / cn, c[1] / cn, c[2] / cn};
    const J nb[3] = {n[1] * b[2] - n[2] * b[1], n[2] * b[0] - n[0] * b[2], n[0] * b[1] - n[1] * b[0]};
    const double w = std::sqrt(0.5) * mLevel.invLambda;
    const J r[4] = {(a[0] + nb[0]) * w, (a[1] + nb[1]) * w, (a[2] + nb[2]) * w, barrier};
    for (int i = 0; i < 4; ++i) residuals[i] = r[i].a;
    if (jacobians)
      for (int k = 0; k < 3; ++k)
        if (jacobians[k])
          for (int i = 0; i < 4; ++i) {
            jacobians[k][2 * i] = r[i].v[2 * k];
            jacobians[k][2 * i + 1] = r[i].v[2 * k + 1];
          }
    return true;
  }

 private:
  static constexpr double kBarrier = 0.05, kBarrierWeight = 1.0;
  const LevelRelief& mLevel;
  int mUpper;
  double mG;
};

/// Reports progress after every iteration of the last level (parameters updated in place).
class ProgressIteration final : public ceres::IterationCallback {
 public:
  ProgressIteration(const std::vector<double>& params, Grid& grid, OptimizerClock& clock,
                    const ProgressCallback& progress, bool last)
      : mParams(params), mGrid(grid), mClock(clock), mProgress(progress), mLast(last) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (!mProgress) return ceres::SOLVER_CONTINUE;
    const double seconds = mClock.seconds();
    for (std::size_t k = 0; k < mGrid.vertexCount(); ++k) {
      mGrid.u()[k] = float(mParams[2 * k]);
      mGrid.v()[k] = float(mParams[2 * k + 1]);
    }
    mClock.excluding(mProgress, mGrid,
                     Progress{mGrid.g(), s.iteration, seconds, s.cost, mLast, false});
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::vector<double>& mParams;
  Grid& mGrid;
  OptimizerClock& mClock;
  const ProgressCallback& mProgress;
  bool mLast;
};

}  // namespace detail

/// True when this build can solve with `type` (SuiteSparse or Eigen sparse present).
inline bool ceresSparseAvailable() {
  return ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ||
         ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE);
}

/// optimizeCeres as a stateful solver for repeated runs (geometry-central's function + solver
/// pairs, as SpringSolver): each level's Ceres problem (its 2 g^2 residual blocks, the boundary's
/// manifolds, the parameter storage) is built on first use and kept, and a later solve, on the same
/// map or another, rebinds the level's relief and pays only for the minimization. solve() also
/// takes a warm start: an earlier result (for example after the map's detail changed a little)
/// is refined from its own level up, instead of from the identity at the coarsest.
/// The options may change between solves (options()); levels are keyed by their size and by
/// whether they are the last, since only the last sees the unfiltered relief.
class CeresSolver {
 public:
  /// Throws Error for options out of range.
  explicit CeresSolver(CeresOptions options = {}) : mOptions(std::move(options)) { checkOptions(); }

  CeresOptions& options() { return mOptions; }
  const CeresOptions& options() const { return mOptions; }

  /// Solves multi-scale from the identity; returns M at options().gridSize.
  Grid solve(const ReliefMap& relief, const ProgressCallback& progress = {}, CeresReport* report = nullptr) {
    checkOptions();
    const std::vector<int> levels = multiScaleSchedule(mOptions.gridSize, mOptions.startGridSize);
    return solveLevels(relief, Grid(levels.front()), levels, progress, report);
  }

  /// Solves from `start` (a grid of at most options().gridSize cells per side): the levels of the
  /// schedule from start's size up, start resampled to the first of them where it is not one.
  Grid solve(const ReliefMap& relief, const Grid& start, const ProgressCallback& progress = {},
             CeresReport* report = nullptr) {
    checkOptions();
    if (start.g() > mOptions.gridSize || !start.isFinite())
      throw Error(ErrorKind::InvalidArgument, "ceres: a warm start of " + std::to_string(start.g()) +
                                                  " cells per side, finite and at most the grid size " +
                                                  std::to_string(mOptions.gridSize) + ", is needed");
    std::vector<int> levels;
    for (const int g : multiScaleSchedule(mOptions.gridSize, mOptions.startGridSize))
      if (g >= start.g()) levels.push_back(g);
    const Grid first = levels.front() == start.g() ? start : start.resampled(levels.front());
    return solveLevels(relief, first, levels, progress, report);
  }

  /// Levels whose problems are built (for tests and memory accounting).
  std::size_t builtLevels() const { return mLevels.size(); }

 private:
  struct Level {
    detail::LevelRelief data;
    std::vector<double> params;
    ceres::SubsetManifold fixU{2, {0}}, fixV{2, {1}};
    std::unique_ptr<ceres::Problem> problem;
  };

  void checkOptions() const {
    checkGridSize(mOptions.gridSize);
    if (mOptions.maxIterations < 1 || mOptions.maxFinalIterations < 1 || !(mOptions.functionTolerance > 0) ||
        mOptions.startGridSize < 2)
      throw Error(ErrorKind::InvalidArgument, "ceres: iterations and tolerances must be positive");
  }

  /// The level's problem over its own parameters: a residual block per triangle, corners fixed,
  /// edge vertices sliding.
  Level& levelOf(int g, bool last) {
    std::unique_ptr<Level>& slot = mLevels[{g, last}];
    if (slot) return *slot;
    slot = std::make_unique<Level>();
    Level& level = *slot;
    const int side = g + 1;
    level.params.assign(2 * std::size_t(side) * side, 0.0);
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    level.problem = std::make_unique<ceres::Problem>(po);
    ceres::Problem& problem = *level.problem;
    auto block = [&](int i, int j) { return &level.params[2 * (std::size_t(j) * side + i)]; };
    for (int j = 0; j < g; ++j)
      for (int i = 0; i < g; ++i)
        for (int t = 0; t < 2; ++t) {
          const auto& tri = kCellTriangles[t];
          problem.AddResidualBlock(new detail::TriangleMetricCost(level.data, t, g), nullptr,
                                   block(i + tri[0][0], j + tri[0][1]), block(i + tri[1][0], j + tri[1][1]),
                                   block(i + tri[2][0], j + tri[2][1]));
        }
    for (int j = 0; j <= g; ++j)
      for (int i = 0; i <= g; ++i) {
        const bool eu = i == 0 || i == g, ev = j == 0 || j == g;
        if (eu && ev)
          problem.SetParameterBlockConstant(block(i, j));
        else if (eu)
          problem.SetManifold(block(i, j), &level.fixU);
        else if (ev)
          problem.SetManifold(block(i, j), &level.fixV);
      }
    return level;
  }

  ceres::Solver::Options solverOptions(bool last) const {
    const CeresOptions& o = mOptions;
    ceres::Solver::Options so;
    so.linear_solver_type = o.linearSolver;
    if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE))
      so.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
    so.trust_region_strategy_type = o.dogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
    so.initial_trust_region_radius = o.initialTrustRegionRadius;
    if (o.lbfgs) {
      so.minimizer_type = ceres::LINE_SEARCH;
      so.line_search_direction_type = ceres::LBFGS;
    }
    so.num_threads = o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    so.max_num_iterations = last ? o.maxFinalIterations : o.maxIterations;
    so.function_tolerance = last ? o.functionTolerance : o.coarseFunctionTolerance;
    so.minimizer_progress_to_stdout = o.verbose;
    so.logging_type = o.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
    return so;
  }

  /// Solves `levels` in turn from `grid` (whose size is the first level's).
  Grid solveLevels(const ReliefMap& relief, Grid grid, const std::vector<int>& levels, const ProgressCallback& progress,
                   CeresReport* report) {
    OptimizerClock clock;
    CeresReport rep;
    const double invLambda = 1.0 / std::sqrt(relief.surfaceArea());
    for (std::size_t l = 0; l < levels.size(); ++l) {
      if (l > 0) grid = grid.resampled(levels[l]);
      const bool last = l + 1 == levels.size();
      const int g = grid.g();
      Level& level = levelOf(g, last);
      // A coarse level sees the relief filtered to 4 texels per cell: its corners would otherwise
      // sample texel-scale detail at random and the level would fit that noise (measured: on the
      // full-size Sponza bricks at g = 256 the result was worse than the identity without it).
      level.data.relief = last ? relief : downsample(relief, 4 * g);
      level.data.invLambda = invLambda;
      for (std::size_t k = 0; k < grid.vertexCount(); ++k) {
        level.params[2 * k] = grid.u()[k];
        level.params[2 * k + 1] = grid.v()[k];
      }
      ceres::Solver::Options so = solverOptions(last);
      detail::ProgressIteration callback(level.params, grid, clock, progress, last);
      if (progress && last) {
        so.update_state_every_iteration = true;
        so.callbacks.push_back(&callback);
      }
      ceres::Solver::Summary summary;
      ceres::Solve(so, level.problem.get(), &summary);
      if (!summary.IsSolutionUsable())
        throw Error(ErrorKind::InvalidInput, "ceres: no usable solution at g = " + std::to_string(g) + ": " + summary.message);
      for (std::size_t k = 0; k < grid.vertexCount(); ++k) {
        grid.u()[k] = float(level.params[2 * k]);
        grid.v()[k] = float(level.params[2 * k + 1]);
      }
      const int iterations = int(summary.iterations.size());
      rep.iterations += iterations;
      if (l == 0) rep.initialCost = summary.initial_cost;
      if (last) {
        rep.finalIterations = iterations;
        rep.finalCost = summary.final_cost;
        rep.summary = summary.FullReport();
      }
      clock.excluding(progress, grid, Progress{g, iterations, clock.seconds(), summary.final_cost, last, true});
    }
    rep.seconds = clock.seconds();
    if (report) *report = rep;
    return grid;
  }

  CeresOptions mOptions;
  std::map<std::pair<int, bool>, std::unique_ptr<Level>> mLevels;
};

/// Solves the metric least-squares problem multi-scale; returns M at options.gridSize (one solve of
/// a CeresSolver).
inline Grid optimizeCeres(const ReliefMap& relief, const CeresOptions& options = {},
                          const ProgressCallback& progress = {}, CeresReport* report = nullptr) {
  return CeresSolver(options).solve(relief, progress, report);
}

/// The Ceres optimizers for the table of optimizer_table.h: L-BFGS (the default minimizer) and
/// Levenberg-Marquardt with sparse Cholesky (the plain Ceres solve, fewer iterations).
inline std::vector<OptimizerEntry> ceresOptimizers() {
  auto entry = [](bool lm) {
    return [lm](const ReliefMap& relief, const OptimizerSettings& settings, const ProgressCallback& progress,
                int& iterations) {
      CeresOptions o;
      o.gridSize = settings.gridSize;
      if (lm) {
        o.lbfgs = false;
        o.maxIterations = 15;
        o.maxFinalIterations = 50;
      }
      CeresReport r;
      Grid grid = optimizeCeres(relief, o, progress, &r);
      iterations = r.iterations;
      return grid;
    };
  };
  return {{"ceres", "the conformal energy on the vertices' heights, Ceres L-BFGS", entry(false)},
          {"ceres-lm", "the same, Ceres Levenberg-Marquardt with sparse Cholesky", entry(true)}};
}

}  // namespace cellrelief::indirection
