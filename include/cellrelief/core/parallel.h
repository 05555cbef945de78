// SPDX-License-Identifier: MIT
/// @file parallel.h
/// Thin wrappers over TBB so that modules state parallel loops in one line and the thread count is
/// controlled in one place (ThreadLimit, e.g. 2 threads for a benchmark that compares with Embree).
#pragma once

#include <cstddef>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace cellrelief {

/// Calls body(i) for i in [begin, end), in parallel chunks of at least `grain` iterations.
template <class Body>
void parallelFor(std::size_t begin, std::size_t end, Body&& body, std::size_t grain = 1024) {
  if (begin >= end) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
                    });
}

/// Calls body(begin, end) on parallel sub-ranges: for loops that keep per-chunk state.
template <class Body>
void parallelForRange(std::size_t begin, std::size_t end, Body&& body, std::size_t grain = 1024) {
  if (begin >= end) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

/// Limits the worker threads while it lives (0 keeps TBB's default, one per core).
class ThreadLimit {
 public:
  explicit ThreadLimit(std::size_t threads) {
    if (threads > 0)
      mControl = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, threads);
  }

 private:
  std::unique_ptr<tbb::global_control> mControl;
};

}  // namespace cellrelief
