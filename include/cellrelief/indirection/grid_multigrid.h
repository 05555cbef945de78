// SPDX-License-Identifier: MIT
/// @file grid_multigrid.h
/// Linear algebra for the Gauss-Newton optimizer (gauss_newton.h): a symmetric positive definite
/// operator on the (g+1)^2 vertices of a Grid with two unknowns (u, v) per vertex, stored as a
/// 9-point stencil of 2x2 blocks; a geometric multigrid V-cycle over the grid hierarchy as its
/// preconditioner; and conjugate gradients.
///
/// Why this shape: the Hessian of the relief's Dirichlet energy couples each vertex with its
/// neighbours in the cells around it (the 9-point stencil) and couples u with v through the slope
/// (the 2x2 blocks). A direct sparse factorization of 132k unknowns costs about a second
/// (measured in docs/indirection.md); a V-cycle costs a few stencil sweeps and makes the conjugate
/// gradients converge in a number of iterations that does not grow with g.
/// - Coarse grids: coarse vertex I sits on fine vertex min(2I, g), so any g coarsens (odd g ends
///   with one coarse cell of width 1); the prolongation is bilinear in the fine indices, the
///   restriction its transpose, and the coarse operator the Galerkin product P^T A P, which keeps
///   the 9-point stencil and the symmetry.
/// - Fixed unknowns (the optimizer's corners and the sliding edges) are identity rows and columns;
///   on coarse grids the same components are fixed (the boundary maps onto the boundary).
/// - Smoother: block Gauss-Seidel in four colours (the parities of i and j: no two vertices of one
///   colour share a 9-point stencil), so each colour runs in parallel; forward before the coarse
///   correction and backward after it, which keeps the preconditioner symmetric as CG needs.
/// - The coarsest grid (g <= 8) is solved by a dense Cholesky factorization.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/parallel.h"

namespace cellrelief::indirection {

/// A 2x2 matrix [xx xy; yx yy].
struct Block2 {
  double xx = 0, xy = 0, yx = 0, yy = 0;
  Block2& operator+=(const Block2& o) {
    xx += o.xx, xy += o.xy, yx += o.yx, yy += o.yy;
    return *this;
  }
  Block2 operator*(double s) const { return {xx * s, xy * s, yx * s, yy * s}; }
  Block2 transposed() const { return {xx, yx, xy, yy}; }
};

/// The symmetric operator on a side x side vertex grid: for vertex k = j side + i and each offset
/// (di, dj) in [-1, 1]^2, the 2x2 block coupling (u, v) of k with (u, v) of (i + di, j + dj).
/// Vectors hold (u, v) interleaved: x[2k], x[2k + 1].
class GridStencil {
 public:
  static constexpr int kTaps = 9;
  static int tap(int di, int dj) { return (dj + 1) * 3 + (di + 1); }

  void reset(int side) {
    mSide = side;
    const std::size_t n = std::size_t(side) * side;
    mBlocks.assign(n * kTaps * 4, 0.0f);
    mFixed.assign(n, 0);
  }
  int side() const { return mSide; }
  std::size_t vertexCount() const { return std::size_t(mSide) * mSide; }
  std::size_t unknowns() const { return 2 * vertexCount(); }

  /// Adds `b` to the block of vertex k coupling it with the vertex at offset (di, dj).
  void add(std::size_t k, int di, int dj, const Block2& b) {
    float* p = &mBlocks[(k * kTaps + tap(di, dj)) * 4];
    p[0] += float(b.xx), p[1] += float(b.xy), p[2] += float(b.yx), p[3] += float(b.yy);
  }
  Block2 block(std::size_t k, int t) const {
    const float* p = &mBlocks[(k * kTaps + t) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
  float* blocks(std::size_t k) { return &mBlocks[k * kTaps * 4]; }
  const float* blocks(std::size_t k) const { return &mBlocks[k * kTaps * 4]; }

  /// Bit 0: u of vertex k is fixed, bit 1: v is fixed.
  std::uint8_t fixed(std::size_t k) const { return mFixed[k]; }
  void setFixed(std::size_t k, std::uint8_t bits) { mFixed[k] = bits; }

  /// Makes every fixed component an identity row and column (call once the blocks are summed).
  void applyConstraints() {
    const int side = mSide;
    parallelFor(0, vertexCount(), [&](std::size_t k) {
      const int i = int(k % side), j = int(k / side);
      float* b = blocks(k);
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int ni = i + di, nj = j + dj;
          float* blk = b + tap(di, dj) * 4;
          if (ni < 0 || nj < 0 || ni >= side || nj >= side) {
            std::fill(blk, blk + 4, 0.0f);
            continue;
          }
          const std::uint8_t row = mFixed[k], col = mFixed[std::size_t(nj) * side + ni];
          if (row & 1) blk[0] = blk[1] = 0;
          if (row & 2) blk[2] = blk[3] = 0;
          if (col & 1) blk[0] = blk[2] = 0;
          if (col & 2) blk[1] = blk[3] = 0;
        }
      float* c = b + tap(0, 0) * 4;
      if (mFixed[k] & 1) c[0] = 1;
      if (mFixed[k] & 2) c[3] = 1;
    }, 256);
  }

  /// Levenberg-Marquardt damping: multiplies the diagonal entries by 1 + mu (fixed rows stay 1).
  void dampDiagonal(double mu) {
    parallelFor(0, vertexCount(), [&](std::size_t k) {
      float* c = blocks(k) + tap(0, 0) * 4;
      if (!(mFixed[k] & 1)) c[0] *= float(1 + mu);
      if (!(mFixed[k] & 2)) c[3] *= float(1 + mu);
    }, 1024);
  }

  /// Zeroes the fixed components of x.
  void mask(std::vector<double>& x) const {
    for (std::size_t k = 0; k < vertexCount(); ++k) {
      if (mFixed[k] & 1) x[2 * k] = 0;
      if (mFixed[k] & 2) x[2 * k + 1] = 0;
    }
  }

  /// The product of row k with x: sum over the taps of block * x(neighbour), skipping the centre
  /// when `offDiagonalOnly`.
  void rowProduct(std::size_t k, const double* x, double& yu, double& yv,
                  bool offDiagonalOnly = false) const {
    const int side = mSide, i = int(k % side), j = int(k / side);
    const float* b = blocks(k);
    double su = 0, sv = 0;
    for (int dj = -1; dj <= 1; ++dj) {
      const int nj = j + dj;
      if (nj < 0 || nj >= side) continue;
      for (int di = -1; di <= 1; ++di) {
        const int ni = i + di;
        if (ni < 0 || ni >= side || (offDiagonalOnly && di == 0 && dj == 0)) continue;
        const float* blk = b + tap(di, dj) * 4;
        const std::size_t n = std::size_t(nj) * side + ni;
        su += blk[0] * x[2 * n] + blk[1] * x[2 * n + 1];
        sv += blk[2] * x[2 * n] + blk[3] * x[2 * n + 1];
      }
    }
    yu = su, yv = sv;
  }

  /// y = A x.
  void apply(const std::vector<double>& x, std::vector<double>& y) const {
    y.resize(unknowns());
    parallelFor(0, vertexCount(), [&](std::size_t k) {
      rowProduct(k, x.data(), y[2 * k], y[2 * k + 1]);
    }, 512);
  }

 private:
  int mSide = 0;
  std::vector<float> mBlocks;
  std::vector<std::uint8_t> mFixed;
};

namespace detail {

/// One axis of the prolongation: fine index f takes its value from one or two coarse indices.
struct Parents {
  int index[2] = {0, 0};
  double weight[2] = {1, 0};
  int count = 1;
};

/// Coarse vertex I sits on fine vertex min(2I, g); fine vertices between two coarse ones
/// interpolate them linearly.
inline std::vector<Parents> prolongationAxis(int g) {
  std::vector<Parents> axis(std::size_t(g) + 1);
  for (int f = 0; f <= g; ++f) {
    Parents& p = axis[std::size_t(f)];
    const int i0 = f / 2;
    if (2 * i0 == f) {
      p.index[0] = i0;
      continue;
    }
    const int at1 = std::min(2 * (i0 + 1), g);
    if (at1 == f) {  // g odd, f = g: the last coarse vertex
      p.index[0] = i0 + 1;
      continue;
    }
    p.count = 2;
    p.index[0] = i0, p.index[1] = i0 + 1;
    p.weight[1] = double(f - 2 * i0) / double(at1 - 2 * i0);
    p.weight[0] = 1 - p.weight[1];
  }
  return axis;
}

/// Dense Cholesky factorization of a small SPD matrix (the coarsest grid), in place.
class DenseCholesky {
 public:
  void factor(std::vector<double> a, std::size_t n) {
    mN = n;
    for (std::size_t j = 0; j < n; ++j) {
      double d = a[j * n + j];
      for (std::size_t k = 0; k < j; ++k) d -= a[j * n + k] * a[j * n + k];
      if (!(d > 0))
        throw Error(ErrorKind::InvalidInput, "multigrid: the coarsest operator is not positive definite");
      d = std::sqrt(d);
      a[j * n + j] = d;
      for (std::size_t i = j + 1; i < n; ++i) {
        double s = a[i * n + j];
        for (std::size_t k = 0; k < j; ++k) s -= a[i * n + k] * a[j * n + k];
        a[i * n + j] = s / d;
      }
    }
    mL = std::move(a);
  }
  void solve(std::vector<double>& x) const {
    const std::size_t n = mN;
    for (std::size_t i = 0; i < n; ++i) {
      double s = x[i];
      for (std::size_t k = 0; k < i; ++k) s -= mL[i * n + k] * x[k];
      x[i] = s / mL[i * n + i];
    }
    for (std::size_t i = n; i-- > 0;) {
      double s = x[i];
      for (std::size_t k = i + 1; k < n; ++k) s -= mL[k * n + i] * x[k];
      x[i] = s / mL[i * n + i];
    }
  }

 private:
  std::size_t mN = 0;
  std::vector<double> mL;
};

}  // namespace detail

/// The V-cycle preconditioner over the hierarchy of an operator (see the file comment).
class GridMultigrid {
 public:
  /// The side (g + 1) at and below which the grid is solved directly.
  static constexpr int kCoarsestSide = 9;

  /// Builds the hierarchy of `fine` (which must outlive this object or the next build).
  void build(const GridStencil& fine) {
    mFine = &fine;
    std::size_t levels = 0;
    for (int side = fine.side(); side > kCoarsestSide; side = side / 2 + 1) ++levels;
    mCoarse.resize(levels);
    mAxes.resize(levels);
    mResidual.resize(levels + 1);
    mX.resize(levels + 1);
    mB.resize(levels + 1);
    const GridStencil* a = &fine;
    for (std::size_t l = 0; l < levels; ++l) {
      mAxes[l] = detail::prolongationAxis(a->side() - 1);
      galerkin(*a, mAxes[l], mCoarse[l]);
      a = &mCoarse[l];
    }
    for (std::size_t l = 0; l <= levels; ++l) {
      const GridStencil& s = level(l);
      mResidual[l].assign(s.unknowns(), 0.0);
      mX[l].assign(s.unknowns(), 0.0);
      mB[l].assign(s.unknowns(), 0.0);
    }
    invertDiagonals();
    factorCoarsest();
  }

  std::size_t levels() const { return mCoarse.size() + 1; }

  /// z = M^-1 r: one V-cycle from z = 0.
  void apply(const std::vector<double>& r, std::vector<double>& z) {
    mB[0] = r;
    vcycle(0);
    z = mX[0];
  }

 private:
  const GridStencil& level(std::size_t l) const { return l == 0 ? *mFine : mCoarse[l - 1]; }

  /// A_c = P^T A P, gathered per coarse vertex (no two threads write one block).
  static void galerkin(const GridStencil& a, const std::vector<detail::Parents>& axis,
                       GridStencil& coarse) {
    const int g = a.side() - 1, side = a.side();
    const int gc = (g + 1) / 2, sideC = gc + 1;
    coarse.reset(sideC);
    // Children of coarse index I along one axis: fine f in [2I - 1, 2I + 1] with I as a parent.
    parallelFor(0, coarse.vertexCount(), [&](std::size_t kc) {
      const int ic = int(kc % sideC), jc = int(kc / sideC);
      const std::uint8_t fixedBits = std::uint8_t((ic == 0 || ic == gc ? 1 : 0) |
                                                  (jc == 0 || jc == gc ? 2 : 0));
      coarse.setFixed(kc, fixedBits);
      for (int fj = 2 * jc - 1; fj <= 2 * jc + 1; ++fj) {
        if (fj < 0 || fj > g) continue;
        const double wj = weight(axis, fj, jc);
        if (wj == 0) continue;
        for (int fi = 2 * ic - 1; fi <= 2 * ic + 1; ++fi) {
          if (fi < 0 || fi > g) continue;
          const double w = wj * weight(axis, fi, ic);
          if (w == 0) continue;
          const std::size_t f = std::size_t(fj) * side + fi;
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const int ni = fi + di, nj = fj + dj;
              if (ni < 0 || nj < 0 || ni > g || nj > g) continue;
              const Block2 b = a.block(f, GridStencil::tap(di, dj)) * w;
              const detail::Parents& pi = axis[std::size_t(ni)];
              const detail::Parents& pj = axis[std::size_t(nj)];
              for (int cj = 0; cj < pj.count; ++cj)
                for (int ci = 0; ci < pi.count; ++ci)
                  coarse.add(kc, pi.index[ci] - ic, pj.index[cj] - jc,
                             b * (pi.weight[ci] * pj.weight[cj]));
            }
        }
      }
    }, 64);
    coarse.applyConstraints();
  }

  void invertDiagonals() {
    mDiagonalInverse.resize(levels());
    for (std::size_t l = 0; l < levels(); ++l) {
      const GridStencil& s = level(l);
      std::vector<Block2>& inv = mDiagonalInverse[l];
      inv.resize(s.vertexCount());
      for (std::size_t k = 0; k < s.vertexCount(); ++k) {
        const Block2 d = s.block(k, GridStencil::tap(0, 0));
        const double det = d.xx * d.yy - d.xy * d.yx;
        inv[k] = std::abs(det) > 0 ? Block2{d.yy / det, -d.xy / det, -d.yx / det, d.xx / det}
                                   : Block2{};
      }
    }
  }

  void factorCoarsest() {
    const GridStencil& s = level(levels() - 1);
    const std::size_t n = s.unknowns(), side = std::size_t(s.side());
    std::vector<double> dense(n * n, 0.0);
    for (std::size_t k = 0; k < s.vertexCount(); ++k) {
      const int i = int(k % side), j = int(k / side);
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int ni = i + di, nj = j + dj;
          if (ni < 0 || nj < 0 || ni >= int(side) || nj >= int(side)) continue;
          const std::size_t m = std::size_t(nj) * side + ni;
          const Block2 b = s.block(k, GridStencil::tap(di, dj));
          dense[(2 * k) * n + 2 * m] += b.xx;
          dense[(2 * k) * n + 2 * m + 1] += b.xy;
          dense[(2 * k + 1) * n + 2 * m] += b.yx;
          dense[(2 * k + 1) * n + 2 * m + 1] += b.yy;
        }
    }
    mCoarsest.factor(std::move(dense), n);
  }

  /// Block Gauss-Seidel over the four colours, in order or reversed.
  void smooth(std::size_t l, bool reverse) {
    const GridStencil& s = level(l);
    const int side = s.side();
    std::vector<double>& x = mX[l];
    const std::vector<double>& b = mB[l];
    const std::vector<Block2>& inv = mDiagonalInverse[l];
    for (int c = 0; c < 4; ++c) {
      const int colour = reverse ? 3 - c : c, ci = colour & 1, cj = colour >> 1;
      const std::size_t rows = std::size_t(side - cj + 1) / 2;
      parallelFor(0, rows, [&](std::size_t r) {
        const int j = cj + 2 * int(r);
        for (int i = ci; i < side; i += 2) {
          const std::size_t k = std::size_t(j) * side + i;
          double ou, ov;
          s.rowProduct(k, x.data(), ou, ov, true);
          const double ru = b[2 * k] - ou, rv = b[2 * k + 1] - ov;
          x[2 * k] = inv[k].xx * ru + inv[k].xy * rv;
          x[2 * k + 1] = inv[k].yx * ru + inv[k].yy * rv;
        }
      }, 4);
    }
  }

  void vcycle(std::size_t l) {
    const GridStencil& s = level(l);
    std::vector<double>& x = mX[l];
    if (l + 1 == levels()) {
      x = mB[l];
      mCoarsest.solve(x);
      return;
    }
    std::fill(x.begin(), x.end(), 0.0);
    smooth(l, false);
    // Residual, restricted: b_c = P^T (b - A x).
    std::vector<double>& r = mResidual[l];
    s.apply(x, r);
    for (std::size_t k = 0; k < r.size(); ++k) r[k] = mB[l][k] - r[k];
    const std::vector<detail::Parents>& axis = mAxes[l];
    const GridStencil& c = mCoarse[l];
    const int side = s.side(), sideC = c.side();
    std::vector<double>& bc = mB[l + 1];
    parallelFor(0, c.vertexCount(), [&](std::size_t kc) {
      const int ic = int(kc % sideC), jc = int(kc / sideC);
      double su = 0, sv = 0;
      for (int fj = std::max(0, 2 * jc - 1); fj <= std::min(side - 1, 2 * jc + 1); ++fj)
        for (int fi = std::max(0, 2 * ic - 1); fi <= std::min(side - 1, 2 * ic + 1); ++fi) {
          const double w = weight(axis, fi, ic) * weight(axis, fj, jc);
          if (w == 0) continue;
          const std::size_t f = std::size_t(fj) * side + fi;
          su += w * r[2 * f];
          sv += w * r[2 * f + 1];
        }
      const std::uint8_t fixedBits = c.fixed(kc);
      bc[2 * kc] = fixedBits & 1 ? 0.0 : su;
      bc[2 * kc + 1] = fixedBits & 2 ? 0.0 : sv;
    }, 256);
    vcycle(l + 1);
    // Prolongate the coarse correction: x += P x_c.
    const std::vector<double>& xc = mX[l + 1];
    parallelFor(0, s.vertexCount(), [&](std::size_t f) {
      const detail::Parents& pi = axis[f % side];
      const detail::Parents& pj = axis[f / side];
      double du = 0, dv = 0;
      for (int cj = 0; cj < pj.count; ++cj)
        for (int ci = 0; ci < pi.count; ++ci) {
          const std::size_t kc = std::size_t(pj.index[cj]) * sideC + pi.index[ci];
          const double w = pi.weight[ci] * pj.weight[cj];
          du += w * xc[2 * kc];
          dv += w * xc[2 * kc + 1];
        }
      const std::uint8_t fixedBits = s.fixed(f);
      if (!(fixedBits & 1)) x[2 * f] += du;
      if (!(fixedBits & 2)) x[2 * f + 1] += dv;
    }, 512);
    smooth(l, true);
  }

  static double weight(const std::vector<detail::Parents>& axis, int f, int parent) {
    const detail::Parents& p = axis[std::size_t(f)];
    for (int c = 0; c < p.count; ++c)
      if (p.index[c] == parent) return p.weight[c];
    return 0.0;
  }

  const GridStencil* mFine = nullptr;
  std::vector<GridStencil> mCoarse;
  std::vector<std::vector<detail::Parents>> mAxes;
  std::vector<std::vector<Block2>> mDiagonalInverse;
  std::vector<std::vector<double>> mResidual, mX, mB;
  detail::DenseCholesky mCoarsest;
};

/// What a conjugate-gradient solve did.
struct CgReport {
  int iterations = 0;
  double relativeResidual = 0;  ///< |r| / |b| at the end
};

/// Solves A x = b by conjugate gradients preconditioned with `mg` (built on A), from x = 0, until
/// |r| <= tolerance |b| or `maxIterations`. Fixed components of b must be zero. Deterministic: the
/// result does not depend on the thread count.
inline CgReport solveConjugateGradients(const GridStencil& a, GridMultigrid& mg,
                                        const std::vector<double>& b, std::vector<double>& x,
                                        double tolerance, int maxIterations) {
  const std::size_t n = a.unknowns();
  // Dot products over fixed blocks summed in order: the same result on any thread count.
  constexpr std::size_t kBlock = 4096;
  std::vector<double> partial((n + kBlock - 1) / kBlock);
  auto dot = [&](const std::vector<double>& p, const std::vector<double>& q) {
    parallelFor(0, partial.size(), [&](std::size_t block) {
      double s = 0;
      for (std::size_t i = block * kBlock, end = std::min(n, i + kBlock); i < end; ++i)
        s += p[i] * q[i];
      partial[block] = s;
    }, 1);
    double sum = 0;
    for (double s : partial) sum += s;
    return sum;
  };
  x.assign(n, 0.0);
  std::vector<double> r = b, z(n), p(n), ap(n);
  const double bNorm = std::sqrt(dot(b, b));
  CgReport report;
  if (!(bNorm > 0)) return report;
  mg.apply(r, z);
  p = z;
  double rz = dot(r, z);
  for (int it = 0; it < maxIterations; ++it) {
    a.apply(p, ap);
    const double pap = dot(p, ap);
    if (!(pap > 0)) break;
    const double alpha = rz / pap;
    parallelFor(0, n, [&](std::size_t i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * ap[i];
    }, 4096);
    report.iterations = it + 1;
    report.relativeResidual = std::sqrt(dot(r, r)) / bNorm;
    if (report.relativeResidual <= tolerance) break;
    mg.apply(r, z);
    const double rzNew = dot(r, z);
    const double beta = rzNew / rz;
    rz = rzNew;
    parallelFor(0, n, [&](std::size_t i) { p[i] = z[i] + beta * p[i]; }, 4096);
  }
  return report;
}

}  // namespace cellrelief::indirection
