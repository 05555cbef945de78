// SPDX-License-Identifier: MIT
/// @file optimizer.h
/// What the two optimizers (springs, Ceres) share: the multi-scale schedule, the progress report,
/// and a clock that leaves the caller's progress callback out of the measured time, so that the
/// comparison app can measure distortion after every step without charging it to the optimizer.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "cellrelief/indirection/grid.h"

namespace cellrelief::indirection {

/// One report from an optimizer, handed to its ProgressCallback together with the current grid.
struct Progress {
  int g = 0;              ///< the resolution of the level being solved
  int iteration = 0;      ///< iterations so far on this level
  double seconds = 0;     ///< optimizer time since the start, callbacks excluded
  double energy = 0;      ///< springs: total in-plane force; Ceres: the cost
  bool finalLevel = false;
  bool levelDone = false;
};

/// Called every few iterations; the optimizer does not count the time it takes.
using ProgressCallback = std::function<void(const Grid&, const Progress&)>;

/// The resolutions solved in turn: start, 2 start, 4 start, ... and finally `target` (the paper's
/// "start at g = 16 and double"). A target at or below `start` is solved directly.
inline std::vector<int> multiScaleSchedule(int target, int start = 16) {
  checkGridSize(target);
  std::vector<int> levels;
  if (start < 2) start = 2;
  for (int g = start; g < target; g *= 2) levels.push_back(g);
  levels.push_back(target);
  return levels;
}

/// Wall time minus the time spent in callbacks.
class OptimizerClock {
 public:
  OptimizerClock() : mStart(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count() -
           mExcluded;
  }
  /// Runs `callback(args...)` and excludes its time.
  template <class F, class... Args>
  void excluding(F& callback, Args&&... args) {
    if (!callback) return;
    const auto t0 = std::chrono::steady_clock::now();
    callback(std::forward<Args>(args)...);
    mExcluded += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

 private:
  std::chrono::steady_clock::time_point mStart;
  double mExcluded = 0;
};

}  // namespace cellrelief::indirection
