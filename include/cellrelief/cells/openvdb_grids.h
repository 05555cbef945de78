// SPDX-License-Identifier: MIT
/// @file openvdb_grids.h
/// OpenVDB's grid headers as the library includes them, and, for the project's own programs, its
/// int32 grid compiled once.
///
/// Grid and Tree are class templates with virtual functions, so a translation unit that names
/// Int32Grid instantiates the grid and its tree whole (every virtual member, the node code and the
/// parallel reductions they run) and compiles them again: measured with GCC 12 at -O2, a file that
/// only includes cell_complex.h took 13.5 s, and 8.9 s with them declared extern. The project's
/// programs and tests define CELLRELIEF_EXTERN_OPENVDB_GRIDS and link the one compiled copy
/// (target cellrelief_openvdb_grids, src/cells/openvdb_grids.cpp, not installed). Users of the
/// headers see no change. The node types stay implicit: OpenVDB's nodes have members that do not
/// compile for int (printing a buffer), so they cannot be instantiated whole.
#pragma once

#include <openvdb/openvdb.h>

/// The grid and the tree of OpenVDB's Int32Grid, declared (EXTERN = extern) or defined (empty).
#define CELLRELIEF_OPENVDB_INT32_GRID_INSTANCES(EXTERN)                 \
  EXTERN template class openvdb::Grid<openvdb::Int32Tree>;            \
  EXTERN template class openvdb::tree::Tree<openvdb::Int32Tree::RootNodeType>;

#ifdef CELLRELIEF_EXTERN_OPENVDB_GRIDS
CELLRELIEF_OPENVDB_INT32_GRID_INSTANCES(extern)
#endif
