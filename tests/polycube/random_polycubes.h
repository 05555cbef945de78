// SPDX-License-Identifier: MIT
/// @file random_polycubes.h
/// Test polycubes: random cube sets made one manifold shell (keepLargestAndFill, makeManifold).
/// With 60 cubes in a 7^3 box they reach all six vertex cases, 6a and 6b included.
#pragma once

#include <random>
#include <vector>

#include <cellrelief/polycube/polycube.h>

namespace cellrelief::polycube::fixtures {

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
