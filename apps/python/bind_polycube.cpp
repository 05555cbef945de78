// SPDX-License-Identifier: MIT
/// @file bind_polycube.cpp
/// PolyCube-Maps: cellrelief.polycube_map (a mesh mapped onto its polycube, built automatically or
/// given as an (k, 3) array of cubes, with T2 baked from a signal: `cellrelief polycube`),
/// cellrelief.PolycubeMap (cubes, frame, texture positions, distortion and T2 as arrays; save writes
/// what `cellrelief render dir` reads) and load_polycube. A Scene takes a PolycubeMap.
#include <pybind11/stl/filesystem.h>

#include <cellrelief/polycube/mesh_map.h>
#include <cellrelief/polycube/polycube_result.h>
#include <cellrelief/render/scene.h>

#include "bindings.h"

namespace cellrelief::python {

namespace {

/// A mesh mapped onto its polycube: what a scene renders, with where it came from.
struct PolycubeMap {
  std::shared_ptr<polycube::TexturedMesh> textured;
  polycube::PolycubeFrame frame;
  int cubesPerSide = 0;                                  ///< the automatic search's N; 0 for given cubes
  std::optional<polycube::PolycubeParameterization> map;  ///< none for a map loaded from files

  const polycube::Polycube& cubes() const { return textured->t2->surface().polycube(); }
};

/// Cubes from an (k, 3) integer array, with an optional frame (origin, size).
polycube::PolycubeFile cubesOf(const py::handle& cubes, const py::object& origin, const py::object& cubeSize) {
  const auto rows = rowsOf<std::int64_t>(cubes, 3, "cubes");
  std::vector<Vec3i> list(std::size_t(rows.shape(0)));
  const std::int64_t* p = rows.data();
  constexpr std::int64_t kLimit = polycube::Polycube::kMaxCoordinate - 2;  // as polycube_file.h reads them
  for (std::size_t i = 0; i < list.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const std::int64_t v = p[3 * i + std::size_t(c)];
      if (v < -kLimit || v > kLimit)
        throw Error(ErrorKind::InvalidArgument, "cubes: row " + std::to_string(i) + " has a coordinate beyond +-" +
                                                    std::to_string(kLimit));
      list[i][c] = int(v);
    }
  }
  if (list.empty()) throw Error(ErrorKind::InvalidArgument, "cubes: no cubes");
  if (list.size() > polycube::kMaxCubes) throw Error(ErrorKind::ResourceLimit, "cubes: more than 2^24 cubes");
  polycube::PolycubeFile file;
  file.polycube = polycube::Polycube(std::move(list));
  if (origin.is_none() != cubeSize.is_none())
    throw Error(ErrorKind::InvalidArgument, "origin and cube_size place the cubes together: give both or neither");
  if (!origin.is_none()) {
    file.frame.origin = vec3Of(origin, "origin");
    file.frame.cubeSize = cubeSize.cast<double>();
    if (!(file.frame.cubeSize > 0) || !std::isfinite(file.frame.cubeSize))
      throw Error(ErrorKind::InvalidArgument, "cube_size must be a positive finite number");
    file.hasFrame = true;
  }
  return file;
}

py::dict distortionOf(const polycube::Distortion& d) {
  py::dict out;
  out["area"] = d.area;
  out["angle"] = d.angle;
  out["stretch_efficiency"] = d.stretchEfficiency;
  out["flipped"] = d.flipped;
  return out;
}

PolycubeMap polycubeMapOf(const TriangleMesh& mesh, const py::object& grid, const py::object& cubes,
                          const py::object& origin, const py::object& cubeSize, const std::string& energy, int sweeps,
                          const std::string& signal, int texels, const py::object& progress) {
  polycube::MeshMapOptions o;
  if (py::isinstance<py::str>(grid)) {
    if (grid.cast<std::string>() != "auto")
      throw Error(ErrorKind::InvalidArgument, "grid takes a cube count per side or 'auto'");
  } else if (!py::isinstance<py::int_>(grid)) {
    throw Error(ErrorKind::InvalidArgument, "grid takes a cube count per side (an integer) or 'auto'");
  } else {
    if (!cubes.is_none()) throw Error(ErrorKind::InvalidArgument, "grid and cubes: give one, the cubes need no grid");
    o.polycube.cubesPerSide = grid.cast<int>();
    if (o.polycube.cubesPerSide < 2 || o.polycube.cubesPerSide > 256)
      throw Error(ErrorKind::InvalidArgument, "grid must lie in 2..256 (or be 'auto')");
  }
  if (!cubes.is_none()) o.cubes = cubesOf(cubes, origin, cubeSize);
  else if (!origin.is_none() || !cubeSize.is_none())
    throw Error(ErrorKind::InvalidArgument, "origin and cube_size place given cubes: pass cubes too");
  const std::optional<polycube::PolycubeEnergy> e = polycube::parsePolycubeEnergy(energy);
  if (!e) throw Error(ErrorKind::InvalidArgument, "energy: '" + energy + "' is not mvc, mips or extended-mips");
  o.map.energy = *e;
  if (sweeps < 1 || sweeps > 100000) throw Error(ErrorKind::InvalidArgument, "sweeps must lie in 1..100000");
  o.map.maxSweeps = sweeps;
  o.signal = polycube::parseSignal(signal, "signal");
  o.texelsPerSquarelet = texels;
  // Progress after each sweep: the user's callback (with the GIL) and a check for Ctrl-C. A handle,
  // not an object: the options are copied without the GIL (progressOf in bind_relief.cpp says why).
  o.map.progress = [progress = py::handle(progress)](int sweep, const polycube::Distortion& d) {
    py::gil_scoped_acquire gil;
    if (!progress.is_none()) progress(sweep, distortionOf(d));
    if (PyErr_CheckSignals() != 0) throw Interrupted{};
  };
  polycube::MeshMap result = withoutGil([&] { return polycube::mapMeshOntoPolycube(mesh, o); });
  PolycubeMap out;
  out.textured = std::move(result.textured);
  out.frame = result.domain.frame;
  out.cubesPerSide = result.domain.search ? result.domain.search->cubesPerSide : 0;
  out.map = std::move(result.map);
  return out;
}

PolycubeMap loadPolycube(const std::filesystem::path& dir) {
  return withoutGil([&] {
    if (!polycube::isPolycubeResult(dir))
      throw Error(ErrorKind::FileNotFound, dir,
                  std::string("not a polycube result: it needs ") + polycube::kResultCubes + " and " +
                      polycube::kResultMesh);
    PolycubeMap out;
    out.textured = polycube::readPolycubeResult(dir);
    out.frame = polycube::readPolycube(dir / polycube::kResultCubes).frame;
    return out;
  });
}

}  // namespace

void bindPolycube(py::module_& m) {
  py::class_<PolycubeMap>(m, "PolycubeMap", R"(A mesh mapped onto its polycube (PolyCube-Maps), with T2.

Arrays: cubes (k, 3) int32 lattice coordinates of the cubes' lowest corners, texture (n, 3) float32
each vertex's position on the polycube's surface in lattice units, t2 the texture atlas (h, w, 4)
uint8 (every squarelet's tile, mip levels below). origin and cube_size place the lattice in world
space. Scene.add takes it.)")
      .def_property_readonly(
          "mesh", [](const PolycubeMap& p) { return std::make_shared<TriangleMesh>(p.textured->mesh); },
          "The mapped mesh (a copy)")
      .def_property_readonly(
          "cubes",
          [](const PolycubeMap& p) {
            const auto cubes = p.cubes().cubes();
            std::vector<std::int32_t> values;
            values.reserve(3 * cubes.size());
            for (const Vec3i& c : cubes) values.insert(values.end(), {c.x, c.y, c.z});
            return arrayOf(std::move(values), {py::ssize_t(cubes.size()), 3});
          })
      .def_property_readonly(
          "texture",
          [](const py::object& self) {
            const auto& texture = self.cast<const PolycubeMap&>().textured->texture;
            py::array a = py::array_t<float>({py::ssize_t(texture.size()), py::ssize_t(3)}, &texture.data()->x, self);
            a.attr("setflags")(py::arg("write") = false);
            return a;
          },
          "(n, 3) float32, a read-only view")
      .def_property_readonly(
          "t2",
          [](const py::object& self) {
            const Image<std::uint8_t>& atlas = self.cast<const PolycubeMap&>().textured->t2->atlas();
            py::array a = py::array_t<std::uint8_t>(
                {py::ssize_t(atlas.height()), py::ssize_t(atlas.width()), py::ssize_t(atlas.channels())},
                atlas.levelData(0).data(), self);
            a.attr("setflags")(py::arg("write") = false);
            return a;
          },
          "(h, w, 4) uint8 atlas, a read-only view")
      .def_property_readonly("texels_per_squarelet", [](const PolycubeMap& p) { return p.textured->t2->texelsPerSquarelet(); })
      .def_property_readonly("squarelets", [](const PolycubeMap& p) { return p.textured->t2->surface().lut().tileCount(); })
      .def_property_readonly("use", [](const PolycubeMap& p) {
        return std::string(p.textured->use == polycube::TextureUse::Normal ? "normal" : "color");
      })
      .def_property_readonly("origin", [](const PolycubeMap& p) {
        return std::vector<double>{p.frame.origin.x, p.frame.origin.y, p.frame.origin.z};
      })
      .def_property_readonly("cube_size", [](const PolycubeMap& p) { return p.frame.cubeSize; })
      .def_property_readonly("cubes_per_side", [](const PolycubeMap& p) { return p.cubesPerSide; },
                             "the automatic search's N (0 for given or loaded cubes)")
      .def_property_readonly("genus", [](const PolycubeMap& p) { return p.cubes().surfaceStats().genus(); })
      .def_property_readonly(
          "distortion",
          [](const PolycubeMap& p) -> py::object {
            if (!p.map) return py::none();
            py::dict out;
            out["start"] = distortionOf(p.map->initial);
            out["optimized"] = distortionOf(p.map->final);
            out["sweeps"] = p.map->sweeps;
            out["seconds"] = p.map->seconds;
            return out;
          },
          "The paper's Table 1 measures before and after optimization (None for a loaded map)")
      .def_property_readonly("nbytes", [](const PolycubeMap& p) { return p.textured->t2->byteSize(); })
      .def(
          "save",
          [](const PolycubeMap& p, const std::filesystem::path& dir) {
            withoutGil([&] {
              const std::vector<Vec3d> texture(p.textured->texture.begin(), p.textured->texture.end());
              polycube::writePolycubeResult(dir, p.cubes(), p.frame, p.textured->mesh, texture, *p.textured->t2,
                                            p.textured->use);
              return 0;
            });
          },
          py::arg("dir"),
          "Writes what `cellrelief render dir` and load_polycube read. Each file is written atomically, the "
          "four together are not: write into a new folder to replace a result.")
      .def("__repr__", [](const PolycubeMap& p) {
        return "<cellrelief.PolycubeMap " + std::to_string(p.textured->mesh.triangleCount()) + " triangles on " +
               std::to_string(p.cubes().size()) + " cubes, T2 " + std::to_string(p.textured->t2->texelsPerSquarelet()) +
               " texels per squarelet>";
      });

  m.def("polycube_map", &polycubeMapOf, py::arg("mesh"), py::kw_only(), py::arg("grid") = py::str("auto"),
        py::arg("cubes") = py::none(), py::arg("origin") = py::none(), py::arg("cube_size") = py::none(),
        py::arg("energy") = "extended-mips", py::arg("sweeps") = 400, py::arg("signal") = "grid",
        py::arg("texels") = 16, py::arg("progress") = py::none(),
        R"(Maps a mesh onto its polycube and bakes T2 (`cellrelief polycube`).

The polycube is built automatically (grid: cubes along the mesh's bounding cube, or 'auto', the
coarsest that keeps the mesh's genus) or given: cubes (k, 3) integer lattice coordinates, placed by
origin and cube_size or else fitted over the mesh. energy: extended-mips, mips or mvc; signal: grid,
normals, shading or color; texels: S, a power of two. progress(sweep, distortion) is called after
each sweep; Ctrl-C stops the map. A map that still folds a triangle is an InvalidInputError.)");
  m.def("load_polycube", &loadPolycube, py::arg("dir"), "Reads a folder written by `cellrelief polycube` or save.");

  // Scene.add(PolycubeMap): one more overload of the method bindRendering made (as class_::def adds one).
  const py::object scene = m.attr("Scene");
  scene.attr("add") = py::cpp_function(
      [](render::Scene& s, const PolycubeMap& map) { s.polycubeMeshes.push_back(map.textured); }, py::name("add"),
      py::is_method(scene), py::sibling(py::getattr(scene, "add", py::none())), py::arg("map"));
}

}  // namespace cellrelief::python
