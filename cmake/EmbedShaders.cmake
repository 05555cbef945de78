# SPDX-License-Identifier: MIT
# Writes the GLSL sources of SHADER_DIR into OUTPUT as C++ string constants (cmake -P script), so
# the header-only GPU backends carry their shaders and need no files at run time.
set(_body "")
foreach(_pair "relief_trace.comp|kReliefTraceComp" "cell_cover.vert|kCellCoverVert" "full_screen.vert|kFullScreenVert")
  string(REPLACE "|" ";" _pair "${_pair}")
  list(GET _pair 0 _file)
  list(GET _pair 1 _name)
  file(READ "${SHADER_DIR}/${_file}" _text)
  string(FIND "${_text}" ")glsl\"" _clash)
  if(NOT _clash EQUAL -1)
    message(FATAL_ERROR "${_file} contains the raw-string delimiter )glsl\"")
  endif()
  string(APPEND _body "inline constexpr std::string_view ${_name} = R\"glsl(${_text})glsl\";\n")
endforeach()
file(WRITE "${OUTPUT}.tmp"
"// Generated from backends/shaders by cmake/EmbedShaders.cmake: do not edit.\n"
"#pragma once\n#include <string_view>\n"
"namespace cellrelief::gpu {\n"
"${_body}"
"}  // namespace cellrelief::gpu\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUTPUT}.tmp")
