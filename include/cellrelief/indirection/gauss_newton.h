// SPDX-License-Identifier: MIT
/// @file gauss_newton.h
/// The fast optimizer: the conformal energy of the map texture -> relief surface minimized by
/// damped Gauss-Newton steps (Levenberg-Marquardt) whose linear systems are solved by conjugate
/// gradients preconditioned with multigrid over the grid hierarchy (grid_multigrid.h). GLM and TBB
/// only: no Ceres, no Eigen.
///
/// Energy, per level of resolution g, over the 2 g^2 triangles of the grid (grid.h):
///     E = sum_T [ (a^T T a + b^T T b) / 2 - det(a, b) rho ] / lambda^2  +  sum_T barrier_T^2
/// with a, b the in-plane columns of the triangle's Jacobian texture -> base plane, T and rho the
/// relief's metric and area density averaged over cells (relief_metric.h: the energy sees every
/// texel's slope, not only the heights at the vertices) and integrated over the triangle by a
/// 3-point quadrature rule (a squeezed triangle sees only the relief it covers),
/// lambda^2 the relief's surface area, and barrier_T = log(tau / det) where the in-plane determinant
/// det (1 for the identity) is below tau = 5%, as in ceres_optimizer.h. The first term is the
/// Dirichlet energy on the relief, the second its area; their difference vanishes exactly when the
/// triangle is mapped conformally, and L2 stretch^2 = 1 + (their difference) / area.
///
/// Why Gauss-Newton on the Dirichlet part works: with the metric frozen, the Dirichlet energy is
/// quadratic in the vertices, and its Hessian H (2x2 blocks over a 9-point stencil, the metric in
/// the blocks) is symmetric positive definite; the area term is, in the limit, the same for every
/// map. Each step solves (H + mu diag H) d = -grad E with the exact gradient of the whole energy
/// (the metric following the centroids, area and barrier included). What H leaves out is how the
/// metric changes as a triangle moves, which on real height maps changes at the scale of a cell;
/// undamped (mu = 0) the steps then overshoot and the line search cut them to 1e-3 of their
/// length (measured on the Sponza lion). The damping mu adapts: divided by 3 after a step taken
/// whole, multiplied by 4 after a step the line search had to shorten.
///
/// Each outer iteration, as named steps: evaluate (E, gradient and H in one pass, cell rows of one
/// parity at a time so that threads write disjoint vertex rows), solveStep (damping, multigrid
/// hierarchy, CG to a relative residual `linearTolerance`), lineSearch (first capped below the
/// first fold of any triangle along the step, the root of its signed area, then halved until E
/// decreases enough), adaptDamping. Flip-free by construction: no accepted step leaves a triangle
/// with det below `minDeterminant`.
/// Multi-scale as the other optimizers: g = 16 first, refined to 2g, ..., each level with the
/// metric averaged over its own cells; the last level is then solved once more with the metric at
/// two texels per cell (`refinedMetricTexelsPerCell`).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/indirection/grid.h"
#include "cellrelief/indirection/grid_multigrid.h"
#include "cellrelief/indirection/optimizer.h"
#include "cellrelief/indirection/relief_map.h"
#include "cellrelief/indirection/relief_metric.h"

namespace cellrelief::indirection {

struct GaussNewtonOptions {
  int gridSize = 256;
  int startGridSize = 16;
  int maxIterations = 40;               ///< per coarse level
  int maxFinalIterations = 100;         ///< on the last level
  double functionTolerance = 1e-5;      ///< relative decrease of E that ends the last level
  double coarseFunctionTolerance = 1e-3;  ///< coarse levels only initialize the next one
  int patience = 2;                     ///< iterations in a row below the tolerance
  double linearTolerance = 0.05;        ///< relative residual of each CG solve
  int maxLinearIterations = 40;
  double barrier = 0.05;                ///< tau: in-plane det below which the barrier acts
  double minDeterminant = 1e-3;         ///< no accepted step leaves a triangle below this det
  int metricTexelsPerCell = 1;          ///< resolution of the averaged metric, per grid cell
  /// After the last level, solve it once more with the metric at this many texels per cell (0:
  /// not). The cell-sized metric is smooth enough to descend from the identity robustly; the finer
  /// one then resolves the relief inside the cells. Measured per texel at g = 256: lion 1.0650 ->
  /// 1.0563, bricks 1.3020 -> 1.2662, DirectX rocks 1.0030 -> 1.0021; starting with the finer metric
  /// instead raised the paper's raised box (192^2, g = 48) from 2.32 to 2.77.
  int refinedMetricTexelsPerCell = 2;
  double damping = 0.1;                 ///< the initial Levenberg-Marquardt mu
  /// Points at which each triangle samples the metric (1: the centroid, 3: Strang-Fix, 6:
  /// Dunavant). A squeezed triangle then sees only the relief it covers: on the paper's raised box
  /// (192^2, g = 48) the per-texel L2 stretch went 2.32 -> 2.61 with the centroid and 2.32 -> 1.20
  /// with 3 points; on the Sponza bricks at g = 256, 1.320 in 3.0 s against 1.302 in 1.4 s.
  int quadraturePoints = 3;
};

struct GaussNewtonReport {
  int iterations = 0, finalIterations = 0, linearIterations = 0;
  double seconds = 0, initialEnergy = 0, finalEnergy = 0;
  bool converged = false;  ///< the last level met the tolerance (not the iteration cap)
};

/// Stateful: keeps its arrays between solves, for repeated runs on one map (height scale changes)
/// or many maps of one size.
class GaussNewtonSolver {
 public:
  explicit GaussNewtonSolver(GaussNewtonOptions options = {}) : mO(options) { checkOptions(); }
  const GaussNewtonOptions& options() const { return mO; }

  /// Solves multi-scale from the identity; returns M at options().gridSize.
  Grid solve(const ReliefMap& relief, const ProgressCallback& progress = {},
             GaussNewtonReport* report = nullptr) {
    OptimizerClock clock;
    GaussNewtonReport rep;
    mInvLambda2 = 1.0 / relief.surfaceArea();
    const std::vector<int> levels = multiScaleSchedule(mO.gridSize, mO.startGridSize);
    const int perCell = mO.metricTexelsPerCell;
    const int refine = mO.refinedMetricTexelsPerCell;
    // No finer than twice the height map: there is no detail beyond it (and at g = 4096 the
    // metric would otherwise take gigabytes).
    const int texels = std::max(relief.width(), relief.height());
    auto resolution = [&](int perCellTexels, int g) {
      return std::min(perCellTexels * g, std::max(g, 2 * texels));
    };
    const ReliefMetric fine(relief, resolution(std::max(perCell, refine), levels.back()));
    Grid grid(levels.front());
    for (std::size_t l = 0; l < levels.size(); ++l) {
      if (l > 0) grid = grid.resampled(levels[l]);
      const bool last = l + 1 == levels.size();
      mMetric = fine.averaged(resolution(perCell, grid.g()));
      solveLevel(grid, last && !refine, clock, progress, rep);
      if (last && refine) {
        mMetric = fine.averaged(resolution(refine, grid.g()));
        solveLevel(grid, true, clock, progress, rep);
      }
    }
    rep.seconds = clock.seconds();
    if (report) *report = rep;
    return grid;
  }

 private:
  void checkOptions() const {
    checkGridSize(mO.gridSize);
    auto bad = [](const std::string& what) {
      throw Error(ErrorKind::InvalidArgument, "gauss-newton: " + what);
    };
    if (mO.startGridSize < 2) bad("start grid size must be at least 2");
    if (mO.maxIterations < 1 || mO.maxFinalIterations < 1 || mO.maxLinearIterations < 1 ||
        mO.patience < 1)
      bad("iteration counts must be >= 1");
    if (!(mO.functionTolerance > 0) || !(mO.coarseFunctionTolerance > 0) ||
        !(mO.linearTolerance > 0) || !(mO.linearTolerance < 1))
      bad("tolerances must be in (0, 1)");
    if (!(mO.barrier > 0) || !(mO.minDeterminant > 0) || !(mO.minDeterminant < mO.barrier))
      bad("need 0 < minDeterminant < barrier");
    if (mO.metricTexelsPerCell < 1 || mO.metricTexelsPerCell > 8)
      bad("metric texels per cell must be 1 to 8");
    if (mO.refinedMetricTexelsPerCell < 0 || mO.refinedMetricTexelsPerCell > 8)
      bad("refined metric texels per cell must be 0 (none) to 8");
    if (mO.quadraturePoints != 1 && mO.quadraturePoints != 3 && mO.quadraturePoints != 6)
      bad("quadrature points must be 1, 3 or 6");
    if (!(mO.damping >= 0) || !std::isfinite(mO.damping)) bad("damping must be >= 0");
  }

  // ---- one level ---------------------------------------------------------------------------------

  void solveLevel(Grid& grid, bool last, OptimizerClock& clock, const ProgressCallback& progress,
                  GaussNewtonReport& rep) {
    mG = grid.g();
    mSide = mG + 1;
    const std::size_t n = grid.vertexCount();
    mP.resize(2 * n);
    for (std::size_t k = 0; k < n; ++k) mP[2 * k] = grid.u()[k], mP[2 * k + 1] = grid.v()[k];
    mGradient.assign(2 * n, 0.0);
    mRowEnergy.assign(std::size_t(mG), 0.0);
    mDamping = mO.damping;
    const double tolerance = last ? mO.functionTolerance : mO.coarseFunctionTolerance;
    const int maxIterations = last ? mO.maxFinalIterations : mO.maxIterations;
    double energy = evaluate(mP, true);
    if (!(energy < HUGE_VAL))
      throw Error(ErrorKind::InvalidInput, "gauss-newton: the start grid at g = " +
                                               std::to_string(mG) + " has a folded cell");
    if (rep.iterations == 0) rep.initialEnergy = energy;
    int calm = 0, it = 0;
    bool converged = false;
    while (it < maxIterations) {
      rep.linearIterations += solveStep();
      const double next = lineSearch(energy);
      ++it;
      const double decrease = energy - next;
      if (!(decrease > 0)) {  // no step lowers E: a minimum to the resolution of E
        converged = true;
        break;
      }
      adaptDamping();
      calm = decrease < tolerance * std::abs(next) ? calm + 1 : 0;
      energy = evaluate(mP, true);
      if (progress) {
        writeGrid(grid);
        clock.excluding(progress, grid, Progress{mG, it, clock.seconds(), energy, last, false});
      }
      if (calm >= mO.patience) {
        converged = true;
        break;
      }
    }
    writeGrid(grid);
    rep.iterations += it;
    if (last) {
      rep.finalIterations = it;
      rep.finalEnergy = energy;
      rep.converged = converged;
    }
    clock.excluding(progress, grid, Progress{mG, it, clock.seconds(), energy, last, true});
  }

  /// mStep = -(H + mu diag H)^-1 grad E by multigrid-preconditioned CG; returns the CG iterations.
  int solveStep() {
    if (mDamping > 0) mHessian.dampDiagonal(mDamping);
    mMultigrid.build(mHessian);
    std::vector<double>& rhs = mRhs;
    rhs.resize(mGradient.size());
    for (std::size_t k = 0; k < rhs.size(); ++k) rhs[k] = -mGradient[k];
    mHessian.mask(rhs);
    return solveConjugateGradients(mHessian, mMultigrid, rhs, mStep, mO.linearTolerance,
                                   mO.maxLinearIterations)
        .iterations;
  }

  /// Trust the quadratic model more after a whole step, less after a shortened one.
  void adaptDamping() {
    if (mO.damping <= 0) return;
    mDamping = mHalvings == 0 ? std::max(mDamping / 3, 1e-6) : std::min(mDamping * 4, 1e6);
  }

  void writeGrid(Grid& grid) const {
    for (std::size_t k = 0; k < grid.vertexCount(); ++k) {
      grid.u()[k] = float(mP[2 * k]);
      grid.v()[k] = float(mP[2 * k + 1]);
    }
  }

  // ---- the energy, its gradient and the Gauss-Newton Hessian -------------------------------------

  struct Vec3 {
    double x, y, z;
  };
  static Vec3 sub(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  static Vec3 scaled(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
  static Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  }
  static double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

  /// E at positions `p` (+inf when a triangle's det is below minDeterminant); with `derivatives`,
  /// also mGradient and mHessian (and the constraints of the boundary).
  double evaluate(const std::vector<double>& p, bool derivatives) {
    if (derivatives) {
      std::fill(mGradient.begin(), mGradient.end(), 0.0);
      mHessian.reset(mSide);
    }
    // Cell rows of one parity at a time: row j writes vertex rows j and j + 1 only.
    for (int parity = 0; parity < 2; ++parity) {
      const std::size_t rows = std::size_t(mG - parity + 1) / 2;
      parallelFor(0, rows, [&](std::size_t r) {
        const int j = parity + 2 * int(r);
        double sum = 0;
        for (int i = 0; i < mG && sum < HUGE_VAL; ++i)
          for (int t = 0; t < 2; ++t) sum += triangle(p, i, j, t, derivatives);
        mRowEnergy[std::size_t(j)] = sum;
      }, 2);
    }
    double energy = 0;
    for (double e : mRowEnergy) energy += e;  // in order: the same sum on any thread count
    if (!(energy < HUGE_VAL)) return HUGE_VAL;
    if (derivatives) constrainBoundary();
    return energy;
  }

  /// Corners fixed; edge vertices slide along their edge.
  void constrainBoundary() {
    for (int j = 0; j <= mG; ++j)
      for (int i = 0; i <= mG; ++i) {
        const std::uint8_t bits =
            std::uint8_t((i == 0 || i == mG ? 1 : 0) | (j == 0 || j == mG ? 2 : 0));
        if (!bits) continue;
        const std::size_t k = std::size_t(j) * mSide + i;
        mHessian.setFixed(k, bits);
        if (bits & 1) mGradient[2 * k] = 0;
        if (bits & 2) mGradient[2 * k + 1] = 0;
      }
    mHessian.applyConstraints();
  }

  /// The energy of triangle t of cell (i, j); with `derivatives`, adds its gradient and its
  /// Gauss-Newton Hessian blocks (only rows of the cell's two vertex rows are written).
  double triangle(const std::vector<double>& p, int i, int j, int t, bool derivatives) {
    const auto& tri = kCellTriangles[t];
    std::size_t k[3];
    double x[3], y[3];
    for (int c = 0; c < 3; ++c) {
      k[c] = std::size_t(j + tri[c][1]) * mSide + std::size_t(i + tri[c][0]);
      x[c] = p[2 * k[c]], y[c] = p[2 * k[c] + 1];
    }
    // In-plane columns of the Jacobian: a = g (p[ea1] - p[ea0]), b = g (p[eb1] - p[eb0]), with
    // a = g (p1 - p0), b = g (p2 - p1) on the lower triangle, g (p1 - p2), g (p2 - p0) on the upper.
    const double g = mG;
    const int ea0 = t == 0 ? 0 : 2, ea1 = 1, eb0 = t == 0 ? 1 : 0, eb1 = 2;
    const double ax = g * (x[ea1] - x[ea0]), ay = g * (y[ea1] - y[ea0]);
    const double bx = g * (x[eb1] - x[eb0]), by = g * (y[eb1] - y[eb0]);
    const double det = ax * by - ay * bx;
    if (!(det >= mO.minDeterminant)) return HUGE_VAL;
    // The metric averaged over the triangle by a quadrature rule over points inside it, so that a
    // squeezed triangle sees only the relief it covers.
    const QuadratureRule& rule = quadratureRule();
    MetricSample m{0, 0, 0, 0}, du[kMaxQuadrature], dv[kMaxQuadrature];
    for (int q = 0; q < rule.count; ++q) {
      const double* bc = rule.barycentric[q];
      const double qu = bc[0] * x[0] + bc[1] * x[1] + bc[2] * x[2];
      const double qv = bc[0] * y[0] + bc[1] * y[1] + bc[2] * y[2];
      const MetricSample s =
          mMetric.at(qu, qv, derivatives ? &du[q] : nullptr, derivatives ? &dv[q] : nullptr);
      const double w = rule.weight[q];
      m.xx += w * s.xx, m.xy += w * s.xy, m.yy += w * s.yy, m.rho += w * s.rho;
    }
    // Dirichlet (a^T T a + b^T T b) / 2 and area det rho, both on the relief (relief_metric.h).
    auto quad = [](const MetricSample& s, double px, double py) {
      return s.xx * px * px + 2 * s.xy * px * py + s.yy * py * py;
    };
    const double dirichlet = 0.5 * (quad(m, ax, ay) + quad(m, bx, by));
    double energy = (dirichlet - det * m.rho) * mInvLambda2;
    double barrier = 0;
    if (det < mO.barrier) {
      barrier = std::log(mO.barrier / det);
      energy += barrier * barrier;
    }
    if (!derivatives) return energy;

    // dE/da and dE/db; d det/da = (b.y, -b.x), d det/db = (-a.y, a.x); dE/d det below.
    const double dDet = -m.rho * mInvLambda2 + (barrier > 0 ? -2 * barrier / det : 0.0);
    const double gax = (m.xx * ax + m.xy * ay) * mInvLambda2 + dDet * by;
    const double gay = (m.xy * ax + m.yy * ay) * mInvLambda2 - dDet * bx;
    const double gbx = (m.xx * bx + m.xy * by) * mInvLambda2 - dDet * ay;
    const double gby = (m.xy * bx + m.yy * by) * mInvLambda2 + dDet * ax;
    // The metric follows the quadrature points: dE/dq, to the vertices by the barycentric weights.
    double gx[3] = {0, 0, 0}, gy[3] = {0, 0, 0};
    for (int q = 0; q < rule.count; ++q) {
      const double w = rule.weight[q] * mInvLambda2;
      const double dqu = (0.5 * (quad(du[q], ax, ay) + quad(du[q], bx, by)) - det * du[q].rho) * w;
      const double dqv = (0.5 * (quad(dv[q], ax, ay) + quad(dv[q], bx, by)) - det * dv[q].rho) * w;
      for (int c = 0; c < 3; ++c) {
        gx[c] += rule.barycentric[q][c] * dqu;
        gy[c] += rule.barycentric[q][c] * dqv;
      }
    }
    gx[ea1] += g * gax, gy[ea1] += g * gay, gx[ea0] -= g * gax, gy[ea0] -= g * gay;
    gx[eb1] += g * gbx, gy[eb1] += g * gby, gx[eb0] -= g * gbx, gy[eb0] -= g * gby;
    for (int c = 0; c < 3; ++c) {
      mGradient[2 * k[c]] += gx[c];
      mGradient[2 * k[c] + 1] += gy[c];
    }
    // Gauss-Newton blocks of the Dirichlet part, the metric frozen: g^2 / lambda^2 [T -T; -T T]
    // per edge.
    const double w = g * g * mInvLambda2;
    const Block2 metric{m.xx * w, m.xy * w, m.xy * w, m.yy * w};
    auto addEdge = [&](int e0, int e1) {
      const int di = tri[e1][0] - tri[e0][0], dj = tri[e1][1] - tri[e0][1];
      mHessian.add(k[e0], 0, 0, metric);
      mHessian.add(k[e1], 0, 0, metric);
      mHessian.add(k[e0], di, dj, metric * -1.0);
      mHessian.add(k[e1], -di, -dj, metric * -1.0);
    };
    addEdge(ea0, ea1);
    addEdge(eb0, eb1);
    // Gauss-Newton of the barrier: 2 grad(r) grad(r)^T, r = log(tau / det), grad r = -grad det / det.
    if (barrier > 0) {
      double ddx[3] = {0, 0, 0}, ddy[3] = {0, 0, 0};
      ddx[ea1] += g * by, ddy[ea1] -= g * bx, ddx[ea0] -= g * by, ddy[ea0] += g * bx;
      ddx[eb1] -= g * ay, ddy[eb1] += g * ax, ddx[eb0] += g * ay, ddy[eb0] -= g * ax;
      const double s = 2 * (1 + barrier) / (det * det);
      for (int c = 0; c < 3; ++c)
        for (int q = 0; q < 3; ++q)
          mHessian.add(k[c], tri[q][0] - tri[c][0], tri[q][1] - tri[c][1],
                       Block2{s * ddx[c] * ddx[q], s * ddx[c] * ddy[q], s * ddy[c] * ddx[q],
                              s * ddy[c] * ddy[q]});
    }
    return energy;
  }

  // ---- quadrature over a triangle ----------------------------------------------------------------

  static constexpr int kMaxQuadrature = 6;
  struct QuadratureRule {
    int count;
    double barycentric[kMaxQuadrature][3];
    double weight[kMaxQuadrature];
  };
  const QuadratureRule& quadratureRule() const {
    static const QuadratureRule centroid{1, {{1.0 / 3, 1.0 / 3, 1.0 / 3}}, {1.0}};
    // Strang-Fix: exact for quadratics.
    static const QuadratureRule three{3,
                                      {{2.0 / 3, 1.0 / 6, 1.0 / 6},
                                       {1.0 / 6, 2.0 / 3, 1.0 / 6},
                                       {1.0 / 6, 1.0 / 6, 2.0 / 3}},
                                      {1.0 / 3, 1.0 / 3, 1.0 / 3}};
    // Dunavant degree 4.
    static const QuadratureRule six{6,
                                    {{0.108103018168070, 0.445948490915965, 0.445948490915965},
                                     {0.445948490915965, 0.108103018168070, 0.445948490915965},
                                     {0.445948490915965, 0.445948490915965, 0.108103018168070},
                                     {0.816847572980459, 0.091576213509771, 0.091576213509771},
                                     {0.091576213509771, 0.816847572980459, 0.091576213509771},
                                     {0.091576213509771, 0.091576213509771, 0.816847572980459}},
                                    {0.223381589678011, 0.223381589678011, 0.223381589678011,
                                     0.109951743655322, 0.109951743655322, 0.109951743655322}};
    return mO.quadraturePoints >= 6 ? six : mO.quadraturePoints >= 3 ? three : centroid;
  }

  // ---- the line search --------------------------------------------------------------------------

  /// The largest alpha in (0, inf) before a triangle's in-plane area reaches zero along mStep.
  double foldingStep() const {
    double limit = HUGE_VAL;
    const double g2 = double(mG) * mG;
    for (int j = 0; j < mG; ++j)
      for (int i = 0; i < mG; ++i)
        for (const auto& tri : kCellTriangles) {
          double x[3], y[3], dx[3], dy[3];
          for (int c = 0; c < 3; ++c) {
            const std::size_t k = std::size_t(j + tri[c][1]) * mSide + std::size_t(i + tri[c][0]);
            x[c] = mP[2 * k], y[c] = mP[2 * k + 1];
            dx[c] = mStep[2 * k], dy[c] = mStep[2 * k + 1];
          }
          // det(alpha) = g^2 cross(e1 + alpha f1, e2 + alpha f2) = c0 + c1 alpha + c2 alpha^2.
          const double e1x = x[1] - x[0], e1y = y[1] - y[0], e2x = x[2] - x[0], e2y = y[2] - y[0];
          const double f1x = dx[1] - dx[0], f1y = dy[1] - dy[0], f2x = dx[2] - dx[0],
                       f2y = dy[2] - dy[0];
          const double c0 = g2 * (e1x * e2y - e1y * e2x);
          const double c1 = g2 * (e1x * f2y - e1y * f2x + f1x * e2y - f1y * e2x);
          const double c2 = g2 * (f1x * f2y - f1y * f2x);
          limit = std::min(limit, firstPositiveRoot(c0, c1, c2));
        }
    return limit;
  }

  static double firstPositiveRoot(double c0, double c1, double c2) {
    if (std::abs(c2) < 1e-14 * (std::abs(c1) + std::abs(c0))) return c1 < 0 ? -c0 / c1 : HUGE_VAL;
    const double disc = c1 * c1 - 4 * c2 * c0;
    if (disc < 0) return HUGE_VAL;
    const double sq = std::sqrt(disc);
    const double q = -0.5 * (c1 + (c1 >= 0 ? sq : -sq));
    double r1 = q / c2, r2 = q != 0 ? c0 / q : HUGE_VAL;
    if (r1 > r2) std::swap(r1, r2);
    if (r1 > 0) return r1;
    if (r2 > 0) return r2;
    return HUGE_VAL;
  }

  /// Moves mP along mStep; returns the new energy (the old one when no step was accepted) and
  /// records in mHalvings how often the step was halved.
  double lineSearch(double energy) {
    const std::size_t n = mP.size();
    double slope = 0;
    for (std::size_t k = 0; k < n; ++k) slope += mGradient[k] * mStep[k];
    if (!(slope < 0)) return energy;  // not a descent direction (CG failed): stop
    double alpha = std::min(1.0, 0.9 * foldingStep());
    mTrial.resize(n);
    for (int halving = 0; halving < 30; ++halving, alpha *= 0.5) {
      for (std::size_t k = 0; k < n; ++k) mTrial[k] = mP[k] + alpha * mStep[k];
      const double next = evaluate(mTrial, false);
      if (next <= energy + 1e-4 * alpha * slope) {
        mP.swap(mTrial);
        mHalvings = halving;
        return next;
      }
    }
    return energy;
  }

  GaussNewtonOptions mO;
  int mG = 0, mSide = 0;
  double mInvLambda2 = 1, mDamping = 0;
  int mHalvings = 0;
  std::vector<double> mP, mTrial, mStep, mGradient, mRowEnergy, mRhs;
  ReliefMetric mMetric;
  GridStencil mHessian;
  GridMultigrid mMultigrid;
};

/// Gauss-Newton with multigrid-preconditioned conjugate gradients (see the file comment);
/// returns M at options.gridSize. Throws Error for options out of range.
inline Grid optimizeGaussNewton(const ReliefMap& relief, const GaussNewtonOptions& options = {},
                                const ProgressCallback& progress = {},
                                GaussNewtonReport* report = nullptr) {
  GaussNewtonSolver solver(options);
  return solver.solve(relief, progress, report);
}

}  // namespace cellrelief::indirection
