// SPDX-License-Identifier: MIT
/// @file random_polycubes.h
/// Test polycubes: a few shapes drawn by hand (flat, convex and concave edges, genus 0 to 2), and
/// random cube sets made one manifold shell (keepLargestAndFill, makeManifold). With 60 cubes in
/// a 7^3 box the random ones reach all six vertex cases, 6a and 6b included.
#pragma once

#include <random>
#include <vector>

#include <cellrelief/polycube/polycube.h>

namespace cellrelief::polycube::fixtures {

/// A 3 x 3 x 2 box, a ring of eight cubes (genus 1), two rings side by side (genus 2), and a
/// plus of seven cubes (vertices of case 5 with six faces).
inline std::vector<Polycube> shapedPolycubes() {
  std::vector<Vec3i> box, ring, twoRings;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) box.push_back({x, y, z});
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      if (x != 1 || y != 1) ring.push_back({x, y, 0});
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      if (y != 1 || (x != 1 && x != 3)) twoRings.push_back({x, y, 0});
  const std::vector<Vec3i> plus = {{0, 0, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  return {Polycube(box), Polycube(ring), Polycube(twoRings), Polycube(plus)};
}

inline std::vector<Polycube> randomManifoldPolycubes(int count, unsigned seed = 11) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> coordinate(-3, 3);
  std::vector<Polycube> out;
  for (int trial = 0; trial < count; ++trial) {
    std::vector<Vec3i> cubes;
    for (int i = 0; i < 60; ++i) cubes.push_back({coordinate(random), coordinate(random), coordinate(random)});
    Polycube p = keepLargestAndFill(Polycube(cubes));
    makeManifold(p);
    p = keepLargestAndFill(p);
    makeManifold(p);
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace cellrelief::polycube::fixtures
