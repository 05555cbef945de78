// SPDX-License-Identifier: MIT
/// @file openvdb_grids.cpp
/// OpenVDB's Int32Grid and its tree, compiled once for the project's programs and tests (see
/// cells/openvdb_grids.h).
#include "cellrelief/cells/openvdb_grids.h"

#ifndef CELLRELIEF_EXTERN_OPENVDB_GRIDS
#error "compiled with CELLRELIEF_EXTERN_OPENVDB_GRIDS, as the target cellrelief_openvdb_grids defines it"
#endif

CELLRELIEF_OPENVDB_INT32_GRID_INSTANCES()
