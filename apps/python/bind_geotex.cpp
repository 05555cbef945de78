// SPDX-License-Identifier: MIT
/// @file bind_geotex.cpp
/// Geometry textures: cellrelief.convert_geotex (VSA charts as height maps in oriented boxes),
/// cellrelief.GeoTexModel (save, load_geotex).
#include <pybind11/stl/filesystem.h>

#include <cellrelief/geotex/convert.h>
#include <cellrelief/geotex/geotex_file.h>

#include "bindings.h"

namespace cellrelief::python {

void bindGeoTex(py::module_& m) {
  using geotex::GeoTexModel;
  py::class_<GeoTexModel, std::shared_ptr<GeoTexModel>>(m, "GeoTexModel",
                                                        "Geometry textures: charts as height maps in oriented boxes.")
      .def_property_readonly("charts", [](const GeoTexModel& g) { return g.charts.size(); })
      .def_property_readonly("texels", &GeoTexModel::texelCount)
      .def_property_readonly("has_colors", &GeoTexModel::hasColors)
      .def_property_readonly("nbytes", &GeoTexModel::byteSize)
      .def(
          "bounds", [](const GeoTexModel& g) {
            const Aabbd b = g.boundsWS();
            return arrayOf(std::vector<double>{b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}, {2, 3});
          },
          "(2, 3): the charts' boxes' lowest and highest corner")
      .def(
          "save", [](const GeoTexModel& g, const std::filesystem::path& path) {
            withoutGil([&] {
              geotex::writeGeoTex(g, path);
              return 0;
            });
          },
          py::arg("path"), "Writes the model (.cgt), atomically.")
      .def("__repr__", [](const GeoTexModel& g) {
        return "<cellrelief.GeoTexModel " + std::to_string(g.charts.size()) + " charts, " +
               std::to_string(g.texelCount()) + " texels>";
      });
  m.def(
      "load_geotex",
      [](const std::filesystem::path& path) {
        return std::make_shared<GeoTexModel>(withoutGil([&] { return geotex::readGeoTex(path); }));
      },
      py::arg("path"), "Reads a geometry-texture model (.cgt).");
  m.def(
      "convert_geotex",
      [](const TriangleMesh& mesh, int charts, int maxTexels, int bits, const py::object& progress) {
        geotex::GeoTexOptions o;
        o.vsa.proxies = charts;
        o.maxTexels = maxTexels;
        o.heightBits = bits;
        o.vsa.progress = [progress = py::handle(progress)](double fraction) {  // a handle: see progressOf
          py::gil_scoped_acquire gil;
          if (!progress.is_none()) progress(fraction);
          if (PyErr_CheckSignals() != 0) throw Interrupted{};
        };
        return std::make_shared<GeoTexModel>(withoutGil([&] { return geotex::convertMesh(mesh, o).model; }));
      },
      py::arg("mesh"), py::kw_only(), py::arg("charts") = 64, py::arg("max_texels") = 128, py::arg("bits") = 16,
      py::arg("progress") = py::none(),
      "Converts a mesh to geometry textures (`cellrelief geotex`): `charts` VSA regions, maps of at most "
      "`max_texels` a side. Ctrl-C stops the partition.");
}

}  // namespace cellrelief::python
