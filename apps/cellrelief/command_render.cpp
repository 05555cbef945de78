// SPDX-License-Identifier: MIT
/// @file command_render.cpp
/// `cellrelief render <model.crm | mesh | polycube folder | heightmap> -o out.png`: ray casts a
/// relief model, a mesh textured through its polycube map, or a height map with its indirection
/// map (parallax occlusion mapping), on a backend and writes the color image, and on request the
/// depth and normal buffers. A mesh is converted at default settings first, so any
/// mesh can be looked at in one command.
#include <chrono>
#include <cstdio>
#include <memory>
#include <sstream>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/geotex/geotex_file.h>
#include <cellrelief/indirection/relief_surface.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/polycube_result.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/model_file.h>

#include "commands.h"

namespace cellrelief::app {

namespace {

struct RenderCli {
  std::string input, output, backend = "auto", device, size = "800x800", camera, depth, normals;
  gpu::RayEntry entry = gpu::RayEntry::Fastest;
  bool shadows = true, skip = true;
  int reflections = 0;
  SurfaceCli surface;
};

std::vector<double> parseNumbers(const std::string& text, const std::string& what) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw Error(ErrorKind::InvalidArgument, what + " '" + text + "': '" + item + "' is not a number");
    }
  }
  return values;
}

}  // namespace

void setRayEntry(render::Backend& backend, gpu::RayEntry entry) {
  if (auto* controls = dynamic_cast<gpu::TraversalControls*>(&backend)) controls->setRayEntry(entry);
}

std::string lastRayEntry(const render::Backend& backend) {
  const auto* controls = dynamic_cast<const gpu::TraversalControls*>(&backend);
  if (!controls) return "";
  return controls->lastRayEntry() == gpu::RayEntry::Rasterized ? "rasterized entry" : "compute entry";
}

std::pair<int, int> parseImageSize(const std::string& size) {
  const std::size_t x = size.find('x');
  int w = 0, h = 0;
  try {
    if (x != std::string::npos) {
      std::size_t a = 0, b = 0;
      w = std::stoi(size.substr(0, x), &a);
      h = std::stoi(size.substr(x + 1), &b);
      if (a != x || b != size.size() - x - 1) w = h = 0;
    }
  } catch (const std::exception&) {
    w = h = 0;
  }
  if (w < 1 || h < 1 || w > 16384 || h > 16384)
    throw Error(ErrorKind::InvalidArgument, "--size '" + size + "': expected WxH, 1 to 16384 each");
  return {w, h};
}

render::Camera parseCamera(const std::string& spec, const Aabbd& bounds) {
  const Vec3d centre = bounds.center();
  const double radius = 0.5 * bounds.diagonal();
  if (spec.empty()) return render::Camera::framing(centre, radius);
  const std::vector<double> v = parseNumbers(spec, "--camera");
  if ((v.size() == 3 || v.size() == 7) && !(v.back() > 0 && v.back() < 180))
    throw Error(ErrorKind::InvalidArgument,
                "--camera '" + spec + "': the field of view must lie between 0 and 180 degrees");
  if (v.size() == 2 || v.size() == 3)
    return render::Camera::framing(centre, radius, v[0], v[1], v.size() == 3 ? v[2] : 40.0);
  if (v.size() == 6 || v.size() == 7) {
    render::Camera c;
    c.eye = Vec3d(v[0], v[1], v[2]);
    c.target = Vec3d(v[3], v[4], v[5]);
    if (v.size() == 7) c.verticalFovDegrees = v[6];
    if (glm::length(c.target - c.eye) == 0)
      throw Error(ErrorKind::InvalidArgument, "--camera '" + spec + "': eye and target coincide");
    return c;
  }
  throw Error(ErrorKind::InvalidArgument,
              "--camera '" + spec + "': expected yaw,pitch[,fov] or ex,ey,ez,tx,ty,tz[,fov]");
}

std::shared_ptr<const relief::ReliefModel> loadOrConvert(const std::string& input) {
  if (std::filesystem::path(input).extension() == ".crm")
    return std::make_shared<relief::ReliefModel>(relief::readRelief(input));
  const TriangleMesh mesh = io::readMesh(input);
  const auto t0 = std::chrono::steady_clock::now();
  auto model = std::make_shared<relief::ReliefModel>(withPath(input, [&] { return relief::convert(mesh); }));
  std::printf("converted     %s: N = %d, T = %d, %zu grey cells, %s in %.2f s\n", input.c_str(),
              model->gridSize, model->texels, model->cells.size(),
              formatBytes(double(model->byteSize())).c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return model;
}

Wrap parseWrap(const std::string& w) {
  if (w == "clamp") return Wrap::Clamp;
  if (w == "repeat") return Wrap::Repeat;
  throw Error(ErrorKind::InvalidArgument, "--wrap takes clamp or repeat, not '" + w + "'");
}

void addSurfaceOptions(CLI::App* cmd, SurfaceCli& o) {
  cmd->add_option("--indirection", o.indirection,
                  "With a height map: its indirection map (as `cellrelief indirect` writes it, PNG + .json)");
  cmd->add_option("--texture", o.colors, "With a height map: the colour map fetched at (u, v) + I(u, v) (default: a checkerboard)");
  cmd->add_option("--normal-map", o.normals,
                  "With a height map: a tangent-space normal map (default: a DirectX SDK TGA's RGB, else the heights' normals)");
  cmd->add_option("--height-scale", o.heightScale,
                  "With a height map: relief height in tile widths (default: the indirection map's, else 0.1)");
  cmd->add_option("--wrap", o.wrap, "With a height map: clamp or repeat (tiling maps)")->capture_default_str();
  cmd->add_option("--checker", o.checker, "With a height map and no texture: checkerboard squares per side")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("--base-mesh", o.baseMesh,
                  "With a height map: a mesh with UVs to carve the relief into (per-fragment POM; default: a square tile)");
  cmd->add_option("--uv-scale", o.uvScale, "With --base-mesh: the maps repeat this often over the UVs")
      ->check(CLI::Range(1e-3, 1e4))
      ->capture_default_str();
}

namespace {

render::Scene reliefSurfaceScene(const std::string& input, const SurfaceCli& o) {
  if (o.heightScale < 0 || !std::isfinite(o.heightScale) || o.heightScale > 100)
    throw Error(ErrorKind::InvalidArgument, "--height-scale must lie in (0, 100]");
  indirection::ReliefSurfaceFiles files;
  files.heightmap = input;
  files.indirection = o.indirection;
  files.colors = o.colors;
  files.normals = o.normals;
  if (o.heightScale > 0) files.heightScale = o.heightScale;
  files.wrap = parseWrap(o.wrap);
  files.baseMesh = o.baseMesh;
  files.uvScale = o.uvScale;
  auto surface = std::make_shared<indirection::ReliefSurface>(indirection::loadReliefSurface(files));
  surface->checkerSquares = o.checker;
  std::printf("relief surface %s: %dx%d texels, height scale %g, %s, %s, %s\n", input.c_str(), surface->relief.width(),
              surface->relief.height(), surface->relief.heightScale(),
              surface->hasIndirection() ? ("indirection " + o.indirection).c_str() : "no indirection map (plain POM)",
              o.colors.empty() ? "checkerboard" : ("colours " + o.colors).c_str(),
              surface->normals.isEmpty() ? "normals of the heights"
                                         : (o.normals.empty() ? "normals from the TGA's RGB" : ("normals " + o.normals).c_str()));
  if (surface->onMesh())
    std::printf("  carved into %s: %zu triangles, UVs times %g\n", o.baseMesh.c_str(), surface->baseMesh->triangleCount(),
                double(surface->uvScale));
  render::Scene scene;
  scene.reliefSurfaces.push_back(std::move(surface));
  return scene;
}

}  // namespace

render::Scene loadScene(const std::string& input, const SurfaceCli& surface) {
  if (io::isImageFile(input)) return reliefSurfaceScene(input, surface);
  if (!surface.indirection.empty() || !surface.colors.empty() || !surface.normals.empty() || !surface.baseMesh.empty())
    throw Error(ErrorKind::InvalidArgument,
                "--indirection, --texture, --normal-map and --base-mesh apply to a height map (an image), not " + input);
  if (std::filesystem::path(input).extension() == ".cgt") {
    render::Scene scene;
    scene.geotexModels.push_back(std::make_shared<geotex::GeoTexModel>(geotex::readGeoTex(input)));
    const geotex::GeoTexModel& m = *scene.geotexModels.back();
    std::printf("geotex model  %s: %zu charts, %llu texels, %s\n", input.c_str(), m.charts.size(),
                (unsigned long long)m.texelCount(), formatBytes(double(m.byteSize())).c_str());
    return scene;
  }
  if (!polycube::isPolycubeResult(input)) return render::Scene::of(loadOrConvert(input));
  render::Scene scene;
  scene.polycubeMeshes.push_back(polycube::readPolycubeResult(input));
  const polycube::TexturedMesh& m = *scene.polycubeMeshes.back();
  std::printf("polycube map  %s: %zu triangles, %zu cubes, T2 of %d texels per squarelet (%s)\n", input.c_str(),
              m.mesh.triangleCount(), m.t2->surface().polycube().size(), m.t2->texelsPerSquarelet(),
              m.use == polycube::TextureUse::Normal ? "normals" : "colour");
  return scene;
}

namespace {

Image<std::uint8_t> depthImage(const render::Frame& frame) {
  float lo = std::numeric_limits<float>::infinity(), hi = 0;
  for (float d : frame.depth.levelData())
    if (std::isfinite(d)) lo = std::min(lo, d), hi = std::max(hi, d);
  Image<std::uint8_t> out(frame.width, frame.height, 1);
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      const float d = frame.depth.at(x, y, 0);
      // Near is bright; misses are black.
      out.at(x, y, 0) = std::isfinite(d) ? std::uint8_t(std::lround(255 - 220 * (d - lo) / std::max(hi - lo, 1e-20f))) : 0;
    }
  return out;
}

Image<std::uint8_t> normalImage(const render::Frame& frame) {
  Image<std::uint8_t> out(frame.width, frame.height, 3);
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x)
      for (int c = 0; c < 3; ++c)
        out.at(x, y, c) = frame.mask.at(x, y, 0)
                              ? std::uint8_t(std::lround(127.5f * (frame.normal.at(x, y, c) + 1.0f)))
                              : 0;
  return out;
}

int runRender(const RenderCli& o) {
  const auto [width, height] = parseImageSize(o.size);
  auto backend = backends::createBackend(render::parseBackendKind(o.backend), {.vulkanDevice = o.device});
  const render::Scene scene = loadScene(o.input, o.surface);
  render::RenderOptions options;
  options.width = width;
  options.height = height;
  options.shadows = o.shadows;
  options.reflectionBounces = o.reflections;
  options.trace.skipEmptySpace = o.skip;
  const render::Camera camera = parseCamera(o.camera, scene.boundsWS());
  setRayEntry(*backend, o.entry);
  withPath(o.input, [&] { backend->upload(scene); });
  // The first frame builds the tracers (or compiles the shader); it is read back, so that the
  // timed frame does not wait for it on an asynchronous backend. With the fastest entry on a GPU,
  // the first frame and the timed one are its two trials.
  backend->renderFrame(camera, options);
  const auto t0 = std::chrono::steady_clock::now();
  backend->render(camera, options);
  render::Frame frame;
  backend->readBack(frame);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::size_t hits = 0;
  for (std::uint8_t m : frame.mask.levelData()) hits += m;
  std::printf("rendered      %dx%d on %s in %.3f s (%.2f Mpixel/s, %zu hits; shading with%s shadows, "
              "%d reflection bounce%s)\n",
              width, height, backend->description().c_str(), seconds, width * height / seconds * 1e-6,
              hits, o.shadows ? "" : "out", o.reflections, o.reflections == 1 ? "" : "s");
  if (backend->deviceSeconds() > 0)
    std::printf("device time   %.3f s (the GPU's own clock)\n", backend->deviceSeconds());
  if (const std::string entry = lastRayEntry(*backend); !entry.empty()) std::printf("entry         %s\n", entry.c_str());
  io::writePng(frame.color, o.output);
  std::printf("wrote         %s\n", o.output.c_str());
  if (!o.depth.empty()) {
    io::writePng(depthImage(frame), o.depth);
    std::printf("wrote         %s\n", o.depth.c_str());
  }
  if (!o.normals.empty()) {
    io::writePng(normalImage(frame), o.normals);
    std::printf("wrote         %s\n", o.normals.c_str());
  }
  return 0;
}

}  // namespace

void renderModelPicture(std::shared_ptr<const relief::ReliefModel> model,
                        const std::filesystem::path& png, int size) {
  cpu::CpuBackend backend;
  const render::Scene scene = render::Scene::of(std::move(model));
  backend.upload(scene);
  render::RenderOptions options;
  options.width = options.height = size;
  options.channels = render::kColor;
  const auto t0 = std::chrono::steady_clock::now();
  const render::Frame frame = backend.renderFrame(parseCamera("", scene.boundsWS()), options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  io::writePng(frame.color, png);
  std::printf("demo: ray cast the relief model (%dx%d, shadows, CPU backend) in %.2f s: wrote %s\n",
              size, size, seconds, png.c_str());
}

Command addRenderCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "render", "Ray cast a relief model (or a mesh, converted first, or a height map by parallax occlusion mapping) to a PNG");
  auto o = std::make_shared<RenderCli>();
  cmd->add_option("model", o->input,
                  "Relief model (.crm), geometry textures (.cgt), mesh (.obj .ply .off .stl), a folder "
                  "written by `cellrelief polycube`, or a height map (.png .jpg .tga .bmp) shown by parallax "
                  "occlusion mapping")
      ->required();
  cmd->add_option("-o,--output", o->output, "Color image to write (.png)")->required();
  cmd->add_option("--backend", o->backend, backends::kBackendHelp)->capture_default_str();
  cmd->add_option("--device", o->device, backends::kDeviceHelp);
  cmd->add_option("--entry", o->entry, kRayEntryHelp)
      ->transform(CLI::CheckedTransformer(rayEntryNames(), CLI::ignore_case).description("fastest|rasterized|compute"))
      ->default_str("fastest");
  cmd->add_option("--size", o->size, "Image size WxH")->capture_default_str();
  cmd->add_option("--camera", o->camera,
                  "yaw,pitch[,fov] around the model, or ex,ey,ez,tx,ty,tz[,fov] (default 35,20,40)");
  cmd->add_option("--depth", o->depth, "Also write the depth buffer (.png, near is bright)");
  cmd->add_option("--normals", o->normals, "Also write the normal buffer (.png)");
  cmd->add_flag("!--no-shadows", o->shadows, "No shadow rays");
  cmd->add_option("--reflections", o->reflections, "Mirror bounces per hit")
      ->check(CLI::Range(0, 8))
      ->capture_default_str();
  cmd->add_flag("!--no-skip", o->skip, "Plain linear + binary search (no empty-space skipping)");
  addSurfaceOptions(cmd, o->surface);
  return {cmd, [o]() { return runRender(*o); }};
}

}  // namespace cellrelief::app
