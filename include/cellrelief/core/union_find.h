// SPDX-License-Identifier: MIT
/// @file union_find.h
/// Disjoint sets with path halving and union by size: components of meshes, fans around vertices,
/// boundary loops, connected regions of grids.
#pragma once

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace cellrelief {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : mParent(n), mSize(n, 1) {
    std::iota(mParent.begin(), mParent.end(), std::uint32_t(0));
  }
  std::uint32_t find(std::uint32_t x) {
    while (mParent[x] != x) {
      mParent[x] = mParent[mParent[x]];
      x = mParent[x];
    }
    return x;
  }
  /// Joins the sets of a and b; returns false when they were already one set.
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (mSize[a] < mSize[b]) std::swap(a, b);
    mParent[b] = a;
    mSize[a] += mSize[b];
    return true;
  }
  std::size_t size() const { return mParent.size(); }

 private:
  std::vector<std::uint32_t> mParent;
  std::vector<std::uint32_t> mSize;
};

}  // namespace cellrelief
