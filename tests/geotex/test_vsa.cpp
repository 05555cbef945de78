// SPDX-License-Identifier: MIT
// Variational Shape Approximation: exact answers on planar shapes, monotone error, connected
// regions, one region per component, soups like welded meshes, refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include <set>

#include <cellrelief/core/procedural.h>
#include <cellrelief/geotex/vsa.h>
#include <cellrelief/io/mesh_io.h>

#include "geotex/geotex_test_meshes.h"
#include "test_support.h"

namespace cellrelief::geotex {
namespace {

/// Every region is connected in the face graph.
void expectConnectedRegions(const TriangleMesh& mesh, const VsaPartition& p) {
  const FaceGraph g = buildFaceGraph(mesh);
  const std::size_t k = p.proxies.size();
  std::vector<std::vector<std::uint32_t>> members(k);
  for (std::uint32_t f = 0; f < p.regionOfFace.size(); ++f) members[p.regionOfFace[f]].push_back(f);
  for (std::size_t r = 0; r < k; ++r) {
    ASSERT_FALSE(members[r].empty()) << "region " << r << " is empty";
    std::vector<char> seen(g.faceCount(), 0);
    std::vector<std::uint32_t> stack{members[r][0]};
    seen[members[r][0]] = 1;
    std::size_t reached = 0;
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      ++reached;
      for (std::uint32_t i = g.neighbourStart[f]; i < g.neighbourStart[f + 1]; ++i) {
        const std::uint32_t n = g.neighbours[i];
        if (!seen[n] && p.regionOfFace[n] == r) {
          seen[n] = 1;
          stack.push_back(n);
        }
      }
    }
    EXPECT_EQ(reached, members[r].size()) << "region " << r << " is not connected";
  }
}

class VsaOnCube : public testing::TestWithParam<std::tuple<VsaMetric, VsaSeeding>> {};

TEST_P(VsaOnCube, SixProxiesFindTheSixFacesExactly) {
  const TriangleMesh cube = test::makeCube(-1, 1, 2);
  VsaOptions o;
  o.proxies = 6;
  o.metric = std::get<0>(GetParam());
  o.seeding = std::get<1>(GetParam());
  const VsaPartition p = partitionVsa(cube, o);
  ASSERT_EQ(p.proxies.size(), 6u);
  EXPECT_NEAR(p.error, 0.0, 1e-9);
  // Each region is one face of the cube: its triangles share one axis normal, and the six
  // regions have six different normals.
  const FaceGraph g = buildFaceGraph(cube);
  std::set<std::tuple<int, int, int>> normals;
  for (std::size_t r = 0; r < 6; ++r) {
    const Vec3d n = p.proxies[r].normal;
    normals.insert({int(std::lround(n.x)), int(std::lround(n.y)), int(std::lround(n.z))});
  }
  EXPECT_EQ(normals.size(), 6u);
  for (std::size_t f = 0; f < g.faceCount(); ++f)
    EXPECT_GT(glm::dot(g.normal[f], p.proxies[p.regionOfFace[f]].normal), 1 - 1e-9) << "face " << f;
  expectConnectedRegions(cube, p);
}

INSTANTIATE_TEST_SUITE_P(MetricsAndSeedings, VsaOnCube,
                         testing::Combine(testing::Values(VsaMetric::L21, VsaMetric::L2),
                                          testing::Values(VsaSeeding::Hierarchical, VsaSeeding::FarthestPoint)));

TEST(Vsa, ErrorNeverRisesAndFallsWithMoreProxies) {
  const TriangleMesh sphere = makeIcosphere(4);
  double previous = std::numeric_limits<double>::infinity();
  for (const int k : {8, 32, 128}) {
    VsaOptions o;
    o.proxies = k;
    const VsaPartition p = partitionVsa(sphere, o);
    ASSERT_EQ(p.proxies.size(), std::size_t(k));
    for (std::size_t i = 1; i < p.errorPerIteration.size(); ++i)
      EXPECT_LE(p.errorPerIteration[i], p.errorPerIteration[i - 1]);
    EXPECT_LT(p.error, previous) << k << " proxies";
    double sum = 0;
    for (const double e : p.regionError) sum += e;
    EXPECT_NEAR(sum, p.error, 1e-9 * std::max(1.0, p.error));
    expectConnectedRegions(sphere, p);
    previous = p.error;
  }
}

TEST(Vsa, LloydIterationsImproveOnTheSeeding) {
  const TriangleMesh torus = makeTorus(1.0f, 0.35f, 96, 48);
  VsaOptions o;
  o.proxies = 24;
  o.seeding = VsaSeeding::FarthestPoint;
  const VsaPartition p = partitionVsa(torus, o);
  ASSERT_GE(p.errorPerIteration.size(), 2u);
  EXPECT_LT(p.errorPerIteration.back(), 0.9 * p.errorPerIteration.front());
}

// The iterations go on through a rise and keep the best partition seen, whose error is the one
// reported; a target error stops them at the first iteration that reaches it.
TEST(Vsa, IterationsKeepTheBestPartitionAndStopAtATargetError) {
  const TriangleMesh torus = makeTorus(1.0f, 0.35f, 96, 48);
  VsaOptions o;
  o.proxies = 24;
  o.seeding = VsaSeeding::FarthestPoint;
  o.maxIterations = 12;
  o.tolerance = 0;
  const VsaPartition full = partitionVsa(torus, o);
  ASSERT_EQ(full.errorPerIteration.size(), 13u);
  EXPECT_NEAR(partitionError(torus, full.regionOfFace, VsaMetric::L21), full.error, 1e-9 * full.error);
  EXPECT_EQ(full.error, full.errorPerIteration.back());
  for (std::size_t i = 1; i < full.errorPerIteration.size(); ++i)
    EXPECT_LE(full.errorPerIteration[i], full.errorPerIteration[i - 1]);
  // The first iteration whose best reaches the error of iteration 4 is where the target stops.
  o.targetError = full.errorPerIteration[4];
  ASSERT_LT(o.targetError, full.errorPerIteration[0]);
  const std::size_t first = std::size_t(
      std::find_if(full.errorPerIteration.begin(), full.errorPerIteration.end(), [&](double e) { return e <= o.targetError; }) -
      full.errorPerIteration.begin());
  const VsaPartition targeted = partitionVsa(torus, o);
  EXPECT_EQ(targeted.errorPerIteration.size(), first + 1);
  EXPECT_LE(targeted.error, o.targetError);
  EXPECT_NEAR(partitionError(torus, targeted.regionOfFace, VsaMetric::L21), targeted.error, 1e-9 * targeted.error);
}

TEST(Vsa, EveryComponentGetsAProxy) {
  TriangleMesh two = test::makeCube(-1, 0, 1);
  const TriangleMesh other = test::makeCube(0.5f, 1.5f, 1);
  const auto base = std::uint32_t(two.positions.size());
  two.positions.insert(two.positions.end(), other.positions.begin(), other.positions.end());
  for (const Vec3u& t : other.triangles) two.triangles.push_back(t + Vec3u(base));
  VsaOptions o;
  o.proxies = 1;
  const VsaPartition p = partitionVsa(two, o);
  EXPECT_EQ(p.components, 2);
  EXPECT_EQ(p.requestedProxies, 1);
  ASSERT_EQ(p.proxies.size(), 2u);
  // The two regions are the two cubes.
  for (std::size_t f = 0; f < two.triangles.size(); ++f)
    EXPECT_EQ(p.regionOfFace[f], p.regionOfFace[f < other.triangles.size() ? 0 : two.triangles.size() - 1]);
  EXPECT_NE(p.regionOfFace.front(), p.regionOfFace.back());
}

TEST(Vsa, ASoupPartitionsLikeItsWeldedMesh) {
  const TriangleMesh cube = test::makeCube(-1, 1, 1);
  const TriangleMesh soup = test::unweld(cube);
  EXPECT_EQ(buildFaceGraph(soup).components, 1);
  VsaOptions o;
  o.proxies = 6;
  const VsaPartition welded = partitionVsa(cube, o), unwelded = partitionVsa(soup, o);
  EXPECT_EQ(welded.regionOfFace, unwelded.regionOfFace);
  EXPECT_NEAR(unwelded.error, 0.0, 1e-9);
}

TEST(Vsa, MoreProxiesThanFacesStopsAtOnePerFace) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5f}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  VsaOptions o;
  o.proxies = 10;
  const VsaPartition p = partitionVsa(m, o);
  EXPECT_EQ(p.proxies.size(), 2u);
  EXPECT_NE(p.regionOfFace[0], p.regionOfFace[1]);
  EXPECT_NEAR(p.error, 0.0, 1e-12);
}

TEST(Vsa, RefusesMeshesWithoutArea) {
  TriangleMesh empty;
  EXPECT_THROW(partitionVsa(empty), Error);
  TriangleMesh line;
  line.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  line.triangles = {{0, 1, 2}};
  try {
    partitionVsa(line);
    FAIL() << "a mesh of zero area was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("zero area"), std::string::npos) << e.what();
  }
  VsaOptions o;
  o.proxies = 0;
  EXPECT_THROW(partitionVsa(test::makeCube(), o), Error);
}

TEST(Vsa, BunnyTwoHundredProxies) {
  const auto path = cellrelief::test::dataDir() / "meshes/medium/stanford-bunny__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh bunny = io::readMesh(path);
  VsaOptions o;
  o.proxies = cellrelief::test::kSlowBuild ? 40 : 200;
  const VsaPartition p = partitionVsa(bunny, o);
  EXPECT_EQ(p.proxies.size(), std::size_t(std::max(o.proxies, p.components)));
  expectConnectedRegions(bunny, p);
  // L2,1 error relative to the area: the mean squared normal deviation, small with 200 planes.
  const double meanDeviation = p.error / surfaceArea(bunny);
  EXPECT_LT(meanDeviation, cellrelief::test::kSlowBuild ? 0.25 : 0.1);
}


// The closed forms a teleport prices merges with (L2,1: 2 (A - |sum A n|); L2: the covariance's
// smallest eigenvalue) against the face-by-face sum against the fitted proxy, on a real mesh cut
// into regions, and for two regions merged.
TEST(Vsa, RegionFitsFromMomentsGiveTheFaceSums) {
  const auto path = cellrelief::test::dataDir() / "meshes/small/fertility_9k__libigl-tutorial-data.off";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  const FaceGraph g = buildFaceGraph(mesh);
  for (const VsaMetric metric : {VsaMetric::L21, VsaMetric::L2}) {
    VsaOptions o;
    o.proxies = 12;
    o.metric = metric;
    o.maxIterations = 2;
    const VsaPartition p = partitionVsa(mesh, o);
    std::vector<std::uint32_t> regions = p.regionOfFace;
    const std::vector<detail::RegionMoments> m = detail::regionMoments(mesh, g, metric, regions, p.proxies.size());
    // Regions 0 and 1 as one, as a merge makes them.
    detail::RegionMoments both = m[0];
    both += m[1];
    for (std::uint32_t& r : regions)
      if (r == 1) r = 0;
    const std::pair<const detail::RegionMoments*, std::uint32_t> cases[] = {{&m[2], 2}, {&m[3], 3}, {&both, 0}};
    for (const auto& [moments, region] : cases) {
      const auto faceSum = [&, r = region](const Proxy& proxy) {
        double sum = 0;
        for (std::size_t f = 0; f < g.faceCount(); ++f)
          if (regions[f] == r) sum += detail::faceError(mesh, g, metric, f, proxy);
        return sum;
      };
      const detail::Fit fit = detail::fitRegion(*moments, metric, p.proxies[region]);
      const double sum = faceSum(fit.proxy);
      EXPECT_NEAR(fit.error, sum, 1e-9 * moments->area + 1e-6 * sum) << "region " << region;
      EXPECT_GT(sum, 0);
      // And the fit is the best: a proxy turned by a degree (and moved, for L2) fits worse.
      Proxy turned = fit.proxy;
      turned.normal = glm::normalize(turned.normal + 0.0175 * glm::normalize(glm::cross(turned.normal, Vec3d(0.3, 0.5, 0.8))));
      turned.point += 0.01 * Vec3d(mesh.bounds().diagonal());
      EXPECT_GT(faceSum(turned), sum) << "region " << region;
    }
  }
}

// Where the iterations settle, teleports move proxies from where two regions merge cheaply to the
// worst regions: a lower error within the same iterations (measured 13% lower on fertility by L2,1
// and 8% on bumpy by L2; over 32 cases of both meshes, metrics and seedings and 30 to 200
// proxies, 19 lower, 12 the same, 1 higher by 0.9%), regions still connected, the budget kept, and
// the best partition reported with its error last in the history.
struct TeleportCase {
  const char* mesh;
  VsaMetric metric;
  VsaSeeding seeding;
};
class VsaTeleports : public testing::TestWithParam<TeleportCase> {};

TEST_P(VsaTeleports, LowerTheErrorWhereTheIterationsSettle) {
  const auto path = cellrelief::test::dataDir() / "meshes/small" / GetParam().mesh;
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  VsaOptions o;
  o.proxies = 200;
  o.metric = GetParam().metric;
  o.seeding = GetParam().seeding;
  o.maxIterations = 30;
  const VsaPartition plain = partitionVsa(mesh, o);
  o.teleports = 20;
  const VsaPartition teleported = partitionVsa(mesh, o);
  EXPECT_EQ(plain.teleports, 0);
  EXPECT_GT(teleported.teleports, 0);
  EXPECT_LE(teleported.teleports, o.teleports);
  EXPECT_LT(teleported.error, 0.95 * plain.error);
  EXPECT_EQ(teleported.proxies.size(), plain.proxies.size());
  EXPECT_NEAR(partitionError(mesh, teleported.regionOfFace, o.metric), teleported.error, 1e-9 * teleported.error);
  EXPECT_EQ(teleported.error, teleported.errorPerIteration.back());  // a teleport's own gain is in the history
  expectConnectedRegions(mesh, teleported);
  std::printf("%s, %zu proxies, at most %d iterations: error %.6g, with %d teleports %.6g (%.1f%% lower)\n",
              GetParam().mesh, plain.proxies.size(), o.maxIterations, plain.error, teleported.teleports,
              teleported.error, 100 * (1 - teleported.error / plain.error));
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, VsaTeleports,
                         testing::Values(TeleportCase{"fertility_9k__libigl-tutorial-data.off", VsaMetric::L21,
                                                      VsaSeeding::FarthestPoint},
                                         TeleportCase{"bumpy__libigl-tutorial-data.off", VsaMetric::L2,
                                                      VsaSeeding::Hierarchical}),
                         [](const auto& param) {
                           return std::string(param.param.metric == VsaMetric::L2 ? "L2_" : "L21_") +
                                  (param.param.seeding == VsaSeeding::Hierarchical ? "hierarchical_" : "farthest_") +
                                  std::string(param.param.mesh).substr(0, std::string(param.param.mesh).find('_'));
                         });

}  // namespace
}  // namespace cellrelief::geotex
