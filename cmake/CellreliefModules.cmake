# SPDX-License-Identifier: MIT
# One module = one folder under include/cellrelief = one namespace = one target cellrelief::<name>.

set(CELLRELIEF_MODULE_TARGETS "")
set(CELLRELIEF_EXPORTED_TARGETS "")

# cellrelief_add_module(<name> DEPENDS <targets...>): a header-only module target.
function(cellrelief_add_module name)
  cmake_parse_arguments(ARG "" "" "DEPENDS" ${ARGN})
  set(target cellrelief_${name})
  add_library(${target} INTERFACE)
  add_library(cellrelief::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(${target} INTERFACE
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>)
  target_compile_features(${target} INTERFACE cxx_std_20)
  target_link_libraries(${target} INTERFACE ${ARG_DEPENDS})
  set(CELLRELIEF_MODULE_TARGETS ${CELLRELIEF_MODULE_TARGETS} ${target} PARENT_SCOPE)
  set(CELLRELIEF_EXPORTED_TARGETS ${CELLRELIEF_EXPORTED_TARGETS} ${target} PARENT_SCOPE)
endfunction()

# Warnings for the project's own programs and tests (not forced on users of the headers).
function(cellrelief_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wno-dangling-else)
endfunction()

# cellrelief_add_backend(<name> DEPENDS <targets...> [INSTALL]): a header-only backend target
# cellrelief::<name> with its headers in <this folder>/include. INSTALL installs the headers and
# adds the target to the exported package (the caller passes CELLRELIEF_EXPORTED_TARGETS up);
# verification backends (Embree, CGAL) are build-tree only.
include(GNUInstallDirs)
function(cellrelief_add_backend name)
  cmake_parse_arguments(ARG "INSTALL" "" "DEPENDS" ${ARGN})
  set(target cellrelief_${name})
  add_library(${target} INTERFACE)
  add_library(cellrelief::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(${target} INTERFACE
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>)
  target_link_libraries(${target} INTERFACE ${ARG_DEPENDS})
  if(ARG_INSTALL)
    install(DIRECTORY include/ DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
    set(CELLRELIEF_EXPORTED_TARGETS ${CELLRELIEF_EXPORTED_TARGETS} ${target} PARENT_SCOPE)
  endif()
endfunction()
