// SPDX-License-Identifier: MIT
/// @file render_options.h
/// How a frame is rendered, independent of the backend: size, buffers, the traversal's search
/// parameters, and which secondary rays shading casts. Every backend reads the same struct so that
/// one scene rendered with one set of options looks the same everywhere.
#pragma once

#include <cstddef>

#include "cellrelief/render/frame.h"
#include "cellrelief/trace/trace_options.h"

namespace cellrelief::render {

struct RenderOptions {
  int width = 800;
  int height = 800;
  unsigned channels = kAllChannels;  ///< FrameChannel flags
  trace::TraceOptions trace;         ///< linear/binary steps, empty-space skipping
  bool shadows = true;               ///< one shadow ray per light from each hit
  int reflectionBounces = 0;         ///< mirror rays per hit (0: none)
  float reflectivity = 0.25f;        ///< weight of the reflected color
  std::size_t threads = 0;           ///< CPU worker threads (0: all cores)
};

}  // namespace cellrelief::render
