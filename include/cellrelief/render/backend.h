// SPDX-License-Identifier: MIT
/// @file backend.h
/// The one interface every renderer implements, in a handful of coarse calls: upload a scene (in
/// the representation's GPU layout: the cell table as a storage buffer, the maps as array
/// textures), render a camera into the frame's buffers, read them back. Calls are per frame, never
/// per ray, so a virtual call costs nothing next to the work behind it; the traversal itself is a
/// policy template inside each backend.
///
/// Backends are chosen at run time by BackendKind or by name ("auto", "cpu", "opengl", "vulkan");
/// the table that maps kinds to factories and says why one is unavailable lives with the backends
/// (backends/backend_table.h), because this layer sits below them.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "cellrelief/core/error.h"
#include "cellrelief/render/camera.h"
#include "cellrelief/render/frame.h"
#include "cellrelief/render/render_options.h"
#include "cellrelief/render/scene.h"

namespace cellrelief::render {

enum class BackendKind { Auto, Cpu, OpenGL, Vulkan };

inline constexpr std::array<BackendKind, 4> kBackendKinds = {BackendKind::Auto, BackendKind::Cpu,
                                                             BackendKind::OpenGL, BackendKind::Vulkan};

inline std::string_view backendName(BackendKind kind) {
  switch (kind) {
    case BackendKind::Auto: return "auto";
    case BackendKind::Cpu: return "cpu";
    case BackendKind::OpenGL: return "opengl";
    case BackendKind::Vulkan: return "vulkan";
  }
  return "unknown";
}

/// The kind named `name` (case-sensitive, as printed by backendName). An unknown name throws an
/// Error that lists the valid ones.
inline BackendKind parseBackendKind(std::string_view name) {
  std::string valid;
  for (BackendKind k : kBackendKinds) {
    if (backendName(k) == name) return k;
    valid += (valid.empty() ? "" : ", ") + std::string(backendName(k));
  }
  throw Error(ErrorKind::InvalidArgument,
              "unknown backend '" + std::string(name) + "' (valid: " + valid + ")");
}

/// Whether a backend can run here, and if not, why ("compiled without Vulkan", "no Vulkan device").
struct Availability {
  bool available = false;
  std::string reason;
  explicit operator bool() const { return available; }
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual BackendKind kind() const = 0;
  /// What runs the frames, e.g. "CPU reference, 2 threads" or the GPU's name.
  virtual std::string description() const = 0;
  /// Converts the scene to the backend's layout and keeps it until the next upload. The scene's
  /// models must outlive the backend's use of them (it holds their shared pointers).
  virtual void upload(const Scene& scene) = 0;
  /// Renders the uploaded scene. May return before the work ends on an asynchronous backend.
  virtual void render(const Camera& camera, const RenderOptions& options) = 0;
  /// Waits for the last render and copies its buffers (options.channels) into `frame`.
  virtual void readBack(Frame& frame) = 0;
  /// Bytes the backend holds for the uploaded scene (maps, tables, acceleration).
  virtual std::size_t sceneBytes() const = 0;
  /// Seconds the last frame took on the device's own clock (GPU timer queries), known after
  /// readBack(); 0 where the backend has no such clock (the CPU reference).
  virtual double deviceSeconds() const { return 0; }

  /// render() then readBack().
  Frame renderFrame(const Camera& camera, const RenderOptions& options) {
    render(camera, options);
    Frame frame;
    readBack(frame);
    return frame;
  }
};

}  // namespace cellrelief::render
