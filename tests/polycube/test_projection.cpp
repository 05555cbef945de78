// SPDX-License-Identifier: MIT
// The projection P: onto the surface, the identity on it, continuous, and on every cell face the
// surface crosses exactly the face's own 2D rule (so two cells sharing a face agree).
#include <random>

#include <gtest/gtest.h>

#include <cellrelief/polycube/projection.h>

namespace cellrelief::polycube {
namespace {

double distanceToSurface(std::uint8_t configuration, const Vec3d& p) {
  double best = INFINITY;
  for (int i = 0; i < 12; ++i)
    if (kVertexConfigurations[configuration].squarelets & (1u << i)) {
      const SquareletBounds box = squareletBounds(i);
      best = std::min(best, glm::length(p - glm::clamp(p, box.min, box.max)));
    }
  return best;
}

/// The 2D rule of cell face (axis, side) for a point p of it: orthogonal projection onto a
/// straight line, central projection from the odd quadrant's corner onto a corner. Nothing when
/// the surface does not cross the face.
std::optional<Vec3d> faceRule(std::uint8_t configuration, int axis, int side, const Vec3d& p) {
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const int u = std::min(a, b), v = std::max(a, b);
  bool solid[2][2];  // [u side][v side]
  int count = 0;
  for (int su = 0; su < 2; ++su)
    for (int sv = 0; sv < 2; ++sv) {
      const int octant = (side << axis) | (su << u) | (sv << v);
      solid[su][sv] = (configuration >> octant) & 1;
      count += solid[su][sv];
    }
  if (count == 0 || count == 4) return std::nullopt;
  Vec3d q = p;
  if (count == 2) {
    if (solid[0][0] == solid[1][0]) q[v] = 0;  // the solid half is on one v side: the line v = 0
    else q[u] = 0;
    return q;
  }
  // The odd quadrant: the one whose state appears once.
  int ou = 0, ov = 0;
  for (int su = 0; su < 2; ++su)
    for (int sv = 0; sv < 2; ++sv)
      if ((solid[su][sv] ? 1 : 0) == (count == 1 ? 1 : 0)) ou = su, ov = sv;
  const Vec2d c(ou ? 0.5 : -0.5, ov ? 0.5 : -0.5), d(p[u] - c.x, p[v] - c.y);
  double t = INFINITY;
  if (d.x != 0 && -c.x / d.x > 0) t = std::min(t, -c.x / d.x);
  if (d.y != 0 && -c.y / d.y > 0) t = std::min(t, -c.y / d.y);
  q[u] = c.x + t * d.x;
  q[v] = c.y + t * d.y;
  return q;
}

Vec3d randomInCell(std::mt19937& random) {
  std::uniform_real_distribution<double> coordinate(-0.5, 0.5);
  return {coordinate(random), coordinate(random), coordinate(random)};
}

constexpr double kReach = 0.45;  // P is used within half a cube of the surface

TEST(PolycubeProjection, MapsOntoTheSurfaceAndFixesIt) {
  std::mt19937 random(1);
  int checked = 0;
  for (int c = 1; c < 255; ++c) {
    const auto configuration = std::uint8_t(c);
    if (!kVertexConfigurations[c].manifold) continue;
    for (int k = 0; k < 400; ++k) {
      const Vec3d p = randomInCell(random);
      if (distanceToSurface(configuration, p) > kReach) continue;
      const Vec3d q = project(configuration, p);
      ASSERT_LT(distanceToSurface(configuration, q), 1e-9) << "configuration " << c;
      ++checked;
      // On the surface, P is the identity.
      EXPECT_LT(glm::length(project(configuration, q) - q), 1e-9) << "configuration " << c;
    }
  }
  EXPECT_GT(checked, 10000);
}

TEST(PolycubeProjection, OnEveryCrossedCellFaceItIsTheFacesOwnRule) {
  std::mt19937 random(2);
  std::uniform_real_distribution<double> coordinate(-0.5, 0.5);
  int checked = 0;
  for (int c = 1; c < 255; ++c) {
    const auto configuration = std::uint8_t(c);
    if (!kVertexConfigurations[c].manifold) continue;
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side)
        for (int k = 0; k < 100; ++k) {
          Vec3d p = randomInCell(random);
          p[axis] = side ? 0.5 : -0.5;
          if (distanceToSurface(configuration, p) > kReach) continue;
          const std::optional<Vec3d> expected = faceRule(configuration, axis, side, p);
          ASSERT_TRUE(expected.has_value()) << "a point near the surface on a face it does not cross";
          const Vec3d q = project(configuration, p);
          EXPECT_LT(glm::length(q - *expected), 1e-9)
              << "configuration " << c << " face " << axis << (side ? "+" : "-");
          ++checked;
        }
  }
  EXPECT_GT(checked, 5000);
}

TEST(PolycubeProjection, IsContinuousWithinReachOfTheSurface) {
  std::mt19937 random(3);
  std::normal_distribution<double> gauss;
  double worst[kVertexCaseCount] = {};
  for (int c = 1; c < 255; ++c) {
    const auto configuration = std::uint8_t(c);
    if (!kVertexConfigurations[c].manifold) continue;
    double& caseWorst = worst[static_cast<int>(kVertexConfigurations[c].vertexCase)];
    for (int k = 0; k < 300; ++k) {
      const Vec3d p = randomInCell(random);
      const Vec3d step = 1e-5 * glm::normalize(Vec3d(gauss(random), gauss(random), gauss(random)));
      const Vec3d p2 = glm::clamp(p + step, Vec3d(-0.5), Vec3d(0.5));
      if (distanceToSurface(configuration, p) > kReach || distanceToSurface(configuration, p2) > kReach) continue;
      caseWorst = std::max(caseWorst, glm::length(project(configuration, p) - project(configuration, p2)) /
                                          glm::length(p2 - p));
    }
  }
  // A Lipschitz bound: central projections from half a cube away stretch by at most a few times.
  // Case 6b's rays from near its middle cubes' diagonal meet the surface near the vertex at a
  // grazing angle (projection.h), so its bound is larger; a jump would show as about 1e5.
  for (int k = 0; k < kVertexCaseCount; ++k) {
    const auto vertexCase = static_cast<VertexCase>(k);
    EXPECT_LT(worst[k], vertexCase == VertexCase::k6b ? 60.0 : 20.0) << "case " << toString(vertexCase);
    std::printf("case %-2s: largest stretch |P(p) - P(p')| / |p - p'| within %.2f of the surface: %.2f\n",
                std::string(toString(vertexCase)).c_str(), kReach, worst[k]);
  }
}

TEST(PolycubeProjection, ConfigurationsWithoutSurfaceAreRefused) {
  EXPECT_THROW(project(0, Vec3d(0.1)), Error);
  EXPECT_THROW(project(255, Vec3d(0.1)), Error);
  EXPECT_THROW(project(0b10000001, Vec3d(0.1)), Error);  // two cubes meeting at the vertex: not manifold
}

}  // namespace
}  // namespace cellrelief::polycube
