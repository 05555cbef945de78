# SPDX-License-Identifier: MIT
# Writes the GLSL sources of SHADER_DIR into OUTPUT as C++ string constants (cmake -P script), so
# the header-only GPU backends carry their shaders and need no files at run time.
file(READ "${SHADER_DIR}/relief_trace.comp" _trace)
string(FIND "${_trace}" ")glsl\"" _clash)
if(NOT _clash EQUAL -1)
  message(FATAL_ERROR "relief_trace.comp contains the raw-string delimiter )glsl\"")
endif()
file(WRITE "${OUTPUT}.tmp"
"// Generated from backends/shaders by cmake/EmbedShaders.cmake: do not edit.\n"
"#pragma once\n#include <string_view>\n"
"namespace cellrelief::gpu {\n"
"inline constexpr std::string_view kReliefTraceComp = R\"glsl(${_trace})glsl\";\n"
"}  // namespace cellrelief::gpu\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
