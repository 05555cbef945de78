// SPDX-License-Identifier: MIT
/// @file module.cpp
/// The `cellrelief` Python module: the library's errors as Python exceptions, then each part's
/// bindings (bindings.h). Built as `_cellrelief`; the package `cellrelief` (cellrelief/__init__.py)
/// re-exports it.
#include "bindings.h"

#include <cellrelief/version.h>

namespace cellrelief::python {

namespace {

/// One Python class per ErrorKind, all under cellrelief.Error, each also under the built-in
/// exception a Python user would catch for it (ValueError, FileNotFoundError, OSError, MemoryError).
struct ErrorClasses {
  py::object base;
  py::object byKind[7];
};

/// Never freed: a static's destructor would release Python objects after the interpreter is gone.
ErrorClasses& errorClasses() {
  static ErrorClasses* classes = new ErrorClasses;
  return *classes;
}

py::object newErrorClass(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string qualified = std::string("cellrelief.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  py::object cls = py::reinterpret_steal<py::object>(type);
  m.attr(name) = cls;
  return cls;
}

}  // namespace

void bindErrors(py::module_& m) {
  ErrorClasses& c = errorClasses();
  c.base = newErrorClass(m, "Error", py::make_tuple(py::handle(PyExc_Exception)),
                         "Every error of cellrelief; its message names the file and the problem.");
  const auto sub = [&](ErrorKind kind, const char* name, PyObject* builtin, const char* doc) {
    const py::tuple bases = builtin ? py::make_tuple(c.base, py::handle(builtin)) : py::make_tuple(c.base);
    c.byKind[int(kind)] = newErrorClass(m, name, bases, doc);
  };
  sub(ErrorKind::InvalidArgument, "InvalidArgumentError", PyExc_ValueError, "A parameter out of its range.");
  sub(ErrorKind::InvalidInput, "InvalidInputError", PyExc_ValueError, "Data that cannot be used (NaN, bad indices, ...).");
  sub(ErrorKind::FileNotFound, "FileNotFoundError", PyExc_FileNotFoundError, "A path that does not exist or cannot be opened.");
  sub(ErrorKind::FileFormat, "FileFormatError", nullptr, "Bytes that are not a valid file of the expected format.");
  sub(ErrorKind::FileWrite, "FileWriteError", PyExc_OSError, "An output file that could not be written.");
  sub(ErrorKind::Unsupported, "UnsupportedError", nullptr, "A valid request this build or machine cannot serve.");
  sub(ErrorKind::ResourceLimit, "ResourceLimitError", PyExc_MemoryError, "A request beyond a memory or size limit.");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      PyErr_SetString(errorClasses().byKind[int(e.kind())].ptr(), e.what());
    }
  });
}

}  // namespace cellrelief::python

PYBIND11_MODULE(_cellrelief, m) {
  namespace cp = cellrelief::python;
  m.doc() = "cellrelief: relief representations of surfaces (cubic cell complexes, geometry textures, "
            "indirection maps, polycube maps) and their ray tracing on the CPU, OpenGL and Vulkan, with NumPy arrays in and out.";
  m.attr("__version__") = CELLRELIEF_VERSION_STRING;
  cp::bindErrors(m);
  cp::bindMeshes(m);
  cp::bindRelief(m);
  cp::bindGeoTex(m);
  cp::bindIndirection(m);
  cp::bindRendering(m);
  cp::bindPolycube(m);
}
