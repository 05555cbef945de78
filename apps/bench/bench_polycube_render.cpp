// SPDX-License-Identifier: MIT
/// @file bench_polycube_render.cpp
/// Benchmark: what PolyCube-Maps texturing costs a frame. Per mesh, its automatic polycube and
/// map, the grid baked into T2 (S = 16); then per backend the same view rendered untextured (the
/// mesh in grey with its vertex normals, TextureUse::None: the peer, which costs no more than
/// plain 2D texturing would), and textured through P, M and T2 with each filter. The ratio
/// textured / untextured is the texturing's cost; the goal is at most 2x that of plain 2D
/// texturing, which this bounds from above. Prints the table, writes CSV.
///
///   bench_polycube_render [--data DIR] [--out out/bench] [--quick] [--threads N]
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <cellrelief/backends/backend_table.h>
#include <cellrelief/core/parallel.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/from_mesh.h>
#include <cellrelief/polycube/parameterization.h>

#include "bench_common.h"
#include "bench_programs.h"

namespace cellrelief::bench::polycube_render_program {

int run(int argc, char** argv) {
  CLI::App app{"PolyCube-Maps texturing: frame time textured over untextured, per backend", "bench_polycube_render"};
  bench::BenchOptions options;
  options.addTo(app);
  CLI11_PARSE(app, argc, argv);
  const ThreadLimit limit{std::size_t(options.threads)};
  const std::vector<std::pair<std::string, std::string>> meshes =
      options.quick ? std::vector<std::pair<std::string, std::string>>{{"3holes", "meshes/small/3holes__cinolib.obj"}}
                    : std::vector<std::pair<std::string, std::string>>{
                          {"3holes", "meshes/small/3holes__cinolib.obj"},
                          {"spot", "meshes/small/spot__common-3d-test-models.obj"},
                          {"bumpy-cube", "meshes/medium/bumpy-cube__libigl-tutorial-data.obj"}};
  const int size = options.quick ? 128 : 512, repeats = options.quick ? 1 : 5;
  bench::CsvWriter csv(std::filesystem::path(options.out) / "polycube_render.csv",
                       "mesh,triangles,backend,texturing,seconds,device_seconds,over_untextured");
  std::printf("%d x %d pixels, median of %d frames; device: the GPU's own clock where it has one\n", size, size,
              repeats);
  std::printf("\n%-11s %9s %-8s %-22s %10s %10s %16s\n", "mesh", "triangles", "backend", "texturing", "frame [ms]",
              "device [ms]", "over untextured");
  for (const auto& [name, relative] : meshes) {
    TriangleMesh mesh;
    std::shared_ptr<polycube::TexturedMesh> textured;
    try {
      mesh = io::readMesh(options.data + "/" + relative);
      const polycube::PolycubeResult cubes = polycube::polycubeOfMesh(mesh);
      auto surface = std::make_shared<const polycube::PolycubeSurface>(cubes.polycube);
      const polycube::PolycubeParameterization map = polycube::parameterize(mesh, *surface, cubes.frame);
      textured = std::make_shared<polycube::TexturedMesh>();
      textured->mesh = mesh;
      textured->texture.assign(map.texture.begin(), map.texture.end());
      textured->t2 = std::make_shared<const polycube::PolycubeTexture>(surface, polycube::gridSignalFor(16),
                                                                       polycube::TextureOptions{16});
    } catch (const Error& e) {
      std::printf("%-11s failed: %s\n", name.c_str(), e.what());
      continue;
    }
    struct Variant {
      const char* label;
      polycube::TextureUse use;
      polycube::TextureFilter filter;
    };
    const Variant variants[] = {{"untextured", polycube::TextureUse::None, polycube::TextureFilter::Nearest},
                                {"polycube nearest", polycube::TextureUse::Color, polycube::TextureFilter::Nearest},
                                {"polycube bilinear", polycube::TextureUse::Color, polycube::TextureFilter::Bilinear},
                                {"polycube trilinear", polycube::TextureUse::Color, polycube::TextureFilter::Trilinear}};
    for (render::BackendKind kind : {render::BackendKind::Cpu, render::BackendKind::OpenGL, render::BackendKind::Vulkan}) {
      if (const render::Availability a = backends::isAvailable(kind); !a) {
        std::printf("%-11s %9s %-8s skipped: %s\n", name.c_str(), "", std::string(render::backendName(kind)).c_str(),
                    a.reason.c_str());
        continue;
      }
      std::unique_ptr<render::Backend> backend = backends::createBackend(kind);
      double untextured = 0;
      for (const Variant& v : variants) {
        auto instance = std::make_shared<polycube::TexturedMesh>(*textured);
        instance->use = v.use;
        instance->filter = v.filter;
        render::Scene scene;
        scene.polycubeMeshes.push_back(instance);
        backend->upload(scene);
        const Aabbd bounds = scene.boundsWS();
        const render::Camera camera = render::Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), 35, 25);
        render::RenderOptions o;
        o.width = o.height = size;
        o.channels = render::kColor;
        backend->renderFrame(camera, o);  // warm: shader variants, acceleration
        std::vector<double> devices;
        const double seconds = bench::medianSeconds(repeats, [&] {
          backend->renderFrame(camera, o);
          devices.push_back(backend->deviceSeconds());
        });
        std::sort(devices.begin(), devices.end());
        const double device = devices[devices.size() / 2];
        const double measure = device > 0 ? device : seconds;
        if (v.use == polycube::TextureUse::None) untextured = measure;
        const double ratio = untextured > 0 ? measure / untextured : 0;
        std::printf("%-11s %9zu %-8s %-22s %10.2f %10.2f %15.2fx\n", name.c_str(), mesh.triangleCount(),
                    std::string(render::backendName(kind)).c_str(), v.label, seconds * 1e3, device * 1e3, ratio);
        csv.row(name, mesh.triangleCount(), render::backendName(kind), v.label, seconds, device, ratio);
      }
    }
  }
  std::printf("\nover untextured: the frame (device clock where there is one) over the same backend's untextured frame.\n"
              "The GPU backends ray cast the meshes (BVH) in the traversal shader, so a frame's cost is mostly the\n"
              "traversal; the texturing's share is what the ratio shows.\nwrote %s\n", csv.path().c_str());
  return 0;
}

}  // namespace cellrelief::bench::polycube_render_program
