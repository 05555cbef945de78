// SPDX-License-Identifier: MIT
/// @file backend_table.h
/// The explicit table from BackendKind to factories, and why a backend is unavailable. No
/// self-registering statics: what a build holds is decided here, by the CELLRELIEF_HAS_<BACKEND>
/// definitions the `cellrelief::backends` target carries, so a reader sees every backend in one
/// place and an absent dependency compiles nothing.
///
/// "auto" takes a hardware GPU when there is one: Vulkan on a discrete, integrated or virtual
/// GPU, else OpenGL on a hardware renderer. On software rasterizers only (llvmpipe, lavapipe:
/// machines without a GPU) it takes OpenGL: bench_backends measured Vulkan at about 1.1x
/// OpenGL per frame there (9 of 12 measurements, the rest within this machine's noise; one GLSL
/// source, docs/backends.md), but OpenGL reaches the first frame 0.5 to 0.7 s sooner, because
/// Mesa caches its compiled shader variants on disk while lavapipe compiles every pipeline again
/// in each process, and auto mostly serves one-shot commands. Both are 1.1x to 2.5x the CPU
/// reference. Without either, auto is the CPU reference.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cellrelief/cpu/cpu_backend.h"
#ifdef CELLRELIEF_HAS_OPENGL
#include "cellrelief/gl/gl_backend.h"
#endif
#ifdef CELLRELIEF_HAS_VULKAN
#include "cellrelief/vulkan/vulkan_backend.h"
#endif
#include "cellrelief/render/backend.h"

namespace cellrelief::backends {

/// What --backend takes, for a command line's help.
inline constexpr const char* kBackendHelp =
    "auto, cpu, opengl or vulkan (auto: Vulkan on a hardware GPU, else OpenGL on one; without a GPU "
    "OpenGL on llvmpipe: within about 10% of Vulkan on lavapipe per frame and 0.5 s sooner to the first, "
    "its shaders cached on disk; both faster than cpu; else cpu; see docs/backends.md)";

/// What --device takes, for a command line's help.
inline constexpr const char* kDeviceHelp =
    "Vulkan device to render on: part of its name, case-insensitive (e.g. llvmpipe, NVIDIA); default: "
    "CELLRELIEF_VULKAN_DEVICE, else the first discrete, integrated, virtual, then CPU device";

/// How to create a backend beyond its kind.
struct BackendSettings {
  std::string vulkanDevice;  ///< part of a Vulkan device's name (vulkan/vulkan_context.h); empty: the ranking
};

/// The settings that apply to `kind`: for a program that creates several kinds of backend from
/// one --device (which names a Vulkan device only).
inline BackendSettings settingsFor(render::BackendKind kind, const BackendSettings& settings) {
  return kind == render::BackendKind::Vulkan ? settings : BackendSettings{};
}

/// Whether `kind` can render here; for Auto, whether any backend can.
inline render::Availability isAvailable(render::BackendKind kind) {
  using render::BackendKind;
  switch (kind) {
    case BackendKind::Auto:
    case BackendKind::Cpu: return {true, ""};
    case BackendKind::OpenGL:
#ifdef CELLRELIEF_HAS_OPENGL
      return gl::probeAvailability();
#else
      return {false, "compiled without OpenGL (install libegl-dev libegl1-mesa-dev)"};
#endif
    case BackendKind::Vulkan:
#ifdef CELLRELIEF_HAS_VULKAN
      return vulkan::probeAvailability();
#else
      return {false, "compiled without Vulkan (install libvulkan-dev glslc)"};
#endif
  }
  return {false, "unknown backend kind"};
}

/// A renderer (not Auto) and whether it runs here.
struct RendererStatus {
  render::BackendKind kind;
  render::Availability availability;
};
/// Every renderer in the table's order (cpu, opengl, vulkan), with whether it runs here and why not.
inline std::vector<RendererStatus> renderers() {
  std::vector<RendererStatus> out;
  for (render::BackendKind k : render::kBackendKinds)
    if (k != render::BackendKind::Auto) out.push_back({k, isAvailable(k)});
  return out;
}

/// The kind "auto" stands for here.
inline render::BackendKind resolve(render::BackendKind kind) {
  using render::BackendKind;
  if (kind != BackendKind::Auto) return kind;
#ifdef CELLRELIEF_HAS_VULKAN
  if (vulkan::probe().availability && !vulkan::probe().software) return BackendKind::Vulkan;
#endif
#ifdef CELLRELIEF_HAS_OPENGL
  if (gl::probe().availability && !gl::probe().software) return BackendKind::OpenGL;
#endif
  // Software rasterizers only: the one measured faster on this machine class (above).
#ifdef CELLRELIEF_HAS_OPENGL
  if (gl::probe().availability) return BackendKind::OpenGL;
#endif
#ifdef CELLRELIEF_HAS_VULKAN
  if (vulkan::probe().availability) return BackendKind::Vulkan;
#endif
  return BackendKind::Cpu;
}

/// A new backend of `kind`; throws Error (Unsupported) with the reason when it cannot run here.
/// A Vulkan device named in `settings` is an error for a backend that is not Vulkan (the name
/// would otherwise be ignored).
inline std::unique_ptr<render::Backend> createBackend(render::BackendKind kind, const BackendSettings& settings = {}) {
  const render::BackendKind resolved = resolve(kind);
  if (!settings.vulkanDevice.empty() && resolved != render::BackendKind::Vulkan)
    throw Error(ErrorKind::InvalidArgument, "a Vulkan device ('" + settings.vulkanDevice + "') was named, but backend '" +
                                                std::string(render::backendName(resolved)) + "' is not Vulkan");
  if (const render::Availability a = isAvailable(resolved); !a)
    throw Error(ErrorKind::Unsupported,
                "backend '" + std::string(render::backendName(resolved)) + "': " + a.reason);
  switch (resolved) {
    case render::BackendKind::Cpu: return std::make_unique<cpu::CpuBackend>();
#ifdef CELLRELIEF_HAS_OPENGL
    case render::BackendKind::OpenGL: return std::make_unique<gl::GlBackend>();
#endif
#ifdef CELLRELIEF_HAS_VULKAN
    case render::BackendKind::Vulkan:
      return std::make_unique<vulkan::VulkanBackend>(vulkan::ContextOptions{.device = settings.vulkanDevice});
#endif
    default: break;
  }
  throw Error(ErrorKind::Unsupported,
              "backend '" + std::string(render::backendName(resolved)) + "' has no factory");
}

inline std::unique_ptr<render::Backend> createBackend(std::string_view name) {
  return createBackend(render::parseBackendKind(name));
}

}  // namespace cellrelief::backends
