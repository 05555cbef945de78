// SPDX-License-Identifier: MIT
/// @file command_demo.cpp
/// `cellrelief demo [mesh]`: the embedded default job. Without a mesh it generates the built-in
/// model (a torus displaced by ridged noise, 327,680 triangles); with a mesh it takes the user's.
/// It writes the mesh as PLY with a picture, reports on it, converts it into a relief model (.crm)
/// and writes a picture of the model's reconstruction and one of the model itself, ray cast on the
/// CPU reference backend.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/metrics/geometric_error.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/model_file.h>
#include <cellrelief/relief/reconstruct.h>

#include "commands.h"
#include "preview.h"

namespace cellrelief::app {

namespace {
struct DemoOptions {
  std::string input;
  std::string outputDir = "out/demo";
  int tubeSegments = 320;
};

int runDemo(const DemoOptions& o) {
  std::filesystem::create_directories(o.outputDir);
  const std::filesystem::path outDir(o.outputDir);
  std::filesystem::path model;
  if (o.input.empty()) {
    auto start = std::chrono::steady_clock::now();
    DisplacedTorusOptions torus;
    torus.tubeSegments = o.tubeSegments;
    torus.ringSegments = 8 * o.tubeSegments / 5;
    const TriangleMesh mesh = makeDisplacedTorus(torus);
    std::printf("demo: generated the built-in model: %zu triangles, %zu vertices in %.2f s\n",
                mesh.triangleCount(), mesh.vertexCount(), secondsSince(start));
    model = outDir / "displaced_torus.ply";
    start = std::chrono::steady_clock::now();
    io::writeMesh(mesh, model);
    std::printf("demo: wrote %s (%s) in %.2f s\n", model.c_str(),
                formatBytes(double(std::filesystem::file_size(model))).c_str(), secondsSince(start));
  } else {
    const TriangleMesh mesh = io::readMesh(o.input);
    model = outDir / (std::filesystem::path(o.input).stem().string() + ".ply");
    io::writeMesh(mesh, model);
    std::printf("demo: read %s (%zu triangles), wrote %s\n", o.input.c_str(),
                mesh.triangleCount(), model.c_str());
  }
  // Everything below works on the file as written, read back once.
  const TriangleMesh mesh = io::readMesh(model);
  {
    const std::filesystem::path picture = outDir / (model.stem().string() + ".png");
    writePreview(mesh, picture);
    std::printf("demo: wrote %s (a picture of the model)\n", picture.c_str());
  }
  std::printf("\n");
  printMeshInfo(model.string());
  {
    const auto start = std::chrono::steady_clock::now();
    relief::ConvertReport report;
    const auto reliefPtr = std::make_shared<const relief::ReliefModel>(relief::convert(mesh, {}, &report));
    const relief::ReliefModel& relief = *reliefPtr;
    const std::filesystem::path crm = outDir / (model.stem().string() + ".crm");
    relief::writeRelief(relief, crm);
    const TriangleMesh rebuilt = relief::reconstruct(relief);
    const metrics::SurfaceError e =
        metrics::surfaceError(mesh, metrics::DistanceField(mesh), rebuilt, 100000);
    const double d = mesh.bounds().diagonal();
    std::printf("\ndemo: converted to a relief model in %.2f s: N = %d, T = %d, %zu grey cells, "
                "%d layers, %s; RMS error %.4f%%, Hausdorff %.4f%% of the diagonal\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                relief.gridSize, relief.texels, relief.cells.size(), relief.layerCount(),
                formatBytes(double(relief.byteSize())).c_str(), 100 * e.rms() / d,
                100 * e.hausdorff() / d);
    const std::filesystem::path picture = outDir / (model.stem().string() + "_relief.png");
    writePreview(rebuilt, picture);
    std::printf("demo: wrote %s and %s (the model rebuilt from its relief maps)\n", crm.c_str(),
                picture.c_str());
    renderModelPicture(reliefPtr, outDir / (model.stem().string() + "_render.png"));
  }
  std::printf("\ndemo: results are in %s\n", outDir.c_str());
  return 0;
}
}  // namespace

Command addDemoCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "demo", "Run the embedded default job on the built-in model, or on your own mesh");
  auto o = std::make_shared<DemoOptions>();
  cmd->add_option("mesh", o->input, "Your own mesh instead of the built-in model");
  cmd->add_option("-o,--output-dir", o->outputDir, "Where the results go")->capture_default_str();
  cmd->add_option("--tube-segments", o->tubeSegments,
                  "Resolution of the built-in model (2 x 1.6 x s^2 triangles)")
      ->check(CLI::Range(8, 2000))
      ->capture_default_str();
  return {cmd, [o]() { return runDemo(*o); }};
}

}  // namespace cellrelief::app
