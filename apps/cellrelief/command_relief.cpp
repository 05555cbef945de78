// SPDX-License-Identifier: MIT
/// @file command_relief.cpp
/// `cellrelief convert <mesh> -o model.crm` and `cellrelief reconstruct model.crm -o mesh.ply`.
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>

#include <unistd.h>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/metrics/geometric_error.h>
#include <cellrelief/relief/atlas.h>
#include <cellrelief/relief/error_bounded.h>
#include <cellrelief/relief/model_file.h>

#include "commands.h"
#include "preview.h"

namespace cellrelief::app {

namespace {

struct ConvertCli {
  std::string mesh, output, grid = "auto", texture, atlas, metric = "rms";
  int texels = 0, bits = 16;
  double maxError = 0;
  projection::CentreOfProjection centre = projection::CentreOfProjection::FewestCrossings;
  bool measure = true, quiet = false;
};

/// A progress bar on stderr that redraws in place.
void progressBar(double fraction) {
  const int width = 40, filled = int(fraction * width + 0.5);
  std::fprintf(stderr, "\r  sampling [%.*s%*s] %3d%%", filled, "########################################",
               width - filled, "", int(fraction * 100 + 0.5));
  if (fraction >= 1.0) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

int runConvert(const ConvertCli& o) {
  if (o.output.empty()) throw Error(ErrorKind::InvalidArgument, "convert needs -o model.crm");
  const auto start = std::chrono::steady_clock::now();
  const TriangleMesh mesh = io::readMesh(o.mesh);
  std::printf("mesh          %s: %zu triangles\n", o.mesh.c_str(), mesh.triangleCount());
  relief::ConvertOptions co;
  co.texels = o.texels;
  co.distanceBits = o.bits;
  co.centre = o.centre;
  Image<std::uint8_t> texture;
  if (!o.texture.empty()) {
    const io::ImageFile file = io::readImage(o.texture);
    if (file.bitDepth() != 8) throw Error(ErrorKind::Unsupported, o.texture, "textures must be 8-bit");
    texture = std::get<Image<std::uint8_t>>(file.pixels);
    if (!mesh.hasUVs()) throw Error(ErrorKind::InvalidInput, o.mesh, "a texture needs UVs, and the mesh has none");
    co.texture = &texture;
  }
  // A bar that redraws in place makes sense on a terminal only; logs get the summary.
  if (!o.quiet && mesh.triangleCount() > 100000 && ::isatty(2)) co.progress = progressBar;

  relief::ReliefModel model;
  relief::ConvertReport report;
  if (o.maxError > 0) {
    relief::ErrorBoundOptions eb;
    eb.maxError = o.maxError;
    eb.metric = o.metric == "hausdorff" ? relief::ErrorMetric::Hausdorff : relief::ErrorMetric::Rms;
    eb.convert = co;
    eb.convert.progress = nullptr;
    relief::ErrorBoundResult r = withPath(o.mesh, [&] { return relief::convertWithErrorBound(mesh, eb); });
    std::printf("error bound   %s <= %.4f%% of the diagonal; candidates tried (by predicted bytes):\n",
                o.metric.c_str(), 100 * o.maxError);
    for (const auto& c : r.candidates)
      std::printf("  N = %4d T = %3d  %10s  rms %.4f%%  hausdorff %.4f%%  %s\n", c.gridSize, c.texels,
                  formatBytes(double(c.bytes)).c_str(), 100 * c.rms, 100 * c.hausdorff,
                  c.meets ? "meets the bound" : "");
    if (!r.met) std::printf("  no candidate met the bound: keeping the most accurate one\n");
    model = std::move(r.model);
  } else {
    co.gridSize = parseGridSize(o.grid);
    model = withPath(o.mesh, [&] { return relief::convert(mesh, co, &report); });
    for (const auto& t : report.gridTrials)
      if (t.hausdorff >= 0)
        std::printf("grid search   N = %4d hausdorff %.4f%% of the diagonal\n", t.gridSize, 100 * t.hausdorff);
      else if (t.rimBandRatio > 0)
        std::printf("grid search   N = %4d occlusion %.5f rim band %.5f\n", t.gridSize, t.occlusionRatio,
                    t.rimBandRatio);
      else
        std::printf("grid search   N = %4d occlusion %.5f\n", t.gridSize, t.occlusionRatio);
  }
  if (relief::flatAxis(mesh))
    std::printf("flat mesh     modelled as a closed slab %.3g world units thick (%.2g%% of its size)\n",
                relief::kFlatSlabThickness * double(std::max({mesh.bounds().extent().x, mesh.bounds().extent().y, mesh.bounds().extent().z})),
                100 * relief::kFlatSlabThickness);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::size_t filled = 0;
  for (int l = 0; l < model.layerCount(); ++l)
    for (int b = 0; b < model.texels; ++b)
      for (int a = 0; a < model.texels; ++a) filled += model.distanceCodec.hasSurface(model.distanceCode(l, a, b));
  std::printf("grid          N = %d, %zu grey cells\n", model.gridSize, model.cells.size());
  std::printf("domain faces  %d layers of %d x %d samples (%zu filled, %.1f%%)\n", model.layerCount(),
              model.texels, model.texels, filled,
              100.0 * double(filled) / std::max(1.0, double(model.layerCount()) * model.texels * model.texels));
  if (o.maxError == 0)
    std::printf("projection    centre %s: %zu cells moved; %zu filled samples' lines cross the surface "
                "twice (the side past the second crossing is misread)\n",
                projection::toString(co.centre), report.movedCentres, report.linesCrossedTwice);
  std::printf("maps          distance %d-bit%s%s\n", model.distanceCodec.bits,
              model.normalFormat == relief::NormalFormat::None ? "" : ", normals",
              model.colorFormat == relief::ColorFormat::None ? "" : ", colors");
  std::printf("bytes         %s (look-up table %s)\n", formatBytes(double(model.byteSize())).c_str(),
              formatBytes(double(model.cells.size() * sizeof(relief::CellRecord))).c_str());
  std::printf("quantization  %.3g world units (%.2e of the diagonal)\n",
              model.quantizationError() * model.cellSizeWS,
              model.quantizationError() * model.cellSizeWS / mesh.bounds().diagonal());
  std::printf("time          %.3f s\n", seconds);
  if (o.measure) {
    const auto t0 = std::chrono::steady_clock::now();
    const metrics::SurfaceError e =
        metrics::surfaceError(mesh, metrics::DistanceField(mesh), relief::reconstructPerFace(model), 200000);
    const double d = mesh.bounds().diagonal();
    std::printf("error         rms %.4f%%, hausdorff %.4f%% of the diagonal (the maps' samples, "
                "joined per face, vs mesh; %.2f s to measure)\n",
                100 * e.rms() / d, 100 * e.hausdorff() / d,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  relief::writeRelief(model, o.output);
  std::printf("wrote         %s (%s)\n", o.output.c_str(),
              formatBytes(double(std::filesystem::file_size(o.output))).c_str());
  if (!o.atlas.empty())
    for (const auto& p : relief::writeAtlases(model, o.atlas)) std::printf("wrote         %s\n", p.c_str());
  return 0;
}

struct ReconstructCli {
  std::string model, output;
  int lod = 0;
  relief::ReconstructionMethod method = relief::ReconstructionMethod::Auto;
  std::string preview;
};

int runReconstruct(const ReconstructCli& o) {
  if (o.output.empty()) throw Error(ErrorKind::InvalidArgument, "reconstruct needs -o mesh.ply");
  const relief::ReliefModel model = relief::readRelief(o.model);
  const TriangleMesh mesh = relief::reconstruct(model, {o.lod, o.method});
  io::writeMesh(mesh, o.output);
  const std::size_t boundaryEdges = countBoundaryEdges(mesh);
  std::printf("reconstructed %zu triangles, %zu vertices at level of detail %d (max %d), %s, %zu boundary "
              "edges; wrote %s\n",
              mesh.triangleCount(), mesh.vertexCount(), o.lod, relief::maxLevelOfDetail(model),
              boundaryEdges == 0 ? "closed" : "open", boundaryEdges, o.output.c_str());
  if (!o.preview.empty()) {
    writePreview(mesh, o.preview);
    std::printf("wrote         %s\n", o.preview.c_str());
  }
  return 0;
}

}  // namespace

Command addConvertCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("convert", "Convert a mesh into a relief model (.crm)");
  auto o = std::make_shared<ConvertCli>();
  cmd->add_option("mesh", o->mesh, "Mesh file (.obj .ply .off .stl)")->required();
  cmd->add_option("-o,--output", o->output, "The model file to write (.crm)")->required();
  cmd->add_option("--grid", o->grid, "Cells per side N, or 'auto'")->capture_default_str();
  cmd->add_option("--texels", o->texels,
                  "Samples per face side T (2^k + 1 keeps levels of detail); 0: max(512 / N, 8) + 1")
      ->check(CLI::Range(0, 1025))
      ->capture_default_str();
  cmd->add_option("--bits", o->bits, "Distance quantization: 16 or 8")
      ->check(CLI::IsMember({8, 16}))
      ->capture_default_str();
  cmd->add_option("--max-error", o->maxError,
                  "Choose N and T for this error (fraction of the diagonal) with the least memory");
  cmd->add_option("--metric", o->metric, "Error for --max-error: rms or hausdorff")
      ->check(CLI::IsMember({"rms", "hausdorff"}))
      ->capture_default_str();
  cmd->add_option("--texture", o->texture, "Color texture sampled through the mesh's UVs");
  cmd->add_option("--centre", o->centre,
                  "Centre of projection: fewest-crossings (moved where projection lines cross the "
                  "surface twice), cell (the paper's) or centroid (of the cell's surface)")
      ->transform(CLI::CheckedTransformer(centreNames(), CLI::ignore_case))
      ->default_str("fewest-crossings");
  cmd->add_option("--atlas", o->atlas, "Folder for PNG atlases of the maps");
  cmd->add_flag("!--no-error", o->measure, "Skip measuring the error of the result");
  cmd->add_flag("--quiet", o->quiet, "No progress bar");
  return {cmd, [o]() { return runConvert(*o); }};
}

Command addReconstructCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("reconstruct", "Rebuild a triangle mesh from a relief model");
  auto o = std::make_shared<ReconstructCli>();
  cmd->add_option("model", o->model, "Relief model (.crm)")->required();
  cmd->add_option("-o,--output", o->output, "Mesh file to write")->required();
  cmd->add_option("--lod", o->lod, "Level of detail (0: every sample)")->capture_default_str();
  const std::map<std::string, relief::ReconstructionMethod> methods{
      {"auto", relief::ReconstructionMethod::Auto},
      {"closed", relief::ReconstructionMethod::Closed},
      {"per-face", relief::ReconstructionMethod::PerFace}};
  cmd->add_option("--method", o->method,
                  "auto: closed (the zero set of the model's field, no cracks) for a closed input "
                  "of several cells, per-face for an open, single-cell or thin one; per-face: the "
                  "paper's, each face's samples joined")
      ->transform(CLI::CheckedTransformer(methods, CLI::ignore_case))
      ->default_str("auto");
  cmd->add_option("--preview", o->preview, "Also write a picture of the mesh (PNG)");
  return {cmd, [o]() { return runReconstruct(*o); }};
}

}  // namespace cellrelief::app
