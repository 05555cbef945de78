// SPDX-License-Identifier: MIT
/// @file command_demo.cpp
/// `cellrelief demo [mesh]`: the embedded default job. Without a mesh it generates the built-in
/// model (a sphere displaced by ridged noise, a few hundred thousand triangles), writes it as PLY
/// and reports on it; with a mesh it reports on the user's mesh and writes it as PLY. Later issues
/// add conversion and a rendered PNG to this job.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>

#include "commands.h"
#include "preview.h"

namespace cellrelief::app {

namespace {
struct DemoOptions {
  std::string input;
  std::string outputDir = "out/demo";
  int subdivisions = 7;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int runDemo(const DemoOptions& o) {
  std::filesystem::create_directories(o.outputDir);
  const std::filesystem::path outDir(o.outputDir);
  std::filesystem::path model;
  if (o.input.empty()) {
    auto start = std::chrono::steady_clock::now();
    DisplacedSphereOptions sphere;
    sphere.subdivisions = o.subdivisions;
    const TriangleMesh mesh = makeDisplacedSphere(sphere);
    std::printf("demo: generated the built-in model: %zu triangles, %zu vertices in %.2f s\n",
                mesh.triangleCount(), mesh.vertexCount(), secondsSince(start));
    model = outDir / "displaced_sphere.ply";
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
  {
    const TriangleMesh written = io::readMesh(model);
    const std::filesystem::path picture = outDir / (model.stem().string() + ".png");
    writePreview(written, picture);
    std::printf("demo: wrote %s (a picture of the model)\n", picture.c_str());
  }
  std::printf("\n");
  printMeshInfo(model.string());
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
  cmd->add_option("--subdivisions", o->subdivisions,
                  "Icosphere subdivisions of the built-in model (20 * 4^s triangles)")
      ->check(CLI::Range(0, 9))
      ->capture_default_str();
  return {cmd, [o]() { return runDemo(*o); }};
}

}  // namespace cellrelief::app
