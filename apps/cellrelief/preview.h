// SPDX-License-Identifier: MIT
/// @file preview.h
/// A small z-buffer rasterizer for pictures of meshes (the demo model, dumped cells), so that the
/// command line produces something a person can look at before the relief renderers exist. It is a
/// preview, not a backend: flat Lambert shading with vertex colors, one fixed three-quarter view.
#pragma once

#include <filesystem>

#include <cellrelief/core/triangle_mesh.h>

namespace cellrelief::app {

struct PreviewOptions {
  int width = 800;
  int height = 800;
  float yawDegrees = 35.0f;
  float pitchDegrees = 25.0f;
};

/// Renders `mesh` to a PNG (RGB, 8-bit) at `path`.
void writePreview(const TriangleMesh& mesh, const std::filesystem::path& path,
                  const PreviewOptions& options = {});

}  // namespace cellrelief::app
