// SPDX-License-Identifier: MIT
/// @file symmetric_eigen.h
/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations: plane fits (the
/// smallest eigenvector of a covariance) and principal axes. Jacobi rather than the closed-form
/// cubic because it stays accurate for nearly equal eigenvalues (a planar region gives two),
/// where the cubic's trigonometric solution loses the eigenvectors.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "cellrelief/core/math.h"

namespace cellrelief {

struct SymmetricEigen3 {
  Vec3d values;                  ///< ascending
  std::array<Vec3d, 3> vectors;  ///< unit, orthogonal, vectors[i] belongs to values[i]
};

/// `m` must be symmetric (only its upper triangle is read).
inline SymmetricEigen3 symmetricEigen3(const glm::dmat3& m) {
  double a[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[r][c] = r <= c ? m[c][r] : m[r][c];  // glm is column-major
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    const double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    if (off <= 1e-30 * diag || off == 0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A <- A J (columns p, q)
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // A <- J^T A (rows p, q)
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {  // V <- V J
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return a[i][i] < a[j][j]; });
  SymmetricEigen3 r;
  for (int i = 0; i < 3; ++i) {
    const int k = order[i];
    r.values[i] = a[k][k];
    r.vectors[i] = glm::normalize(Vec3d(v[0][k], v[1][k], v[2][k]));
  }
  return r;
}

}  // namespace cellrelief
