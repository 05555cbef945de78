// SPDX-License-Identifier: MIT
/// @file bind_rendering.cpp
/// Scenes, cameras and backends: cellrelief.Scene (relief models, geometry textures and relief
/// surfaces with lights), Camera, Renderer (any backend by name; frames whose buffers come back as
/// NumPy arrays without a copy), render, backends, and Tracer / trace (batches of rays as (n, 3)
/// arrays on the CPU reference, t, normals and cell ids back).
#include <pybind11/stl/filesystem.h>

#include <mutex>

#include <tbb/parallel_for.h>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/indirection/relief_surface.h>
#include <cellrelief/render/scene.h>

#include "bindings.h"

namespace cellrelief::python {

namespace {

using render::Camera;
using render::Frame;
using render::Scene;

/// A read-only view of one of the frame's buffers, keeping the frame alive.
template <TexelScalar T>
py::object bufferOf(const py::object& self, const Image<T>& image, bool dropSingleChannel = true) {
  if (image.isEmpty()) return py::none();
  std::vector<py::ssize_t> shape{image.height(), image.width()};
  if (!dropSingleChannel || image.channels() > 1) shape.push_back(image.channels());
  py::array a = py::array_t<T>(shape, image.levelData(0).data(), self);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

unsigned channelsOf(const std::vector<std::string>& names) {
  unsigned flags = 0;
  for (const std::string& n : names) {
    if (n == "color") flags |= render::kColor;
    else if (n == "depth") flags |= render::kDepth;
    else if (n == "normal") flags |= render::kNormal;
    else if (n == "mask") flags |= render::kMask;
    else if (n == "cell") flags |= render::kCell;
    else if (n == "steps") flags |= render::kSteps;
    else throw Error(ErrorKind::InvalidArgument, "channels take color, depth, normal, mask, cell and steps, not '" + n + "'");
  }
  if (flags == 0) throw Error(ErrorKind::InvalidArgument, "channels: at least one is needed");
  return flags;
}

render::RenderOptions optionsOf(int width, int height, bool shadows, int reflections, float reflectivity,
                                const std::vector<std::string>& channels, std::size_t threads) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error(ErrorKind::InvalidArgument, "width and height must lie in 1..16384");
  if (reflections < 0 || reflections > 8) throw Error(ErrorKind::InvalidArgument, "reflections must lie in 0..8");
  render::RenderOptions o;
  o.width = width;
  o.height = height;
  o.shadows = shadows;
  o.reflectionBounces = reflections;
  o.reflectivity = reflectivity;
  o.channels = channelsOf(channels);
  o.threads = threads;
  return o;
}

/// A backend with the scene it last uploaded (its models must outlive the backend's use of them).
/// Its work runs without the GIL, so Python threads may share one: a mutex lets one call at a time
/// use the backend.
class Renderer {
 public:
  explicit Renderer(const std::string& name, const std::string& device)
      : mBackend(backends::createBackend(render::parseBackendKind(name), {.vulkanDevice = device})) {}
  std::string name() const { return std::string(render::backendName(mBackend->kind())); }
  std::string description() const { return mBackend->description(); }
  void upload(const Scene& scene) {
    withoutGil([&] {
      const std::lock_guard lock(mMutex);
      mScene = scene;  // C++ shared pointers only: no Python reference counts
      mUploaded = false;
      mBackend->upload(mScene);
      mUploaded = true;
      return 0;
    });
  }
  Frame render(const Camera& camera, const render::RenderOptions& options) {
    return withoutGil([&] {
      const std::lock_guard lock(mMutex);
      if (!mUploaded) throw Error(ErrorKind::InvalidArgument, "renderer: upload a scene before rendering");
      return mBackend->renderFrame(camera, options);
    });
  }
  std::size_t sceneBytes() const {
    return withoutGil([&] {
      const std::lock_guard lock(mMutex);
      return mBackend->sceneBytes();
    });
  }
  double deviceSeconds() const {
    return withoutGil([&] {
      const std::lock_guard lock(mMutex);
      return mBackend->deviceSeconds();
    });
  }

 private:
  std::unique_ptr<render::Backend> mBackend;
  Scene mScene;
  bool mUploaded = false;
  mutable std::mutex mMutex;
};

/// Batches of rays against a scene on the CPU reference (its tracers built once).
class Tracer {
 public:
  explicit Tracer(const Scene& scene) {
    mBackend.upload(scene);
    mBackend.buildTracers({});
  }

  py::dict trace(const py::handle& origins, const py::handle& directions, float tmin, float tmax) const {
    const auto o = rowsOf<float>(origins, 3, "origins");
    const auto d = rowsOf<float>(directions, 3, "directions");
    if (o.shape(0) != d.shape(0))
      throw Error(ErrorKind::InvalidArgument, "origins and directions must have as many rows (" +
                                                  std::to_string(o.shape(0)) + " and " + std::to_string(d.shape(0)) + ")");
    if (!(tmin >= 0) || !(tmax >= tmin)) throw Error(ErrorKind::InvalidArgument, "0 <= tmin <= tmax is needed");
    const std::size_t n = std::size_t(o.shape(0));
    for (std::size_t i = 0; i < n; ++i)
      if (d.data()[3 * i] == 0 && d.data()[3 * i + 1] == 0 && d.data()[3 * i + 2] == 0)
        throw Error(ErrorKind::InvalidArgument, "directions: row " + std::to_string(i) + " is zero");
    std::vector<float> t(n, std::numeric_limits<float>::infinity()), normals(3 * n, 0.0f);
    std::vector<std::int32_t> cells(n, -1);
    std::vector<std::uint8_t> hit(n, 0);
    const float* po = o.data();
    const float* pd = d.data();
    withoutGil([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const Vec3f dir = glm::normalize(Vec3f(pd[3 * i], pd[3 * i + 1], pd[3 * i + 2]));
          Rayf ray(Vec3f(po[3 * i], po[3 * i + 1], po[3 * i + 2]), dir, tmin, tmax);
          const cpu::CpuBackend::SceneHit h = mBackend.intersect(ray);
          if (!h.valid()) continue;
          hit[i] = 1;
          t[i] = h.hit.t;
          cells[i] = h.hit.cell;
          for (int c = 0; c < 3; ++c) normals[3 * i + std::size_t(c)] = h.hit.normal[c];
        }
      });
      return 0;
    });
    py::dict out;
    const auto rows = py::ssize_t(n);
    out["t"] = arrayOf(std::move(t), {rows});
    out["normal"] = arrayOf(std::move(normals), {rows, 3});
    out["cell"] = arrayOf(std::move(cells), {rows});
    out["hit"] = arrayOf(std::move(hit), {rows}).attr("astype")("bool");
    return out;
  }

 private:
  cpu::CpuBackend mBackend;
};

std::shared_ptr<indirection::ReliefSurface> reliefSurfaceOf(
    const std::filesystem::path& heightmap, const std::optional<std::filesystem::path>& indirectionMap,
    const std::optional<std::filesystem::path>& texture, const std::optional<std::filesystem::path>& normalMap,
    const std::optional<float>& heightScale, const std::string& wrap, const py::object& baseMesh, float uvScale,
    const py::object& origin, const py::object& uAxis, const py::object& vAxis, int checker) {
  indirection::ReliefSurfaceFiles files;
  files.heightmap = heightmap;
  if (indirectionMap) files.indirection = *indirectionMap;
  if (texture) files.colors = *texture;
  if (normalMap) files.normals = *normalMap;
  files.heightScale = heightScale;
  if (wrap != "clamp" && wrap != "repeat")
    throw Error(ErrorKind::InvalidArgument, "wrap takes clamp or repeat, not '" + wrap + "'");
  files.wrap = wrap == "repeat" ? Wrap::Repeat : Wrap::Clamp;
  std::shared_ptr<const TriangleMesh> mesh;
  if (py::isinstance<TriangleMesh>(baseMesh)) mesh = baseMesh.cast<std::shared_ptr<TriangleMesh>>();
  else if (!baseMesh.is_none()) files.baseMesh = baseMesh.cast<std::filesystem::path>();
  files.uvScale = uvScale;
  auto surface = std::make_shared<indirection::ReliefSurface>(withoutGil([&] { return indirection::loadReliefSurface(files); }));
  if (mesh) {
    surface->baseMesh = mesh;
    surface->uvScale = uvScale;
  }
  surface->originWS = Vec3f(vec3Of(origin, "origin"));
  surface->uAxisWS = Vec3f(vec3Of(uAxis, "u_axis"));
  surface->vAxisWS = Vec3f(vec3Of(vAxis, "v_axis"));
  surface->checkerSquares = checker;
  surface->validate();
  return surface;
}

}  // namespace

void bindRendering(py::module_& m) {
  py::class_<indirection::ReliefSurface, std::shared_ptr<indirection::ReliefSurface>>(
      m, "ReliefSurface", "A height map shown by parallax occlusion mapping, on a square or carved into a mesh with UVs.")
      .def_property_readonly("on_mesh", &indirection::ReliefSurface::onMesh)
      .def_property_readonly("has_indirection", &indirection::ReliefSurface::hasIndirection)
      .def_property_readonly("nbytes", &indirection::ReliefSurface::byteSize);
  m.def("relief_surface", &reliefSurfaceOf, py::arg("heightmap"), py::kw_only(), py::arg("indirection") = py::none(),
        py::arg("texture") = py::none(), py::arg("normal_map") = py::none(), py::arg("height_scale") = py::none(),
        py::arg("wrap") = "clamp", py::arg("base_mesh") = py::none(), py::arg("uv_scale") = 1.0f,
        py::arg("origin") = py::make_tuple(0, 0, 0), py::arg("u_axis") = py::make_tuple(1, 0, 0),
        py::arg("v_axis") = py::make_tuple(0, 1, 0), py::arg("checker") = 16,
        R"(A relief surface (`cellrelief render heightmap.png --indirection ...`): the height map with its
indirection map (as `cellrelief indirect` or indirection_map + a file writes it), colour texture and
normal map, on the square (origin, u_axis, v_axis) or carved into base_mesh (a Mesh with UVs, or a
path), its maps repeated uv_scale times.)");

  py::class_<Scene>(m, "Scene", "What a backend renders: relief models, geometry textures, relief surfaces and polycube maps, and lights.")
      .def(py::init<>())
      .def(
          "add", [](Scene& s, const std::shared_ptr<relief::ReliefModel>& model) { s.models.push_back(model); },
          py::arg("model"))
      .def(
          "add", [](Scene& s, const std::shared_ptr<geotex::GeoTexModel>& model) { s.geotexModels.push_back(model); },
          py::arg("model"))
      .def(
          "add", [](Scene& s, const std::shared_ptr<indirection::ReliefSurface>& surface) {
            s.reliefSurfaces.push_back(surface);
          },
          py::arg("surface"), "Adds a ReliefModel, GeoTexModel, ReliefSurface or PolycubeMap.")
      .def(
          "add_light",
          [](Scene& s, const py::object& direction, const py::object& color, float intensity) {
            render::DirectionalLight l;
            const Vec3d d = vec3Of(direction, "direction");
            if (glm::length(d) == 0) throw Error(ErrorKind::InvalidArgument, "direction must not be zero");
            l.direction = Vec3f(glm::normalize(d));
            l.color = Vec3f(vec3Of(color, "color"));
            l.intensity = intensity;
            s.lights.push_back(l);
          },
          py::arg("direction"), py::arg("color") = py::make_tuple(1, 1, 1), py::arg("intensity") = 0.85f,
          "A light at infinity; direction points from the surface towards the light.")
      .def("clear_lights", [](Scene& s) { s.lights.clear(); })
      .def_property_readonly("light_count", [](const Scene& s) { return s.lights.size(); })
      .def(
          "bounds", [](const Scene& s) {
            const Aabbd b = s.boundsWS();
            if (b.isEmpty()) throw Error(ErrorKind::InvalidArgument, "scene: nothing in it has bounds");
            return arrayOf(std::vector<double>{b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}, {2, 3});
          },
          "(2, 3): the union of its elements' boxes")
      .def("__repr__", [](const Scene& s) {
        return "<cellrelief.Scene " + std::to_string(s.models.size()) + " relief models, " +
               std::to_string(s.geotexModels.size()) + " geometry textures, " + std::to_string(s.reliefSurfaces.size()) +
               " relief surfaces, " + std::to_string(s.polycubeMeshes.size()) + " polycube maps, " +
               std::to_string(s.lights.size()) + " lights>";
      });

  py::class_<Camera>(m, "Camera", "A pinhole camera: eye, target, up and a vertical field of view in degrees.")
      .def(py::init([](const py::object& eye, const py::object& target, const py::object& up, double fov) {
             if (!(fov > 0 && fov < 180)) throw Error(ErrorKind::InvalidArgument, "fov must lie between 0 and 180 degrees");
             Camera c{vec3Of(eye, "eye"), vec3Of(target, "target"), vec3Of(up, "up"), fov};
             if (glm::length(c.target - c.eye) == 0) throw Error(ErrorKind::InvalidArgument, "eye and target must differ");
             return c;
           }),
           py::arg("eye"), py::arg("target"), py::arg("up") = py::make_tuple(0, 1, 0), py::arg("fov") = 40.0)
      .def_static(
          "framing",
          [](const Scene& scene, double yaw, double pitch, double fov) {
            const Aabbd b = scene.boundsWS();
            if (b.isEmpty()) throw Error(ErrorKind::InvalidArgument, "scene: nothing to frame");
            return Camera::framing(b.center(), 0.5 * b.diagonal(), yaw, pitch, fov);
          },
          py::arg("scene"), py::arg("yaw") = 35.0, py::arg("pitch") = 20.0, py::arg("fov") = 40.0,
          "A camera looking at the scene's bounding sphere from direction (yaw, pitch), as `cellrelief render` frames it.")
      .def_property_readonly("eye", [](const Camera& c) { return std::vector<double>{c.eye.x, c.eye.y, c.eye.z}; })
      .def_property_readonly("target",
                             [](const Camera& c) { return std::vector<double>{c.target.x, c.target.y, c.target.z}; })
      .def_property_readonly("fov", [](const Camera& c) { return c.verticalFovDegrees; });

  py::class_<Frame>(m, "Frame", "A rendered frame; its buffers are read-only NumPy views (None when not asked for).")
      .def_property_readonly("width", [](const Frame& f) { return f.width; })
      .def_property_readonly("height", [](const Frame& f) { return f.height; })
      .def_property_readonly(
          "color", [](const py::object& self) { return bufferOf(self, self.cast<const Frame&>().color, false); },
          "(h, w, 4) uint8 RGBA, alpha 0 where nothing was hit")
      .def_property_readonly(
          "depth", [](const py::object& self) { return bufferOf(self, self.cast<const Frame&>().depth); },
          "(h, w) float32 distance along the unit primary ray, inf where missed")
      .def_property_readonly(
          "normal", [](const py::object& self) { return bufferOf(self, self.cast<const Frame&>().normal, false); },
          "(h, w, 3) float32 unit world-space shading normal, 0 where missed")
      .def_property_readonly(
          "mask",
          [](const py::object& self) -> py::object {
            const py::object mask = bufferOf(self, self.cast<const Frame&>().mask);
            return mask.is_none() ? mask : mask.attr("astype")("bool");
          },
          "(h, w) bool, where the primary ray hit")
      .def_property_readonly(
          "cell", [](const py::object& self) { return bufferOf(self, self.cast<const Frame&>().cell); },
          "(h, w) float32 hit cell of its model, -1 where missed")
      .def_property_readonly(
          "steps", [](const py::object& self) { return bufferOf(self, self.cast<const Frame&>().steps); },
          "(h, w) float32 traversal work per primary ray");

  const std::vector<std::string> defaultChannels{"color", "depth", "normal", "mask"};
  py::class_<Renderer>(m, "Renderer", R"(A backend by name: cpu, opengl, vulkan or auto.

Renderer(backend="auto", device=""): device names a Vulkan device (part of its name). Raises
cellrelief.UnsupportedError with the reason when the backend cannot run here.)")
      .def(py::init<const std::string&, const std::string&>(), py::arg("backend") = "auto", py::arg("device") = "")
      .def_property_readonly("name", &Renderer::name)
      .def_property_readonly("description", &Renderer::description)
      .def_property_readonly("scene_bytes", &Renderer::sceneBytes)
      .def_property_readonly("device_seconds", &Renderer::deviceSeconds, "the last frame's GPU time (0 on the CPU)")
      .def("upload", &Renderer::upload, py::arg("scene"))
      .def(
          "render",
          [](Renderer& r, const Camera& camera, int width, int height, bool shadows, int reflections, float reflectivity,
             const std::vector<std::string>& channels, std::size_t threads) {
            return r.render(camera, optionsOf(width, height, shadows, reflections, reflectivity, channels, threads));
          },
          py::arg("camera"), py::kw_only(), py::arg("width") = 640, py::arg("height") = 480, py::arg("shadows") = true,
          py::arg("reflections") = 0, py::arg("reflectivity") = 0.25f, py::arg("channels") = defaultChannels,
          py::arg("threads") = 0, "Renders the uploaded scene (the GIL released).");

  m.def(
      "render",
      [](const Scene& scene, const Camera& camera, const std::string& backend, int width, int height, bool shadows,
         int reflections, const std::vector<std::string>& channels) {
        Renderer r(backend, "");
        r.upload(scene);
        return r.render(camera, optionsOf(width, height, shadows, reflections, 0.25f, channels, 0));
      },
      py::arg("scene"), py::arg("camera"), py::kw_only(), py::arg("backend") = "auto", py::arg("width") = 640,
      py::arg("height") = 480, py::arg("shadows") = true, py::arg("reflections") = 0,
      py::arg("channels") = defaultChannels, "One frame of the scene on a backend (Renderer keeps a backend for more).");

  m.def(
      "backends",
      [] {
        std::vector<py::dict> out;
        for (const backends::RendererStatus& s : backends::renderers()) {
          py::dict d;
          d["name"] = std::string(render::backendName(s.kind));
          d["available"] = s.availability.available;
          d["reason"] = s.availability.reason;
          out.push_back(d);
        }
        return out;
      },
      "Every backend with whether it runs here and, if not, why.");

  py::class_<Tracer>(m, "Tracer", "Batches of rays against a scene on the CPU reference (its tracers built once).")
      .def(py::init<const Scene&>(), py::arg("scene"))
      .def("trace", &Tracer::trace, py::arg("origins"), py::arg("directions"), py::kw_only(), py::arg("tmin") = 0.0f,
           py::arg("tmax") = std::numeric_limits<float>::infinity(),
           "Nearest hits of (n, 3) origins and directions: a dict of t (n,) float32 (inf: a miss), normal (n, 3), "
           "cell (n,) int32 (-1 where no relief model's cell was hit) and hit (n,) bool.");
  m.def(
      "trace",
      [](const Scene& scene, const py::handle& origins, const py::handle& directions, float tmin, float tmax) {
        return Tracer(scene).trace(origins, directions, tmin, tmax);
      },
      py::arg("scene"), py::arg("origins"), py::arg("directions"), py::kw_only(), py::arg("tmin") = 0.0f,
      py::arg("tmax") = std::numeric_limits<float>::infinity(), "Tracer(scene).trace(origins, directions).");
}

}  // namespace cellrelief::python
