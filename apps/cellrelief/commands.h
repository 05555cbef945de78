// SPDX-License-Identifier: MIT
/// @file commands.h
/// The subcommands of the `cellrelief` program. Each registers its options on the CLI11 app and
/// returns the function that runs it; errors propagate as cellrelief::Error to main(), which prints
/// them and exits non-zero.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <string>
#include <utility>

#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>

#include <cellrelief/core/aabb.h>
#include <cellrelief/projection/choice.h>
#include <cellrelief/gpu/gpu_frame.h>
#include <cellrelief/render/backend.h>
#include <cellrelief/render/camera.h>
#include <cellrelief/render/scene.h>

namespace cellrelief::relief {
struct ReliefModel;
}

namespace cellrelief::app {

/// A registered subcommand and what runs it once parsed.
struct Command {
  CLI::App* cli = nullptr;
  std::function<int()> run;
};

Command addInfoCommand(CLI::App& app);
Command addDemoCommand(CLI::App& app);
Command addCellsCommand(CLI::App& app);
Command addConvertCommand(CLI::App& app);
Command addReconstructCommand(CLI::App& app);
Command addRenderCommand(CLI::App& app);
Command addBenchCommand(CLI::App& app);

/// Renders a relief model with the default camera, light and shadows on the CPU reference backend
/// into a size x size PNG; prints one line with the time.
void renderModelPicture(std::shared_ptr<const relief::ReliefModel> model,
                        const std::filesystem::path& png, int size = 800);
Command addIndirectCommand(CLI::App& app);
Command addCompareOptimizersCommand(CLI::App& app);

/// Prints the `info` report of a mesh file (also used by `demo`).
void printMeshInfo(const std::string& path);

/// Seconds on the steady clock since `start`.
inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A byte count as "1.23 MiB".
std::string formatBytes(double bytes);

/// The value of --grid: a whole number N >= 1, or 0 for "auto". Throws Error otherwise.
int parseGridSize(const std::string& grid);

/// The values of --centre, by name (projection::toString). Mapped to the enum's number, which
/// CLI11 prints in its error (the enum's uint8_t would print as a character).
inline std::map<std::string, int> centreNames() {
  using projection::CentreOfProjection;
  std::map<std::string, int> names;
  for (const CentreOfProjection c :
       {CentreOfProjection::CellCentre, CentreOfProjection::SurfaceCentroid, CentreOfProjection::FewestCrossings})
    names.emplace(projection::toString(c), int(c));
  return names;
}

/// The value of --size: "WxH", each 1 to 16384. Throws Error otherwise.
std::pair<int, int> parseImageSize(const std::string& size);

/// --entry of the commands that render, by name: how a GPU backend's traversal reaches the pixels
/// (gpu::RayEntry); the CPU backend has one way. Mapped to the enum, as --centre is.
inline std::map<std::string, gpu::RayEntry> rayEntryNames() {
  return {{"fastest", gpu::RayEntry::Fastest}, {"rasterized", gpu::RayEntry::Rasterized}, {"compute", gpu::RayEntry::Compute}};
}
inline constexpr const char* kRayEntryHelp =
    "GPU backends: fastest (each way timed once on the device, the faster kept; rasterized on CPU devices), "
    "rasterized (the paper's: cells and chart boxes rasterized, a fragment pass) or compute (every pixel)";
/// Sets `entry` on a GPU backend; nothing on the CPU backend.
void setRayEntry(render::Backend& backend, gpu::RayEntry entry);
/// How the backend's last frame reached its pixels: "rasterized entry", "compute entry", or "" (CPU).
std::string lastRayEntry(const render::Backend& backend);

/// The value of --camera around a scene's bounds: "" (the default view), yaw,pitch[,fov] or
/// ex,ey,ez,tx,ty,tz[,fov]. Throws Error otherwise.
render::Camera parseCamera(const std::string& spec, const Aabbd& bounds);

/// Runs `work`; an Error it throws goes on with the input's path in front, so that the user sees
/// which file could not be converted.
template <class Work>
auto withPath(const std::string& input, Work&& work) {
  try {
    return work();
  } catch (const Error& e) {
    throw Error(e.kind(), std::filesystem::path(input), e.what());
  }
}

/// A relief model read from a .crm file, or converted at default settings from a mesh (printing
/// one line about the conversion).
std::shared_ptr<const relief::ReliefModel> loadOrConvert(const std::string& input);

/// `--wrap clamp|repeat`.
Wrap parseWrap(const std::string& wrap);

/// How a height map is shown as a relief surface (parallax occlusion mapping with an indirection
/// map): the options `render`, `view` and `compare-backends` share.
struct SurfaceCli {
  std::string indirection, colors, normals, wrap = "clamp", baseMesh;
  float heightScale = 0;  ///< 0: the indirection map's, else 0.1
  float uvScale = 1;
  int checker = 16;
};
void addSurfaceOptions(CLI::App* cmd, SurfaceCli& o);

/// The scene `render`, `view` and `compare-backends` show: a height map (an image) as a relief
/// surface with `surface`'s maps, a `cellrelief polycube` output folder (its mesh textured through
/// its polycube map), a geometry-texture model (.cgt), else the relief model of loadOrConvert.
render::Scene loadScene(const std::string& input, const SurfaceCli& surface = {});

Command addCompareBackendsCommand(CLI::App& app);
Command addViewCommand(CLI::App& app);
Command addPolycubeCommand(CLI::App& app);
Command addGeoTexCommand(CLI::App& app);

}  // namespace cellrelief::app
