// SPDX-License-Identifier: MIT
/// @file command_view.cpp
/// `cellrelief view model.crm|mesh`: a GLFW window that shows the relief model as a backend
/// renders it, with orbit (left drag), pan (right drag) and zoom (wheel), and keys that switch the
/// backend live (1 cpu, 2 opengl, 3 vulkan), toggle shadows (S) and skipping (K), and cycle the
/// channel shown (C: color, depth, normal, cell id, a heat map of steps per ray); frame time and
/// Mrays/s in the title. P writes a screenshot. --frames N --screenshot F renders N frames, saves
/// what the window shows and exits (the test does this under xvfb-run).
///
/// Every backend renders into its own buffers and the window only displays the color image (a
/// texture blitted to the window), so the picture is the backend's, pixel for pixel. The window's
/// context is made through EGL, like the OpenGL backend's, so both live in one process.
#include <chrono>
#include <cmath>
#include <cstdio>

#include <cellrelief/backends/backend_table.h>
#include <cellrelief/io/image_io.h>
#include <cellrelief/relief/relief_model.h>

#include "commands.h"

#ifdef CELLRELIEF_HAS_VIEWER
#define GLFW_INCLUDE_NONE  // the GL declarations come from the backend headers (glcorearb.h)
#include <GLFW/glfw3.h>
#endif

namespace cellrelief::app {
namespace {

struct ViewCli {
  std::string input, backend = "auto", device, size = "960x720", camera, screenshot, channel = "color";
  int frames = 0;
  SurfaceCli surface;
};

enum class Channel { Color, Depth, Normal, Cell, Steps };
constexpr const char* kChannelNames[] = {"color", "depth", "normal", "cell id", "steps per ray"};
constexpr const char* kChannelKeys[] = {"color", "depth", "normal", "cell", "steps"};

/// The channel as display colors (RGB over the scene's white background).
Image<std::uint8_t> displayImage(const render::Frame& f, Channel channel) {
  Image<std::uint8_t> out(f.width, f.height, 3, 255);
  float lo = 1e30f, hi = 0, maxSteps = 1;
  if (channel == Channel::Depth)
    for (float d : f.depth.levelData())
      if (std::isfinite(d)) lo = std::min(lo, d), hi = std::max(hi, d);
  if (channel == Channel::Steps)
    for (float s : f.steps.levelData()) maxSteps = std::max(maxSteps, s);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      Vec3f c(1);
      const bool hit = f.mask.at(x, y, 0) != 0;
      switch (channel) {
        case Channel::Color:
          for (int k = 0; k < 3; ++k) out.at(x, y, k) = f.color.at(x, y, k);
          continue;
        case Channel::Depth:
          if (hit) c = Vec3f(1.0f - 0.85f * (f.depth.at(x, y, 0) - lo) / std::max(hi - lo, 1e-20f));
          break;
        case Channel::Normal:
          if (hit) c = 0.5f * (Vec3f(f.normal.at(x, y, 0), f.normal.at(x, y, 1), f.normal.at(x, y, 2)) + 1.0f);
          break;
        case Channel::Cell:
          if (hit) {  // a hashed color per cell
            std::uint32_t h = std::uint32_t(f.cell.at(x, y, 0)) * 2654435761u;
            c = Vec3f(float((h >> 8) & 255), float((h >> 16) & 255), float((h >> 24) & 255)) / 255.0f;
          }
          break;
        case Channel::Steps: {  // black (none) through red to yellow (the frame's most)
          const float s = std::sqrt(f.steps.at(x, y, 0) / maxSteps);
          c = Vec3f(std::min(1.0f, 2 * s), std::max(0.0f, 2 * s - 1), 0.0f);
          break;
        }
      }
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = std::uint8_t(std::lround(255 * std::clamp(c[k], 0.0f, 1.0f)));
    }
  return out;
}

#ifdef CELLRELIEF_HAS_VIEWER

/// Orbit camera around the model: yaw and pitch in degrees, distance, target.
struct Orbit {
  double yaw = 35, pitch = 20, distance = 1, fov = 40;
  Vec3d target{0};
  render::Camera camera() const {
    const double a = yaw * M_PI / 180, b = pitch * M_PI / 180;
    const Vec3d dir(std::cos(b) * std::sin(a), std::sin(b), std::cos(b) * std::cos(a));
    return {target + distance * dir, target, Vec3d(0, 1, 0), fov};
  }
};

struct ViewerState {
  Orbit orbit;
  double radius = 1;
  bool dragging = false, panning = false, dirty = true, screenshotRequested = false;
  double lastX = 0, lastY = 0;
  int wantedBackend = -1;
  bool shadows = true, skip = true;
  Channel channel = Channel::Color;
};

ViewerState* stateOf(GLFWwindow* w) { return static_cast<ViewerState*>(glfwGetWindowUserPointer(w)); }

void installCallbacks(GLFWwindow* window) {
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
    ViewerState& s = *stateOf(w);
    if (button == GLFW_MOUSE_BUTTON_LEFT) s.dragging = action == GLFW_PRESS;
    if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE) s.panning = action == GLFW_PRESS;
    glfwGetCursorPos(w, &s.lastX, &s.lastY);
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    ViewerState& s = *stateOf(w);
    const double dx = x - s.lastX, dy = y - s.lastY;
    s.lastX = x, s.lastY = y;
    if (s.dragging) {
      s.orbit.yaw -= 0.3 * dx;
      s.orbit.pitch = std::clamp(s.orbit.pitch + 0.3 * dy, -89.0, 89.0);
      s.dirty = true;
    } else if (s.panning) {
      const render::Camera::Basis b = s.orbit.camera().basis();
      const double scale = 0.002 * s.orbit.distance;
      s.orbit.target += scale * (-dx * b.right + dy * b.up);
      s.dirty = true;
    }
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
    ViewerState& s = *stateOf(w);
    s.orbit.distance = std::clamp(s.orbit.distance * std::pow(0.9, dy), 0.05 * s.radius, 50 * s.radius);
    s.dirty = true;
  });
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS) return;
    ViewerState& s = *stateOf(w);
    switch (key) {
      case GLFW_KEY_1: s.wantedBackend = int(render::BackendKind::Cpu); break;
      case GLFW_KEY_2: s.wantedBackend = int(render::BackendKind::OpenGL); break;
      case GLFW_KEY_3: s.wantedBackend = int(render::BackendKind::Vulkan); break;
      case GLFW_KEY_S: s.shadows = !s.shadows; break;
      case GLFW_KEY_K: s.skip = !s.skip; break;
      case GLFW_KEY_C: s.channel = Channel((int(s.channel) + 1) % 5); break;
      case GLFW_KEY_P: s.screenshotRequested = true; break;
      case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(w, 1); break;
      default: return;
    }
    s.dirty = true;
  });
}

/// What the window shows, read back from its framebuffer (rows top to bottom).
Image<std::uint8_t> readWindow(int width, int height) {
  std::vector<std::uint8_t> pixels(std::size_t(width) * height * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  Image<std::uint8_t> out(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        out.at(x, height - 1 - y, c) = pixels[(std::size_t(y) * width + x) * 3 + std::size_t(c)];
  return out;
}

int runView(const ViewCli& o) {
  const auto [width, height] = parseImageSize(o.size);
  const render::Scene scene = loadScene(o.input, o.surface);
  const Aabbd bounds = scene.boundsWS();
  ViewerState state;
  {
    bool known = false;
    for (int c = 0; c < 5; ++c)
      if (o.channel == kChannelKeys[c]) state.channel = Channel(c), known = true;
    if (!known)
      throw Error(ErrorKind::InvalidArgument, "--channel '" + o.channel + "': expected color, depth, normal, cell or steps");
    const render::Camera start = parseCamera(o.camera, bounds);
    state.orbit.target = start.target;
    state.orbit.distance = glm::length(start.eye - start.target);
    state.orbit.fov = start.verticalFovDegrees;
    const Vec3d d = glm::normalize(start.eye - start.target);
    state.orbit.pitch = std::asin(std::clamp(d.y, -1.0, 1.0)) * 180 / M_PI;
    state.orbit.yaw = std::atan2(d.x, d.z) * 180 / M_PI;
    state.radius = 0.5 * bounds.diagonal();
  }
  // The backend first: its EGL display must come up before GLFW's (GLFW terminates EGL on exit).
  render::BackendKind kind = backends::resolve(render::parseBackendKind(o.backend));
  const backends::BackendSettings settings{.vulkanDevice = o.device};
  auto create = [&](render::BackendKind k) {
    return backends::createBackend(k, backends::settingsFor(k, settings));
  };
  if (!o.device.empty() && kind != render::BackendKind::Vulkan)
    throw Error(ErrorKind::InvalidArgument, "--device names a Vulkan device, but the backend is " +
                                                std::string(render::backendName(kind)) + " (use --backend vulkan)");
  std::unique_ptr<render::Backend> backend = create(kind);
  backend->upload(scene);

  if (!glfwInit()) throw Error(ErrorKind::Unsupported, "view: GLFW cannot start (no display? run under xvfb-run)");
  // The backend goes before GLFW: glfwTerminate ends EGL, which the backend's context may share.
  struct Terminate {
    std::unique_ptr<render::Backend>& backend;
    ~Terminate() {
      backend.reset();
      glfwTerminate();
    }
  } terminate{backend};
  glfwWindowHint(GLFW_CONTEXT_CREATION_API, GLFW_EGL_CONTEXT_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_RESIZABLE, o.frames > 0 ? GLFW_FALSE : GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(width, height, "cellrelief view", nullptr, nullptr);
  if (!window) {
    const char* why = nullptr;
    glfwGetError(&why);
    throw Error(ErrorKind::Unsupported, std::string("view: no OpenGL 4.5 window: ") + (why ? why : "unknown reason"));
  }
  glfwSetWindowUserPointer(window, &state);
  installCallbacks(window);
  glfwMakeContextCurrent(window);
  glfwSwapInterval(0);
  GLuint texture = 0, framebuffer = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &texture);
  glCreateFramebuffers(1, &framebuffer);
  int textureW = 0, textureH = 0;

  int shown = 0;
  double lastSeconds = 0;
  Image<std::uint8_t> display;
  while (!glfwWindowShouldClose(window)) {
    if (state.wantedBackend >= 0) {
      const auto wanted = render::BackendKind(state.wantedBackend);
      state.wantedBackend = -1;
      if (const render::Availability a = backends::isAvailable(wanted); !a) {
        std::printf("view: %s is not available: %s\n", std::string(render::backendName(wanted)).c_str(), a.reason.c_str());
      } else if (wanted != kind) {
        kind = wanted;
        backend = create(kind);
        backend->upload(scene);
      }
    }
    int fbW = 0, fbH = 0;
    glfwGetFramebufferSize(window, &fbW, &fbH);
    if (fbW != textureW || fbH != textureH) state.dirty = true;  // resized: the old frame no longer fits
    if (state.dirty && fbW > 0 && fbH > 0) {
      render::RenderOptions options;
      options.width = fbW;
      options.height = fbH;
      options.shadows = state.shadows;
      options.trace.skipEmptySpace = state.skip;
      const auto t0 = std::chrono::steady_clock::now();
      const render::Frame frame = backend->renderFrame(state.orbit.camera(), options);
      lastSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      display = displayImage(frame, state.channel);
      glfwMakeContextCurrent(window);
      if (textureW != fbW || textureH != fbH) {
        glDeleteTextures(1, &texture);
        glCreateTextures(GL_TEXTURE_2D, 1, &texture);
        glTextureStorage2D(texture, 1, GL_RGB8, fbW, fbH);
        glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, texture, 0);
        textureW = fbW, textureH = fbH;
      }
      glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
      glTextureSubImage2D(texture, 0, 0, 0, fbW, fbH, GL_RGB, GL_UNSIGNED_BYTE, display.levelData().data());
      state.dirty = o.frames > 0;  // a timed run keeps rendering; otherwise only on change
      char title[256];
      std::snprintf(title, sizeof title, "cellrelief view: %s, %s, shadows %s, skip %s: %.1f ms, %.2f Mrays/s",
                    std::string(render::backendName(kind)).c_str(), kChannelNames[int(state.channel)],
                    state.shadows ? "on" : "off", state.skip ? "on" : "off", lastSeconds * 1e3,
                    double(fbW) * fbH / lastSeconds * 1e-6);
      glfwSetWindowTitle(window, title);
      if (o.frames > 0) std::printf("frame %d: %s\n", shown + 1, title);
    }
    glfwMakeContextCurrent(window);
    // Frame rows run top to bottom, the window's bottom to top: the blit flips them.
    glBlitNamedFramebuffer(framebuffer, 0, 0, fbH, fbW, 0, 0, 0, fbW, fbH, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    const bool last = o.frames > 0 && shown + 1 >= o.frames;
    if ((last && !o.screenshot.empty()) || state.screenshotRequested) {
      const std::string path = !o.screenshot.empty() ? o.screenshot : "cellrelief_view.png";
      io::writePng(readWindow(fbW, fbH), path);
      std::printf("wrote %s\n", path.c_str());
      state.screenshotRequested = false;
    }
    glfwSwapBuffers(window);
    ++shown;
    if (last) break;
    o.frames > 0 ? glfwPollEvents() : glfwWaitEvents();
  }
  glDeleteFramebuffers(1, &framebuffer);
  glDeleteTextures(1, &texture);
  glfwDestroyWindow(window);
  return 0;
}

#else

int runView(const ViewCli&) {
  throw Error(ErrorKind::Unsupported, "view: compiled without GLFW and OpenGL (install libglfw3-dev libegl-dev)");
}

#endif

}  // namespace

Command addViewCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "view", "Show a relief model in a window: orbit, pan, zoom; keys 1/2/3 switch the backend (cpu, opengl, "
              "vulkan), S shadows, K skipping, C channel (color, depth, normal, cell id, steps), P screenshot");
  auto o = std::make_shared<ViewCli>();
  cmd->add_option("model", o->input,
                  "Relief model (.crm), geometry textures (.cgt), mesh (.obj .ply .off .stl), a folder "
                  "written by `cellrelief polycube`, or a height map (.png .jpg .tga .bmp) shown by parallax "
                  "occlusion mapping")
      ->required();
  cmd->add_option("--backend", o->backend, backends::kBackendHelp)->capture_default_str();
  cmd->add_option("--device", o->device, backends::kDeviceHelp);
  cmd->add_option("--size", o->size, "Window size WxH")->capture_default_str();
  cmd->add_option("--camera", o->camera, "Starting view: yaw,pitch[,fov] or ex,ey,ez,tx,ty,tz[,fov]");
  cmd->add_option("--frames", o->frames, "Render this many frames, then exit (0: until closed)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--channel", o->channel, "Channel shown first: color, depth, normal, cell or steps")
      ->capture_default_str();
  cmd->add_option("--screenshot", o->screenshot, "With --frames: write what the window shows at the end (.png)");
  addSurfaceOptions(cmd, o->surface);
  return {cmd, [o]() { return runView(*o); }};
}

}  // namespace cellrelief::app
