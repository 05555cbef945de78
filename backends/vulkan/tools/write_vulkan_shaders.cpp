// SPDX-License-Identifier: MIT
// Build step of the Vulkan backend: writes the GLSL that glslc compiles into its SPIR-V, the
// shared traversal body with the preamble the OpenGL backend prepends at run time (the constants
// from the C++ values, gpu::traversalConstants), and the variant switches as specialization
// constants; and the cover of the rasterized entry with the same constants.
// Usage: cellrelief_write_vulkan_shaders <output folder>.
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>

#include "cellrelief/gpu/shader_preamble.h"

namespace {

bool writeIfChanged(const std::string& path, const std::string& text) {
  {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (old == text) return true;  // unchanged: glslc does not run again
    }
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  return bool(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output folder>\n", argv[0]);
    return 2;
  }
  const std::string folder = argv[1];
  const std::pair<std::string, std::string> shaders[] = {
      {"/relief_trace.comp", cellrelief::gpu::reliefTraceShaderForVulkan(false)},
      {"/relief_trace.frag", cellrelief::gpu::reliefTraceShaderForVulkan(true)},
      {"/cell_cover.vert", cellrelief::gpu::cellCoverShader(true)}};
  for (const auto& [name, text] : shaders) {
    const std::string path = folder + name;
    if (!writeIfChanged(path, text)) {
      std::fprintf(stderr, "cellrelief_write_vulkan_shaders: cannot write %s\n", path.c_str());
      return 1;
    }
  }
  return 0;
}
