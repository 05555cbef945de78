// SPDX-License-Identifier: MIT
// The 24 rotations and the 64 configurations grouped into the ten base cases.
#include <set>

#include <gtest/gtest.h>

#include <cellrelief/cells/configuration.h>

namespace cellrelief::cells {
namespace {

TEST(Rotations, TwentyFourDistinctProperRotations) {
  std::set<std::array<std::array<std::int8_t, 3>, 3>> seen;
  for (const CubeRotation& r : kRotations) {
    seen.insert(r.m);
    int det = 0;
    for (int j = 0; j < 3; ++j)
      det += r.m[0][j] * (r.m[1][(j + 1) % 3] * r.m[2][(j + 2) % 3] -
                          r.m[1][(j + 2) % 3] * r.m[2][(j + 1) % 3]);
    EXPECT_EQ(det, 1);
    for (int f = 0; f < 6; ++f) {
      // Faces map to faces, opposite faces stay opposite, and the inverse undoes it.
      EXPECT_EQ(r.applyToFace(oppositeFace(f)), oppositeFace(r.applyToFace(f)));
      EXPECT_EQ(r.inverse().applyToFace(r.applyToFace(f)), f);
      EXPECT_EQ(Vec3i(faceNormal(r.applyToFace(f))), r.apply(faceNormal(f)));
    }
  }
  EXPECT_EQ(seen.size(), 24u);
}

TEST(Configurations, EachOfTheSixtyFourHasExactlyOneBaseCase) {
  std::array<int, kBaseCaseCount> perCase{};
  for (int config = 0; config < 64; ++config) {
    const ConfigurationInfo info = kConfigurationTable[config];
    // Applying the stored rotation to the canonical case reproduces the configuration.
    EXPECT_EQ(rotateConfiguration(kCanonicalConfiguration[int(info.baseCase)], info.rotation),
              config);
    // And no other base case reaches it under any rotation.
    for (int c = 0; c < kBaseCaseCount; ++c)
      for (int r = 0; r < 24; ++r)
        if (rotateConfiguration(kCanonicalConfiguration[c], r) == config)
          EXPECT_EQ(c, int(info.baseCase)) << config;
    EXPECT_EQ(externalFaceCount(std::uint8_t(config)),
              externalFaceCount(kCanonicalConfiguration[int(info.baseCase)]));
    ++perCase[int(info.baseCase)];
  }
  // Orbit sizes: 1, 6, 3 (opposite pairs), 12 (adjacent pairs), 12 (U shapes), 8 (corners),
  // 12, 3, 6, 1.
  const std::array<int, 10> expected{1, 6, 3, 12, 12, 8, 12, 3, 6, 1};
  EXPECT_EQ(perCase, expected);
}

TEST(Configurations, CaseShapesAreAsDocumented) {
  auto caseOf = [](std::initializer_list<int> faces) {
    std::uint8_t config = 0;
    for (int f : faces) config |= std::uint8_t(1u << f);
    return kConfigurationTable[config].baseCase;
  };
  EXPECT_EQ(caseOf({0, 1}), BaseCase::k2a);        // -x +x: opposite
  EXPECT_EQ(caseOf({1, 2}), BaseCase::k2b);        // +x -y: adjacent
  EXPECT_EQ(caseOf({2, 3, 4}), BaseCase::k3a);     // -y +y -z: U
  EXPECT_EQ(caseOf({0, 2, 4}), BaseCase::k3b);     // -x -y -z: corner
  EXPECT_EQ(caseOf({0, 1, 2, 4}), BaseCase::k4a);  // internal +y +z: adjacent
  EXPECT_EQ(caseOf({0, 1, 4, 5}), BaseCase::k4b);  // internal -y +y: opposite (ring around y)
  EXPECT_EQ(domainFacesOf(0), 0b111111);
  EXPECT_EQ(domainFacesOf(0b000101), 0b000101);
}

}  // namespace
}  // namespace cellrelief::cells
