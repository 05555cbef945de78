// SPDX-License-Identifier: MIT
/// @file command_geotex.cpp
/// `cellrelief geotex <mesh | heightmap> -o model.cgt [--charts K] [--texels 128] ...`: geometry
/// textures (de Toledo, Wang, Levy 2008). A mesh is partitioned by VSA into charts, each a height
/// map in an oriented box; a height-map image (a DEM) is one chart as it stands. Prints the
/// charts, folds, empty texels, bytes and time, and for a mesh the accuracy of the result against
/// the mesh itself (rays from three views, the mesh's own BVH as the reference); optionally a
/// picture with every chart in its own colour. The .cgt file is written only when all succeeds.
#include <chrono>
#include <cstdio>
#include <memory>

#include <cellrelief/core/bvh.h>
#include <cellrelief/cpu/cpu_backend.h>
#include <cellrelief/geotex/convert.h>
#include <cellrelief/geotex/geotex_file.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/metrics/ray_comparison.h>

#include "commands.h"

namespace cellrelief::app {

namespace {

struct GeoTexCli {
  std::string input, output, metric = "l21", seeding = "hierarchical", picture, extent;
  int charts = 64, texels = 128, bits = 16, rings = 1, iterations = 50, teleports = 0;
  double smoothing = 0;
};

/// The views the accuracy report and the picture use, around the scene's bounds.
std::vector<render::Camera> reportViews(const Aabbd& bounds) {
  std::vector<render::Camera> views;
  for (const auto& [yaw, pitch] : {std::pair{35.0, 20.0}, {215.0, -20.0}, {125.0, 60.0}})
    views.push_back(render::Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), yaw, pitch));
  return views;
}

/// Geometry textures against the mesh they came from: the CPU backend's depth and mask beside
/// the mesh's own BVH, pixel by pixel, over three views.
metrics::RayComparison measureAgainstMesh(const TriangleMesh& mesh, std::shared_ptr<const geotex::GeoTexModel> model) {
  const TriangleBvh<float> reference(mesh.positions, mesh.triangles);
  render::Scene scene;
  scene.geotexModels.push_back(model);
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  render::RenderOptions options;
  options.width = options.height = 256;
  options.channels = render::kDepth | render::kMask;
  metrics::RayComparison total;
  std::vector<double> depthErrors;
  for (const render::Camera& camera : reportViews(scene.boundsWS())) {
    const render::Frame frame = cpu.renderFrame(camera, options);
    const render::Camera::FloatFrame rays = camera.floatFrame(options.width, options.height);
    Image<float> depth(options.width, options.height, 1);
    Image<std::uint8_t> mask(options.width, options.height, 1);
    parallelFor(0, std::size_t(options.width) * options.height, [&](std::size_t i) {
      const int x = int(i % options.width), y = int(i / options.width);
      const Rayf ray = rays.ray(x, y);
      const Hitf hit = reference.closestHit(ray);
      // The inner side of an open mesh, seen through a hole, is no surface of a solid.
      const bool front = hit.valid() && glm::dot(hit.geometricNormal, ray.direction) < 0;
      depth.at(x, y, 0) = front ? hit.t : std::numeric_limits<float>::infinity();
      mask.at(x, y, 0) = front ? 1 : 0;
    });
    for (int y = 0; y < options.height; ++y)
      for (int x = 0; x < options.width; ++x) {
        const bool meshHit = mask.at(x, y, 0) != 0, ours = frame.mask.at(x, y, 0) != 0;
        ++total.rays;
        total.bothHit += meshHit && ours;
        total.onlyReference += meshHit && !ours;
        total.onlyTest += ours && !meshHit;
        if (meshHit && ours)
          depthErrors.push_back(std::abs(double(depth.at(x, y, 0)) - double(frame.depth.at(x, y, 0))));
      }
  }
  total.depthError = metrics::distributionOf(std::move(depthErrors));
  return total;
}

/// The model with every chart's colour map set to one colour per chart (a golden-ratio hue walk).
geotex::GeoTexModel chartColoured(const geotex::GeoTexModel& model) {
  geotex::GeoTexModel coloured = model;
  coloured.colors.assign(model.texelCount(), Color8(0));
  for (std::size_t c = 0; c < model.charts.size(); ++c) {
    const double hue = std::fmod(0.618033988749895 * double(c), 1.0) * 6;
    const Vec3d rgb = glm::clamp(Vec3d(std::abs(hue - 3) - 1, 2 - std::abs(hue - 2), 2 - std::abs(hue - 4)),
                                 Vec3d(0), Vec3d(1));
    const Color8 colour(Vec3f(40) + Vec3f(rgb) * 200.0f, 255);
    const geotex::ChartBox& box = model.charts[c];
    std::fill_n(coloured.colors.begin() + std::ptrdiff_t(box.firstTexel), box.texelCount(), colour);
  }
  return coloured;
}

void writePicture(std::shared_ptr<const geotex::GeoTexModel> model, const std::filesystem::path& png) {
  render::Scene scene;
  scene.geotexModels.push_back(std::move(model));
  cpu::CpuBackend cpu;
  cpu.upload(scene);
  render::RenderOptions options;
  options.width = options.height = 800;
  options.channels = render::kColor;
  const auto t0 = std::chrono::steady_clock::now();
  io::writePng(cpu.renderFrame(reportViews(scene.boundsWS()).front(), options).color, png);
  std::printf("picture       %s (charts in colour, CPU backend, %.2f s)\n", png.c_str(), secondsSince(t0));
}

geotex::GeoTexOptions parseOptions(const GeoTexCli& o) {
  geotex::GeoTexOptions options;
  options.vsa.proxies = o.charts;
  options.vsa.maxIterations = o.iterations;
  options.vsa.teleports = o.teleports;
  if (o.metric == "l21")
    options.vsa.metric = geotex::VsaMetric::L21;
  else if (o.metric == "l2")
    options.vsa.metric = geotex::VsaMetric::L2;
  else
    throw Error(ErrorKind::InvalidArgument, "--metric: '" + o.metric + "' is not l21 or l2");
  if (o.seeding == "hierarchical")
    options.vsa.seeding = geotex::VsaSeeding::Hierarchical;
  else if (o.seeding == "farthest")
    options.vsa.seeding = geotex::VsaSeeding::FarthestPoint;
  else
    throw Error(ErrorKind::InvalidArgument, "--seeding: '" + o.seeding + "' is not hierarchical or farthest");
  options.maxTexels = o.texels;
  options.heightBits = o.bits;
  options.rings = o.rings;
  options.smoothing = o.smoothing;
  return options;
}

/// --extent "W,D,H" for a height map; by default the image's aspect in a unit square, 0.2 high.
geotex::HeightMapExtent parseExtent(const std::string& text, int width, int height) {
  geotex::HeightMapExtent e;
  const double longest = std::max(width, height);
  e.width = width / longest;
  e.depth = height / longest;
  if (text.empty()) return e;
  double v[3];
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3 ||
      !(v[0] > 0 && v[1] > 0 && v[2] > 0) || !std::isfinite(v[0] + v[1] + v[2]))
    throw Error(ErrorKind::InvalidArgument, "--extent '" + text + "': expected W,D,H, three positive numbers");
  return {v[0], v[1], v[2]};
}

int runGeoTex(const GeoTexCli& o) {
  if (std::filesystem::path(o.output).extension() != ".cgt")
    throw Error(ErrorKind::InvalidArgument, "-o '" + o.output + "': the model file must end in .cgt");
  const auto t0 = std::chrono::steady_clock::now();
  std::shared_ptr<geotex::GeoTexModel> model;
  if (io::isImageFile(o.input)) {
    const io::ImageFile image = io::readImage(o.input);
    const geotex::HeightMapExtent extent = parseExtent(o.extent, image.width(), image.height());
    model = std::make_shared<geotex::GeoTexModel>(withPath(o.input, [&] {
      return std::visit([&](const auto& pixels) { return geotex::heightMapModel(pixels, extent, o.bits); },
                        image.pixels);
    }));
    std::printf("height map    %s: %d x %d, %d-bit, one chart of %.3g x %.3g x %.3g, %s in %.2f s\n",
                o.input.c_str(), image.width(), image.height(), image.bitDepth(), extent.width, extent.depth,
                extent.height, formatBytes(double(model->byteSize())).c_str(), secondsSince(t0));
  } else {
    const geotex::GeoTexOptions options = parseOptions(o);
    const TriangleMesh mesh = io::readMesh(o.input);
    const geotex::GeoTexConversion r = withPath(o.input, [&] { return geotex::convertMesh(mesh, options); });
    model = std::make_shared<geotex::GeoTexModel>(r.model);
    const double seconds = secondsSince(t0);
    std::printf("charts        %zu (asked %d, %d components), VSA %s error %.4g after %zu iterations, %d teleports\n",
                model->charts.size(), o.charts, r.partition.components, o.metric.c_str(), r.partition.error,
                r.partition.errorPerIteration.size() - 1, r.partition.teleports);
    std::printf("maps          %llu texels, %llu empty (%.1f%%), %d-bit heights%s; %zu folded faces\n",
                (unsigned long long)model->texelCount(), (unsigned long long)r.emptyTexels(),
                100.0 * double(r.emptyTexels()) / double(std::max<std::uint64_t>(1, model->texelCount())), o.bits,
                model->hasColors() ? ", colours" : "", r.foldedFaces());
    std::printf("converted     %s: %s in %.2f s\n", o.input.c_str(), formatBytes(double(model->byteSize())).c_str(),
                seconds);
    const metrics::RayComparison c = measureAgainstMesh(mesh, model);
    const double diagonal = mesh.surfaceBounds().diagonal();
    std::printf("accuracy      %zu rays against the mesh: depth error median %.4f%%, p99 %.4f%%, max %.3f%% of "
                "the diagonal; %.0f per million rays disagree on hit or miss\n",
                c.rays, 100 * c.depthError.median / diagonal, 100 * c.depthError.p99 / diagonal,
                100 * c.depthError.max / diagonal, 1e6 * c.disagreementRate());
  }
  geotex::writeGeoTex(*model, o.output);
  std::printf("wrote         %s\n", o.output.c_str());
  if (!o.picture.empty()) writePicture(std::make_shared<geotex::GeoTexModel>(chartColoured(*model)), o.picture);
  return 0;
}

}  // namespace

Command addGeoTexCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "geotex", "Geometry textures: a mesh as VSA charts of height maps in oriented boxes, or a height map as one");
  auto o = std::make_shared<GeoTexCli>();
  cmd->add_option("input", o->input, "Mesh (.obj .ply .off .stl) or height-map image (.png .jpg .tga .bmp)")
      ->required();
  cmd->add_option("-o,--output", o->output, "Model file to write (.cgt)")->required();
  cmd->add_option("--charts", o->charts, "VSA proxies (at least one per connected component)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--texels", o->texels, "Largest map side, a power of two; smaller charts get less")
      ->capture_default_str();
  cmd->add_option("--bits", o->bits, "Height bits, 8 or 16")->capture_default_str();
  cmd->add_option("--metric", o->metric, "VSA error: l21 (normals) or l2 (distances)")->capture_default_str();
  cmd->add_option("--seeding", o->seeding, "VSA seeding: hierarchical or farthest")->capture_default_str();
  cmd->add_option("--iterations", o->iterations, "Most Lloyd iterations")
      ->capture_default_str()
      ->check(CLI::Range(0, 10000));
  cmd->add_option("--teleports", o->teleports,
                  "Most VSA region teleports where the iterations settle (a cheap merge frees a proxy for the worst region)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--rings", o->rings, "Rings of faces added around each chart (0: cracks show)")
      ->capture_default_str()
      ->check(CLI::Range(0, 16));
  cmd->add_option("--smooth", o->smoothing, "Gaussian sigma in texels applied to the heights (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 64.0));
  cmd->add_option("--extent", o->extent, "Height map only: world W,D,H (default: the image's aspect, 0.2 high)");
  cmd->add_option("--picture", o->picture, "Also render the charts in colour to this PNG");
  return {cmd, [o] { return runGeoTex(*o); }};
}

}  // namespace cellrelief::app
