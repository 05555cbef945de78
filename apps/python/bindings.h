// SPDX-License-Identifier: MIT
/// @file bindings.h
/// The pieces of the `cellrelief` Python module (pybind11): one function per part of the library,
/// each adding its classes and functions to the module, and the helpers they share: NumPy arrays
/// in (checked for shape, dtype and finite values, with an error that names the argument) and out
/// (owning their C++ buffer, so a frame or a map is not copied), errors as Python exceptions, and
/// work that releases the GIL and stops on Ctrl-C.
#pragma once

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <cellrelief/core/error.h>
#include <cellrelief/core/image.h>
#include <cellrelief/core/math.h>

namespace cellrelief::python {

namespace py = pybind11;

void bindErrors(py::module_& m);
void bindMeshes(py::module_& m);
void bindRelief(py::module_& m);
void bindRendering(py::module_& m);
void bindIndirection(py::module_& m);
void bindGeoTex(py::module_& m);
/// After bindRendering: it adds Scene.add(PolycubeMap).
void bindPolycube(py::module_& m);

/// Thrown out of long work when Python has a signal pending (Ctrl-C): the binding re-raises the
/// Python exception (KeyboardInterrupt) once the work has unwound.
struct Interrupted {};

/// Checks for a pending signal from any thread (the GIL is taken for the check); throws
/// Interrupted when one is pending. Call it from progress callbacks of work that released the GIL.
inline void checkSignals() {
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) throw Interrupted{};
}

/// Runs `work` without the GIL, turning Interrupted back into the pending Python exception.
template <class Work>
auto withoutGil(Work&& work) {
  try {
    py::gil_scoped_release release;
    return work();
  } catch (const Interrupted&) {
    throw py::error_already_set();
  }
}

/// An (n, columns) array of `T` from any real (or integer, for indices) NumPy array: the values
/// copied row by row (one pass; the C++ side owns its own vectors). Throws InvalidArgument naming
/// `what` for a wrong shape, dtype or (for reals) a value that is not finite.
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> rowsOf(const py::handle& value, int columns,
                                                                 const char* what) {
  const py::array any = py::array::ensure(value);
  if (!any) throw Error(ErrorKind::InvalidArgument, std::string(what) + " must be an array");
  const char kind = any.dtype().kind();
  if constexpr (std::is_floating_point_v<T>) {
    if (kind != 'f' && kind != 'i' && kind != 'u')
      throw Error(ErrorKind::InvalidArgument, std::string(what) + " must hold real numbers, not dtype " +
                                                  std::string(py::str(any.dtype())));
  } else if (kind != 'i' && kind != 'u') {
    throw Error(ErrorKind::InvalidArgument, std::string(what) + " must hold integers, not dtype " +
                                                std::string(py::str(any.dtype())));
  }
  if (any.ndim() != 2 || any.shape(1) != columns)
    throw Error(ErrorKind::InvalidArgument, std::string(what) + " must have shape (n, " + std::to_string(columns) +
                                                "), not " + std::string(py::str(py::tuple(any.attr("shape")))));
  auto rows = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(any);
  if (!rows) throw py::error_already_set();
  if constexpr (std::is_floating_point_v<T>) {
    const T* p = rows.data();
    for (py::ssize_t i = 0; i < rows.size(); ++i)
      if (!std::isfinite(p[i]))
        throw Error(ErrorKind::InvalidArgument, std::string(what) + " has a value that is not finite (row " +
                                                    std::to_string(i / columns) + ")");
  }
  return rows;
}

/// A NumPy array that owns `image` (moved in): (height, width) or (height, width, channels).
template <TexelScalar T>
py::array arrayOf(Image<T>&& image, bool dropSingleChannel = true) {
  if (image.isEmpty()) return py::array_t<T>(std::vector<py::ssize_t>{0, 0});
  auto* owner = new Image<T>(std::move(image));
  const py::capsule free(owner, [](void* p) { delete static_cast<Image<T>*>(p); });
  std::vector<py::ssize_t> shape{owner->height(), owner->width()};
  if (!dropSingleChannel || owner->channels() > 1) shape.push_back(owner->channels());
  return py::array_t<T>(shape, owner->levelData(0).data(), free);
}

/// A NumPy array that owns `values` (moved in), of the given shape.
template <class T>
py::array arrayOf(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owner = new std::vector<T>(std::move(values));
  const py::capsule free(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owner->data(), free);
}

/// A 3-vector from a Python sequence of 3 finite numbers, naming `what` when it is not one.
inline Vec3d vec3Of(const py::handle& value, const char* what) {
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!v || v.size() != 3 || !std::isfinite(v.data()[0]) || !std::isfinite(v.data()[1]) || !std::isfinite(v.data()[2])) {
    PyErr_Clear();
    throw Error(ErrorKind::InvalidArgument, std::string(what) + " must be 3 finite numbers");
  }
  return {v.data()[0], v.data()[1], v.data()[2]};
}

}  // namespace cellrelief::python
