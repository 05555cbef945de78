// SPDX-License-Identifier: MIT
// CentreOfProjection::FewestCrossings: which centres it tries, and that the one it picks leaves
// fewer projection lines crossing the surface twice than the paper's canonical centre.
#include <gtest/gtest.h>

#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/centre_search.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/reconstruct.h>

namespace cellrelief::relief {
namespace {

using projection::CentreOfProjection;

// Per base case (0 1 2a 2b 3a 3b 4a 4b 5 6): the free coordinates of its point (those at 1/2
// that are not an axis' own direction) take 5 values each.
constexpr int kCandidatesPerBaseCase[10] = {125, 1, 1, 1, 5, 1, 5, 25, 25, 125};

TEST(CentreSearch, CandidatesStartCanonicalAndMoveOnlyFreeCoordinates) {
  for (int config = 0; config < 64; ++config) {
    const auto configuration = std::uint8_t(config);
    const auto canonical = projection::chooseProjection<double>(configuration);
    const auto candidates = centreCandidates(configuration);
    const int baseCase = int(cells::kConfigurationTable[config].baseCase);
    ASSERT_EQ(int(candidates.size()), kCandidatesPerBaseCase[baseCase]) << "configuration " << config;
    EXPECT_EQ(candidates.front().point, canonical.point);
    double previous = 0;
    for (const auto& c : candidates) {
      EXPECT_EQ(c.type, canonical.type);
      EXPECT_EQ(c.faceOrAxis, canonical.faceOrAxis);
      EXPECT_EQ(c.faces, canonical.faces);
      for (int a = 0; a < 3; ++a) {
        // A point on an internal face (0 or 1) stays on it: rays must not reach internal faces.
        if (canonical.point[a] != 0.5) EXPECT_EQ(c.point[a], canonical.point[a]) << "configuration " << config;
        else EXPECT_TRUE(c.point[a] > 0 && c.point[a] < 1);
      }
      const double distance = glm::length(c.point - canonical.point);
      EXPECT_GE(distance, previous);  // nearest the canonical point first
      previous = distance;
    }
  }
}

TEST(CentreSearch, FewerLinesCrossTwiceThanFromTheCellCentre) {
  // A displaced sphere on an 8^3 grid: its ridges fold back within cells, so lines from the
  // canonical centres cross them twice.
  const TriangleMesh sphere = makeDisplacedSphere();
  ConvertReport canonical, searched;
  const ReliefModel fromCentre =
      convert(sphere, {.gridSize = 8, .texels = 17, .centre = CentreOfProjection::CellCentre}, &canonical);
  const ReliefModel fromSearch =
      convert(sphere, {.gridSize = 8, .texels = 17, .centre = CentreOfProjection::FewestCrossings}, &searched);
  const MeshTopology before = analyzeTopology(reconstruct(fromCentre));
  const MeshTopology after = analyzeTopology(reconstruct(fromSearch));
  std::printf("displaced sphere N=8: lines crossed twice %zu -> %zu, %zu cells moved, genus %d -> %d\n",
              canonical.linesCrossedTwice, searched.linesCrossedTwice, searched.movedCentres,
              before.genus.value_or(-1), after.genus.value_or(-1));
  EXPECT_EQ(canonical.movedCentres, 0u);
  EXPECT_GT(searched.movedCentres, 0u);
  ASSERT_GT(canonical.linesCrossedTwice, 0u);
  EXPECT_LT(4 * searched.linesCrossedTwice, canonical.linesCrossedTwice);  // measured 28x fewer
  EXPECT_EQ(after.boundaryEdges, 0u);
  EXPECT_EQ(after.genus, std::optional<int>(0));
}

}  // namespace
}  // namespace cellrelief::relief
