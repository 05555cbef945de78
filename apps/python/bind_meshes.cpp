// SPDX-License-Identifier: MIT
/// @file bind_meshes.cpp
/// cellrelief.Mesh: a triangle mesh made from NumPy arrays (float32 or float64 vertices, int32,
/// int64 or uint32 faces) or read from a file, whose arrays come back as read-only views of its
/// own memory (no copy); read_mesh and write_mesh.
#include <pybind11/stl/filesystem.h>

#include <cellrelief/core/triangle_mesh.h>
#include <cellrelief/io/mesh_io.h>

#include "bindings.h"

namespace cellrelief::python {

namespace {

using MeshPtr = std::shared_ptr<TriangleMesh>;

/// A read-only view of `count` rows of `columns` values of T at `data`, keeping `owner` alive.
template <class T>
py::array view(const T* data, std::size_t count, int columns, const py::handle& owner) {
  py::array a = py::array_t<T>({py::ssize_t(count), py::ssize_t(columns)}, data, owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

MeshPtr meshOf(const py::handle& vertices, const py::handle& faces, const py::handle& normals, const py::handle& uvs) {
  auto mesh = std::make_shared<TriangleMesh>();
  const auto v = rowsOf<float>(vertices, 3, "vertices");
  const auto f = rowsOf<std::int64_t>(faces, 3, "faces");
  mesh->positions.resize(std::size_t(v.shape(0)));
  std::memcpy(mesh->positions.data(), v.data(), std::size_t(v.size()) * sizeof(float));
  mesh->triangles.resize(std::size_t(f.shape(0)));
  const std::int64_t* idx = f.data();
  const std::int64_t n = std::int64_t(mesh->positions.size());
  for (std::size_t t = 0; t < mesh->triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t i = idx[3 * t + std::size_t(k)];
      if (i < 0 || i >= n)
        throw Error(ErrorKind::InvalidArgument, "faces: row " + std::to_string(t) + " refers to vertex " +
                                                    std::to_string(i) + ", but there are " + std::to_string(n) +
                                                    " vertices");
      mesh->triangles[t][k] = std::uint32_t(i);
    }
  if (!normals.is_none()) {
    const auto nrm = rowsOf<float>(normals, 3, "normals");
    if (nrm.shape(0) != v.shape(0))
      throw Error(ErrorKind::InvalidArgument, "normals: one per vertex is needed");
    mesh->normals.resize(mesh->positions.size());
    std::memcpy(mesh->normals.data(), nrm.data(), std::size_t(nrm.size()) * sizeof(float));
  }
  if (!uvs.is_none()) {
    // Per corner (3 per face, as an OBJ's vt indices give them) or per vertex.
    const auto uv = rowsOf<float>(uvs, 2, "uvs");
    const auto row = [&](std::size_t i) { return Vec2f(uv.data()[2 * i], uv.data()[2 * i + 1]); };
    if (std::size_t(uv.shape(0)) == 3 * mesh->triangles.size()) {
      for (std::size_t i = 0; i < std::size_t(uv.shape(0)); ++i) mesh->uvs.push_back(row(i));
    } else if (uv.shape(0) == v.shape(0)) {
      for (const Vec3u& t : mesh->triangles)
        for (int k = 0; k < 3; ++k) mesh->uvs.push_back(row(t[k]));
    } else {
      throw Error(ErrorKind::InvalidArgument, "uvs: one per corner (3 per face) or one per vertex is needed");
    }
  }
  mesh->validate();
  return mesh;
}

}  // namespace

void bindMeshes(py::module_& m) {
  py::class_<TriangleMesh, MeshPtr>(m, "Mesh", R"(A triangle mesh.

Mesh(vertices, faces, normals=None, uvs=None): vertices (n, 3) float32 or float64, faces (m, 3)
int32, int64 or uint32 indices, normals (n, 3) per vertex, uvs (3 m, 2) per corner or (n, 2) per
vertex. The arrays are checked (shape, dtype, finite values, indices in range) and copied once into
the mesh; its properties are read-only views of that copy.)")
      .def(py::init(&meshOf), py::arg("vertices"), py::arg("faces"), py::arg("normals") = py::none(),
           py::arg("uvs") = py::none())
      .def_property_readonly(
          "vertices", [](const py::object& self) {
            const auto& mesh = self.cast<const TriangleMesh&>();
            return view(&mesh.positions.data()->x, mesh.positions.size(), 3, self);
          },
          "(n, 3) float32, a read-only view")
      .def_property_readonly(
          "faces", [](const py::object& self) {
            const auto& mesh = self.cast<const TriangleMesh&>();
            return view(&mesh.triangles.data()->x, mesh.triangles.size(), 3, self);
          },
          "(m, 3) uint32, a read-only view")
      .def_property_readonly(
          "normals", [](const py::object& self) -> py::object {
            const auto& mesh = self.cast<const TriangleMesh&>();
            if (mesh.normals.empty()) return py::none();
            return view(&mesh.normals.data()->x, mesh.normals.size(), 3, self);
          },
          "(n, 3) float32 per vertex, or None")
      .def_property_readonly(
          "uvs", [](const py::object& self) -> py::object {
            const auto& mesh = self.cast<const TriangleMesh&>();
            if (mesh.uvs.empty()) return py::none();
            return view(&mesh.uvs.data()->x, mesh.uvs.size(), 2, self);
          },
          "(3 m, 2) float32 per corner, or None")
      .def_property_readonly("vertex_count", &TriangleMesh::vertexCount)
      .def_property_readonly("face_count", &TriangleMesh::triangleCount)
      .def(
          "bounds", [](const TriangleMesh& mesh) {
            const Aabbf b = mesh.bounds();
            return arrayOf(std::vector<float>{b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}, {2, 3});
          },
          "(2, 3): the lowest and the highest corner")
      .def("__repr__", [](const TriangleMesh& mesh) {
        return "<cellrelief.Mesh " + std::to_string(mesh.vertexCount()) + " vertices, " +
               std::to_string(mesh.triangleCount()) + " faces" + (mesh.hasUVs() ? ", uvs" : "") + ">";
      });

  m.def(
      "read_mesh",
      [](const std::filesystem::path& path, bool normals, bool colors, bool uvs) {
        return std::make_shared<TriangleMesh>(withoutGil([&] {
          return io::readMesh(path, {.normals = normals, .colors = colors, .uvs = uvs});
        }));
      },
      py::arg("path"), py::arg("normals") = true, py::arg("colors") = true, py::arg("uvs") = true,
      "Reads an OBJ, PLY, OFF or STL mesh. Raises cellrelief.Error (naming the file) on bad input.");
  m.def(
      "write_mesh",
      [](const TriangleMesh& mesh, const std::filesystem::path& path) {
        withoutGil([&] {
          io::writeMesh(mesh, path);
          return 0;
        });
      },
      py::arg("mesh"), py::arg("path"), "Writes the mesh (format by extension: .obj .ply .off .stl).");
}

}  // namespace cellrelief::python
