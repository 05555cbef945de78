// SPDX-License-Identifier: MIT
// The 3x3 symmetric eigen-solver: reconstruction A = V diag(L) V^T, orthonormal vectors, and the
// nearly equal eigenvalues of plane fits, where closed-form solutions lose the vectors.
#include <gtest/gtest.h>

#include <random>

#include <cellrelief/core/symmetric_eigen.h>

namespace cellrelief {
namespace {

glm::dmat3 rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  const Vec3d a = glm::normalize(Vec3d(n(rng), n(rng), n(rng)));
  Vec3d b = glm::normalize(Vec3d(n(rng), n(rng), n(rng)));
  b = glm::normalize(b - glm::dot(a, b) * a);
  return glm::dmat3(a, b, glm::cross(a, b));
}

TEST(SymmetricEigen3, RecoversRandomSpectraAndBases) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-10, 10);
  for (int trial = 0; trial < 200; ++trial) {
    const glm::dmat3 r = rotation(rng);
    Vec3d lambda(value(rng), value(rng), value(rng));
    if (trial % 4 == 0) lambda.y = lambda.x * (1 + 1e-12);  // nearly equal pair
    const glm::dmat3 a = r * glm::dmat3(lambda.x, 0, 0, 0, lambda.y, 0, 0, 0, lambda.z) * glm::transpose(r);
    const SymmetricEigen3 e = symmetricEigen3(a);
    EXPECT_LE(e.values[0], e.values[1]);
    EXPECT_LE(e.values[1], e.values[2]);
    glm::dmat3 back(0);
    for (int i = 0; i < 3; ++i) back += e.values[i] * glm::outerProduct(e.vectors[i], e.vectors[i]);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[c][k], a[c][k], 1e-9) << "trial " << trial;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(glm::dot(e.vectors[i], e.vectors[j]), i == j ? 1 : 0, 1e-12);
  }
}

TEST(SymmetricEigen3, PlaneCovarianceGivesItsNormal) {
  // Points of the plane z = 0.3 x - 0.2 y spread in x and y: the smallest eigenvector is the normal.
  glm::dmat3 c(0);
  const Vec3d normal = glm::normalize(Vec3d(-0.3, 0.2, 1));
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j) {
      const Vec3d p(i, j, 0.3 * i - 0.2 * j);
      c += glm::outerProduct(p, p);
    }
  const SymmetricEigen3 e = symmetricEigen3(c);
  EXPECT_NEAR(e.values[0], 0.0, 1e-9);
  EXPECT_NEAR(std::abs(glm::dot(e.vectors[0], normal)), 1.0, 1e-12);
  EXPECT_EQ(symmetricEigen3(glm::dmat3(0)).values, Vec3d(0));
}

}  // namespace
}  // namespace cellrelief
