# SPDX-License-Identifier: MIT
# Finds what cellrelief builds against. Required dependencies fail the configure with the Debian
# package to install; optional ones follow CELLRELIEF_WITH_<DEP> = AUTO | ON | OFF, where AUTO enables
# what is installed, and an absent optional dependency costs nothing at build time.

set(CELLRELIEF_DEPENDENCY_REPORT "")

macro(cellrelief_note_dependency name state detail)
  list(APPEND CELLRELIEF_DEPENDENCY_REPORT "${name}|${state}|${detail}")
endmacro()

# The version a find module or package config reported, under whichever name it uses.
macro(cellrelief_found_version name out)
  string(TOLOWER "${name}" _lower)
  set(${out} "")
  foreach(_var ${name}_VERSION ${name}_VERSION_STRING ${_lower}_VERSION ${name}_VERSION_MAJOR)
    if(${_var})
      set(${out} "${${_var}}")
      break()
    endif()
  endforeach()
endmacro()

# cellrelief_require(<Name> DEBIAN <package> FIND <find_package arguments...>)
macro(cellrelief_require name)
  cmake_parse_arguments(_req "" "DEBIAN" "FIND" ${ARGN})
  find_package(${_req_FIND} QUIET)
  if(NOT ${name}_FOUND)
    message(FATAL_ERROR "cellrelief needs ${name}: install the Debian package '${_req_DEBIAN}' "
                        "(or run scripts/setup-debian.sh)")
  endif()
  cellrelief_found_version(${name} _version)
  cellrelief_note_dependency(${name} "required" "${_version}")
endmacro()

# cellrelief_optional(<Name> DEBIAN <package> [FOUND_VAR <var>] FIND <find_package arguments...>)
# Sets CELLRELIEF_HAS_<Name> to ON or OFF.
macro(cellrelief_optional name)
  cmake_parse_arguments(_opt "" "DEBIAN;FOUND_VAR" "FIND" ${ARGN})
  set(CELLRELIEF_WITH_${name} AUTO CACHE STRING "Use ${name}: AUTO (when installed), ON (required) or OFF")
  set_property(CACHE CELLRELIEF_WITH_${name} PROPERTY STRINGS AUTO ON OFF)
  if(NOT _opt_FOUND_VAR)
    set(_opt_FOUND_VAR ${name}_FOUND)
  endif()
  set(CELLRELIEF_HAS_${name} OFF)
  if(CELLRELIEF_WITH_${name} STREQUAL "OFF")
    cellrelief_note_dependency(${name} "disabled" "CELLRELIEF_WITH_${name}=OFF")
  else()
    find_package(${_opt_FIND} QUIET)
    if(${_opt_FOUND_VAR})
      set(CELLRELIEF_HAS_${name} ON)
      cellrelief_found_version(${name} _version)
      cellrelief_note_dependency(${name} "enabled" "${_version}")
    elseif(CELLRELIEF_WITH_${name} STREQUAL "ON")
      message(FATAL_ERROR "CELLRELIEF_WITH_${name}=ON but ${name} was not found: install the Debian "
                          "package '${_opt_DEBIAN}' (or run scripts/setup-debian.sh)")
    else()
      cellrelief_note_dependency(${name} "absent" "install Debian package '${_opt_DEBIAN}' to enable")
    endif()
  endif()
endmacro()

# ---- required --------------------------------------------------------------------------------------
cellrelief_require(glm DEBIAN libglm-dev FIND glm CONFIG)
cellrelief_require(TBB DEBIAN libtbb-dev FIND TBB CONFIG)
# CONFIG: CGAL ships a FindOpenMesh module that would shadow OpenMesh's own package configuration.
cellrelief_require(OpenMesh DEBIAN libopenmesh-dev FIND OpenMesh CONFIG)
cellrelief_require(PNG DEBIAN libpng-dev FIND PNG)
cellrelief_require(stb DEBIAN libstb-dev FIND stb)
# The cell complex lives on OpenVDB's sparse grid.
list(APPEND CMAKE_MODULE_PATH /usr/lib/x86_64-linux-gnu/cmake/OpenVDB)
cellrelief_require(OpenVDB DEBIAN "libopenvdb-dev libboost-iostreams-dev" FIND OpenVDB)
if(CELLRELIEF_BUILD_APPS)
  cellrelief_require(CLI11 DEBIAN libcli11-dev FIND CLI11 CONFIG)
endif()

# ---- optional --------------------------------------------------------------------------------------
cellrelief_optional(Ceres DEBIAN libceres-dev FIND Ceres CONFIG)
# Google Highway: the SIMD packet tracer (cellrelief::trace_packets, trace/packet_tracer.h).
cellrelief_optional(hwy DEBIAN libhwy-dev FIND hwy CONFIG)
cellrelief_optional(CGAL DEBIAN libcgal-dev FIND CGAL CONFIG)
cellrelief_optional(Embree DEBIAN libembree-dev FIND embree 3 CONFIG FOUND_VAR embree_FOUND)
cellrelief_optional(OpenGL DEBIAN "libegl-dev libegl1-mesa-dev" FIND OpenGL COMPONENTS OpenGL EGL
                    FOUND_VAR OpenGL_EGL_FOUND)
cellrelief_optional(GLFW DEBIAN libglfw3-dev FIND glfw3 CONFIG FOUND_VAR glfw3_FOUND)
cellrelief_optional(Vulkan DEBIAN "libvulkan-dev glslc" FIND Vulkan COMPONENTS glslc)
if(CELLRELIEF_BUILD_APPS)  # the Python module (apps/python); its tests need python3-numpy and python3-pytest
  # Built for, and tested with, Debian's interpreter, whose python3-numpy, python3-pytest and
  # python3-matplotlib the setup script installs: a pyenv or virtualenv python3 first on PATH would
  # not see them. Set CELLRELIEF_PYTHON_EXECUTABLE for another one.
  if(EXISTS /usr/bin/python3)
    set(_cellrelief_python /usr/bin/python3)
  else()
    find_program(_cellrelief_python python3)
  endif()
  set(CELLRELIEF_PYTHON_EXECUTABLE "${_cellrelief_python}" CACHE FILEPATH "The Python the module is built for")
  set(Python_EXECUTABLE "${CELLRELIEF_PYTHON_EXECUTABLE}")
  set(PYBIND11_FINDPYTHON ON)  # pybind11 through CMake's FindPython, with the interpreter above
  cellrelief_optional(PYTHON DEBIAN "pybind11-dev python3-dev" FIND pybind11 CONFIG FOUND_VAR pybind11_FOUND)
  # matplotlib draws the benchmarks' figures from their CSV at run time (apps/plots); without it
  # they say so and write the CSV alone.
  set(CELLRELIEF_HAS_MATPLOTLIB OFF)
  if(CELLRELIEF_PYTHON_EXECUTABLE)
    execute_process(COMMAND "${CELLRELIEF_PYTHON_EXECUTABLE}" -c "import matplotlib" RESULT_VARIABLE _mpl
                    OUTPUT_QUIET ERROR_QUIET)
    if(_mpl EQUAL 0)
      set(CELLRELIEF_HAS_MATPLOTLIB ON)
    endif()
  endif()
  if(CELLRELIEF_HAS_MATPLOTLIB)
    cellrelief_note_dependency(matplotlib "enabled" "the benchmarks' figures")
  else()
    cellrelief_note_dependency(matplotlib "absent" "install Debian package 'python3-matplotlib' for the figures")
  endif()
endif()

function(cellrelief_report_dependencies)
  message(STATUS "cellrelief dependencies:")
  foreach(entry IN LISTS CELLRELIEF_DEPENDENCY_REPORT)
    string(REPLACE "|" ";" fields "${entry}")
    list(GET fields 0 name)
    list(GET fields 1 state)
    list(GET fields 2 detail)
    string(LENGTH "${name}" len)
    math(EXPR pad "12 - ${len}")
    string(REPEAT " " ${pad} spaces)
    message(STATUS "  ${name}${spaces}${state}  ${detail}")
  endforeach()
endfunction()
