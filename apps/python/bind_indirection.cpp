// SPDX-License-Identifier: MIT
/// @file bind_indirection.cpp
/// Indirection mapping: cellrelief.indirection_map (a height map, as a file or a 2D array, to its
/// quasi-conformal indirection map I(u, v) with any optimizer of the library's table) and
/// cellrelief.optimizers.
#include <pybind11/stl/filesystem.h>

#include <cellrelief/indirection/distortion.h>
#include <cellrelief/indirection/indirection_map.h>
#include <cellrelief/indirection/optimizer_table.h>
#include <cellrelief/indirection/relief_map.h>
#ifdef CELLRELIEF_HAS_CERES
#include <cellrelief/indirection/ceres_optimizer.h>
#endif

#include "bindings.h"

namespace cellrelief::python {

namespace {

std::vector<indirection::OptimizerEntry> optimizerTable() {
  std::vector<indirection::OptimizerEntry> table = indirection::builtinOptimizers();
#ifdef CELLRELIEF_HAS_CERES
  for (indirection::OptimizerEntry& e : indirection::ceresOptimizers()) table.push_back(std::move(e));
#endif
  return table;
}

Wrap wrapOf(const std::string& name) {
  if (name == "clamp") return Wrap::Clamp;
  if (name == "repeat") return Wrap::Repeat;
  throw Error(ErrorKind::InvalidArgument, "wrap takes clamp or repeat, not '" + name + "'");
}

/// A height map from a path (as `cellrelief indirect` reads it) or from a 2D array of heights in
/// [0, 1] (row j at v = (j + 1/2) / rows).
indirection::ReliefMap reliefOf(const py::object& height, float heightScale, Wrap wrap) {
  if (!(heightScale > 0) || !std::isfinite(heightScale))
    throw Error(ErrorKind::InvalidArgument, "height_scale must be positive and finite");
  if (py::isinstance<py::str>(height) || py::hasattr(height, "__fspath__")) {
    const auto path = height.cast<std::filesystem::path>();
    return withoutGil([&] { return indirection::loadReliefMap(path, {.heightScale = heightScale, .wrap = wrap}); });
  }
  const py::array any = py::array::ensure(height);
  if (!any || any.ndim() != 2)
    throw Error(ErrorKind::InvalidArgument, "height must be a path or a 2D array of heights in [0, 1]");
  const auto h = rowsOf<float>(any, int(any.shape(1)), "height");
  for (py::ssize_t i = 0; i < h.size(); ++i)
    if (h.data()[i] < 0 || h.data()[i] > 1)
      throw Error(ErrorKind::InvalidArgument, "height has a value outside [0, 1] (at flat index " + std::to_string(i) + ")");
  return indirection::ReliefMap(int(h.shape(1)), int(h.shape(0)), std::vector<float>(h.data(), h.data() + h.size()),
                                heightScale, wrap);
}

}  // namespace

void bindIndirection(py::module_& m) {
  m.def(
      "optimizers",
      [] {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& e : optimizerTable()) out.emplace_back(e.name, e.summary);
        return out;
      },
      "The optimizers indirection_map takes: (name, what it is), the default first.");
  m.def(
      "indirection_map",
      [](const py::object& height, const std::string& optimizer, int grid, float heightScale, const std::string& wrap,
         const py::object& size, const py::object& progress, bool withReport) -> py::object {
        const indirection::ReliefMap relief = reliefOf(height, heightScale, wrapOf(wrap));
        const std::vector<indirection::OptimizerEntry> table = optimizerTable();
        const indirection::OptimizerEntry& entry = indirection::findOptimizer(table, optimizer);
        int width = relief.width(), rows = relief.height();
        if (!size.is_none()) width = rows = size.cast<int>();
        int iterations = 0;
        const indirection::ProgressCallback onProgress = [progress = py::handle(progress)](const indirection::Grid&,
                                                                    const indirection::Progress& p) {
          py::gil_scoped_acquire gil;
          if (!progress.is_none() && p.levelDone) progress(p.g, p.seconds);
          if (PyErr_CheckSignals() != 0) throw Interrupted{};
        };
        auto [map, before, after] = withoutGil([&] {
          const indirection::Grid solved = entry.run(relief, {.gridSize = grid}, onProgress, iterations);
          Image<float> I = indirection::indirectionMap(solved, width, rows);
          indirection::Distortion d0, d1;
          if (withReport) {
            d0 = indirection::measureDistortion(indirection::Grid(grid), relief, 0);
            d1 = indirection::measureDistortion(solved, relief, 0);
          }
          return std::tuple{std::move(I), d0, d1};
        });
        py::array out = arrayOf(std::move(map), false);
        if (!withReport) return out;
        py::dict r;
        r["iterations"] = iterations;
        r["l2_stretch_before"] = before.l2Stretch;
        r["l2_stretch"] = after.l2Stretch;
        r["angle_mean"] = after.angleMean;
        r["flipped_cells"] = after.flippedCells;
        return py::make_tuple(out, r);
      },
      py::arg("height"), py::kw_only(), py::arg("optimizer") = "gauss-newton", py::arg("grid") = 256,
      py::arg("height_scale") = 0.1f, py::arg("wrap") = "clamp", py::arg("size") = py::none(),
      py::arg("progress") = py::none(), py::arg("report") = false,
      R"(The indirection map I(u, v) = M^-1(u, v) - (u, v) of a height map, as `cellrelief indirect` computes it.

height: a path (PNG, JPEG, BMP grey, or a TGA's alpha) or a 2D array of heights in [0, 1]; optimizer:
a name of optimizers(); grid: g, cells per side; height_scale: relief height in tile widths; size: the
map's side (default: the height map's size). Returns (rows, columns, 2) float32 (I_u, I_v); with
report=True also a dict (iterations, L2 stretch before and after, flipped cells). progress(g, seconds)
is called after each level; Ctrl-C stops the solve.)");
}

}  // namespace cellrelief::python
