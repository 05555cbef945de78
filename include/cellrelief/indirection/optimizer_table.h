// SPDX-License-Identifier: MIT
/// @file optimizer_table.h
/// The parameterization optimizers by name, in one table as the backends are: the command line,
/// the comparison and user code choose from it instead of comparing strings. The GLM-only
/// optimizers are here; ceres_optimizer.h adds `ceresOptimizers()` (its own target, since it brings
/// Ceres and Eigen), which callers append when they link it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/indirection/gauss_newton.h"
#include "cellrelief/indirection/springs.h"

namespace cellrelief::indirection {

/// What a caller sets for any optimizer of the table: the resolution, and the options only some
/// optimizers read (each entry takes what applies to it and ignores the rest).
struct OptimizerSettings {
  int gridSize = 256;
  SpringForce springForce = SpringForce::InPlane;  ///< the springs' force (springs, springs-chord)
};

/// One optimizer: its name, what it is in a line, and how to run it (the number of iterations it
/// took goes to `iterations`).
struct OptimizerEntry {
  std::string name, summary;
  std::function<Grid(const ReliefMap&, const OptimizerSettings&, const ProgressCallback&, int& iterations)> run;
};

/// Gauss-Newton (the default: the fastest to within 1% of the lowest distortion, see
/// docs/indirection.md), the paper's springs, and the springs with lengths between the vertices.
inline std::vector<OptimizerEntry> builtinOptimizers() {
  auto springs = [](bool chord) {
    return [chord](const ReliefMap& relief, const OptimizerSettings& settings, const ProgressCallback& progress,
                   int& iterations) {
      SpringOptions o;
      o.gridSize = settings.gridSize;
      o.force = settings.springForce;
      if (chord) o.minSteps = o.maxSteps = 1;  // corner-to-corner lengths
      SpringReport r;
      Grid grid = relaxSprings(relief, o, progress, &r);
      iterations = r.iterations;
      return grid;
    };
  };
  return {
      {"gauss-newton",
       "the conformal energy on the relief's averaged metric, damped Gauss-Newton with multigrid",
       [](const ReliefMap& relief, const OptimizerSettings& settings, const ProgressCallback& progress,
          int& iterations) {
         GaussNewtonOptions o;
         o.gridSize = settings.gridSize;
         GaussNewtonReport r;
         Grid grid = optimizeGaussNewton(relief, o, progress, &r);
         iterations = r.iterations;
         return grid;
       }},
      {"springs", "the paper's spring network, lengths integrated on the surface", springs(false)},
      {"springs-chord", "the springs with lengths between the grid vertices only", springs(true)},
  };
}

/// The entry called `name`; throws a clear error listing the names otherwise.
inline const OptimizerEntry& findOptimizer(const std::vector<OptimizerEntry>& table,
                                           const std::string& name) {
  std::string names;
  for (const OptimizerEntry& e : table) {
    if (e.name == name) return e;
    names += (names.empty() ? "" : ", ") + e.name;
  }
  throw Error(ErrorKind::InvalidArgument,
              "optimizers are " + names + ", not '" + name + "'");
}

}  // namespace cellrelief::indirection
