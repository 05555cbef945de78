// SPDX-License-Identifier: MIT
/// @file bind_relief.cpp
/// cellrelief.convert (a mesh to a relief model on a cubic cell complex, with the options of
/// `cellrelief convert`), cellrelief.ReliefModel (save, load, reconstruct) and load_model.
#include <pybind11/stl/filesystem.h>

#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/error_bounded.h>
#include <cellrelief/relief/model_file.h>
#include <cellrelief/relief/reconstruct.h>

#include "bindings.h"

namespace cellrelief::python {

namespace {

using ModelPtr = std::shared_ptr<relief::ReliefModel>;

projection::CentreOfProjection centreOf(const std::string& name) {
  for (int i = 0; i < 3; ++i)
    if (name == projection::kCentreOfProjectionNames[i]) return projection::CentreOfProjection(i);
  throw Error(ErrorKind::InvalidArgument, "centre takes cell, centroid or fewest-crossings, not '" + name + "'");
}

/// The conversion's progress: the user's callback (with the GIL) and a check for Ctrl-C. It holds a
/// handle, not an object: the work copies the function without the GIL, and copying an object would
/// change its reference count there; the caller's argument keeps the callback alive.
std::function<void(double)> progressOf(const py::object& callbackObject) {
  return [callback = py::handle(callbackObject)](double fraction) {
    py::gil_scoped_acquire gil;
    if (!callback.is_none()) callback(fraction);
    if (PyErr_CheckSignals() != 0) throw Interrupted{};
  };
}

py::dict reportOf(const relief::ConvertReport& r) {
  py::dict d;
  d["seconds"] = r.totalSeconds;
  d["grid_seconds"] = r.gridSeconds;
  d["sample_seconds"] = r.sampleSeconds;
  d["grey_cells"] = r.greyCells;
  d["layers"] = r.layers;
  d["filled_samples"] = r.filledSamples;
  d["empty_samples"] = r.emptySamples;
  d["lines_crossed_twice"] = r.linesCrossedTwice;
  d["moved_centres"] = r.movedCentres;
  d["slab_thickness"] = r.slabThicknessWS;
  return d;
}

py::object convert(const TriangleMesh& mesh, const py::object& grid, int texels, int bits, double maxError,
                   const std::string& metric, const std::string& centre, bool forceNormals, bool colors,
                   const py::object& progress, bool withReport) {
  relief::ConvertOptions co;
  if (py::isinstance<py::str>(grid)) {
    if (grid.cast<std::string>() != "auto")
      throw Error(ErrorKind::InvalidArgument, "grid takes a cell count per side or 'auto'");
  } else {
    co.gridSize = grid.cast<int>();
    if (co.gridSize < 1) throw Error(ErrorKind::InvalidArgument, "grid must be at least 1 (or 'auto')");
  }
  co.texels = texels;
  co.distanceBits = bits;
  co.centre = centreOf(centre);
  co.forceNormals = forceNormals;
  co.colors = colors;
  co.progress = progressOf(progress);
  if (metric != "rms" && metric != "hausdorff")
    throw Error(ErrorKind::InvalidArgument, "metric takes rms or hausdorff, not '" + metric + "'");
  relief::ConvertReport report;
  auto model = std::make_shared<relief::ReliefModel>(withoutGil([&] {
    if (!(maxError > 0)) return relief::convert(mesh, co, &report);
    relief::ErrorBoundOptions eb;
    eb.maxError = maxError;
    eb.metric = metric == "hausdorff" ? relief::ErrorMetric::Hausdorff : relief::ErrorMetric::Rms;
    eb.convert = co;
    return relief::convertWithErrorBound(mesh, eb).model;
  }));
  if (!withReport) return py::cast(model);
  return py::make_tuple(model, reportOf(report));
}

}  // namespace

void bindRelief(py::module_& m) {
  py::class_<relief::ReliefModel, ModelPtr>(m, "ReliefModel",
                                            "A relief model on a cubic cell complex (cellrelief.convert, load_model).")
      .def_property_readonly("grid_size", [](const relief::ReliefModel& r) { return r.gridSize; },
                             "N, cells per side of the grid")
      .def_property_readonly("texels", [](const relief::ReliefModel& r) { return r.texels; },
                             "T, samples per side of a face")
      .def_property_readonly("cell_size", [](const relief::ReliefModel& r) { return r.cellSizeWS; })
      .def_property_readonly("grey_cells", [](const relief::ReliefModel& r) { return r.cells.size(); })
      .def_property_readonly("layers", &relief::ReliefModel::layerCount)
      .def_property_readonly("distance_bits", [](const relief::ReliefModel& r) { return r.distanceCodec.bits; })
      .def_property_readonly("has_normals",
                             [](const relief::ReliefModel& r) { return r.normalFormat != relief::NormalFormat::None; })
      .def_property_readonly("has_colors",
                             [](const relief::ReliefModel& r) { return r.colorFormat != relief::ColorFormat::None; })
      .def_property_readonly("nbytes", &relief::ReliefModel::byteSize, "bytes of maps and tables")
      .def_property_readonly("max_lod", [](const relief::ReliefModel& r) { return relief::maxLevelOfDetail(r); })
      .def(
          "bounds", [](const relief::ReliefModel& r) {
            const Vec3d lo = r.originWS, hi = r.originWS + Vec3d(r.cellSizeWS * r.gridSize);
            return arrayOf(std::vector<double>{lo.x, lo.y, lo.z, hi.x, hi.y, hi.z}, {2, 3});
          },
          "(2, 3): the grid's lowest and highest corner")
      .def(
          "save", [](const relief::ReliefModel& r, const std::filesystem::path& path) {
            withoutGil([&] {
              relief::writeRelief(r, path);
              return 0;
            });
          },
          py::arg("path"), "Writes the model (.crm), atomically.")
      .def(
          "reconstruct",
          [](const relief::ReliefModel& r, int lod, const std::string& method) {
            relief::ReconstructOptions o;
            o.levelOfDetail = lod;
            if (method == "auto") o.method = relief::ReconstructionMethod::Auto;
            else if (method == "closed") o.method = relief::ReconstructionMethod::Closed;
            else if (method == "per-face") o.method = relief::ReconstructionMethod::PerFace;
            else throw Error(ErrorKind::InvalidArgument, "method takes auto, closed or per-face, not '" + method + "'");
            return std::make_shared<TriangleMesh>(withoutGil([&] { return relief::reconstruct(r, o); }));
          },
          py::arg("lod") = 0, py::arg("method") = "auto",
          "The surface the model holds, as a Mesh (closed for a closed input by default).")
      .def("__repr__", [](const relief::ReliefModel& r) {
        return "<cellrelief.ReliefModel N=" + std::to_string(r.gridSize) + " T=" + std::to_string(r.texels) + ", " +
               std::to_string(r.cells.size()) + " grey cells, " + std::to_string(r.byteSize()) + " bytes>";
      });

  m.def(
      "load_model",
      [](const std::filesystem::path& path) {
        return std::make_shared<relief::ReliefModel>(withoutGil([&] { return relief::readRelief(path); }));
      },
      py::arg("path"), "Reads a relief model (.crm). Raises cellrelief.Error naming the file on bad input.");
  m.def("convert", &convert, py::arg("mesh"), py::kw_only(), py::arg("grid") = py::str("auto"),
        py::arg("texels") = 0, py::arg("bits") = 16, py::arg("max_error") = 0.0, py::arg("metric") = "rms",
        py::arg("centre") = "fewest-crossings", py::arg("force_normals") = false, py::arg("colors") = true,
        py::arg("progress") = py::none(), py::arg("report") = false,
        R"(Converts a mesh to a relief model, as `cellrelief convert` does.

grid: cells per side, or 'auto' (from the occlusion ratio); texels: samples per face side (0: chosen);
bits: 16 or 8; max_error > 0: the smallest model whose error (metric 'rms' or 'hausdorff', a fraction
of the bounding box diagonal) is at most this; centre: cell, centroid or fewest-crossings; progress:
called with the fraction done (0..1). The GIL is released while it works, and Ctrl-C stops it.
With report=True, returns (model, dict of timings and counts).)");
}

}  // namespace cellrelief::python
