// SPDX-License-Identifier: MIT
/// @file egl_context.h
/// A headless OpenGL 4.5 core context through EGL: on the EGL device platform when a hardware GPU
/// exposes one (NVIDIA, Mesa's hardware drivers), else on Mesa's surfaceless platform (llvmpipe
/// on a machine without a GPU). No window and no X server. CELLRELIEF_EGL_PLATFORM=device or
/// surfaceless forces one. Failures say why: "no EGL display", "OpenGL 4.5 core not available:
/// the driver offers 3.3".
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"

namespace cellrelief::gl {

class EglContext {
 public:
  /// Creates the context; throws Error (Unsupported) with the reason when it cannot.
  EglContext() {
    std::string reasons;
    const char* forced = std::getenv("CELLRELIEF_EGL_PLATFORM");
    const std::string platform = forced ? forced : "";
    if (platform.empty() || platform == "device") {
      if (tryDevicePlatform(reasons)) return;
    }
    if (platform.empty() || platform == "surfaceless") {
      if (tryDisplay(eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                     "EGL surfaceless", reasons))
        return;
    }
    throw Error(ErrorKind::Unsupported, reasons.empty() ? "no EGL display" : reasons);
  }
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;
  ~EglContext() {
    if (mContext != EGL_NO_CONTEXT) {
      if (eglGetCurrentContext() == mContext)
        eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(mDisplay, mContext);
    }
    // The display is not terminated: EGL shares it with every other context on the platform.
  }

  /// Makes the context current on the calling thread.
  void makeCurrent() const {
    if (eglGetCurrentContext() != mContext &&
        !eglMakeCurrent(mDisplay, EGL_NO_SURFACE, EGL_NO_SURFACE, mContext))
      throw Error(ErrorKind::Unsupported, "eglMakeCurrent failed (EGL error " + hex(eglGetError()) + ")");
  }

  /// "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL surfaceless".
  const std::string& description() const { return mDescription; }
  const std::string& renderer() const { return mRenderer; }
  /// Whether the renderer is a software rasterizer (llvmpipe, softpipe, swrast).
  bool isSoftware() const {
    return mRenderer.find("llvmpipe") != std::string::npos ||
           mRenderer.find("softpipe") != std::string::npos || mRenderer.find("swrast") != std::string::npos;
  }

 private:
  static std::string hex(EGLint v) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%04x", unsigned(v));
    return text;
  }
  static bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
      if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
  }

  /// A hardware device of EGL_EXT_platform_device (Mesa's software device is left to the
  /// surfaceless platform, which gives the same llvmpipe).
  bool tryDevicePlatform(std::string& reasons) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasExtension(client, "EGL_EXT_device_enumeration") || !hasExtension(client, "EGL_EXT_platform_device"))
      return false;
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto queryString =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (!queryDevices || !queryString) return false;
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (!queryDevices(16, devices, &count)) return false;
    for (EGLint i = 0; i < count; ++i) {
      if (hasExtension(queryString(devices[i], EGL_EXTENSIONS), "EGL_MESA_device_software")) continue;
      if (tryDisplay(eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr), "EGL device",
                     reasons))
        return true;
    }
    return false;
  }

  bool tryDisplay(EGLDisplay display, const char* platform, std::string& reasons) {
    auto fail = [&](const std::string& why) {
      reasons += (reasons.empty() ? "" : "; ") + std::string(platform) + ": " + why;
      return false;
    };
    if (display == EGL_NO_DISPLAY) return fail("no EGL display");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return fail("no EGL display (eglInitialize failed)");
    if (!eglBindAPI(EGL_OPENGL_API)) return fail("EGL cannot bind the desktop OpenGL API");
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(extensions, "EGL_KHR_surfaceless_context"))
      return fail("EGL_KHR_surfaceless_context is missing");
    EGLConfig config = nullptr;
    if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
      const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(display, want, &config, 1, &n) || n < 1) return fail("no EGL config for OpenGL");
    }
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT) return fail("OpenGL 4.5 core not available: the driver offers " + offeredVersion(display, config));
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      eglDestroyContext(display, context);
      return fail("eglMakeCurrent failed (EGL error " + hex(eglGetError()) + ")");
    }
    mDisplay = display;
    mContext = context;
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    mRenderer = renderer ? renderer : "unknown renderer";
    mDescription = mRenderer + ", OpenGL " + (version ? version : "?") + ", " + platform;
    return true;
  }

  /// The version a context without requirements gets, to say what the driver offers instead.
  static std::string offeredVersion(EGLDisplay display, EGLConfig config) {
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, nullptr);
    if (context == EGL_NO_CONTEXT) return "no desktop OpenGL context at all";
    std::string offered = "an unknown version";
    if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      GLint major = 0, minor = 0;
      glGetIntegerv(GL_MAJOR_VERSION, &major);
      glGetIntegerv(GL_MINOR_VERSION, &minor);
      if (major > 0) offered = std::to_string(major) + "." + std::to_string(minor);
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    eglDestroyContext(display, context);
    return offered;
  }

  EGLDisplay mDisplay = EGL_NO_DISPLAY;
  EGLContext mContext = EGL_NO_CONTEXT;
  std::string mRenderer, mDescription;
};

}  // namespace cellrelief::gl
