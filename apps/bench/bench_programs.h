// SPDX-License-Identifier: MIT
/// @file bench_programs.h
/// The benchmark programs, each a function in its own namespace: cellrelief_bench_programs
/// compiles them together (apps/bench/CMakeLists.txt says why) and each executable's main calls
/// one (bench_main.cpp).
#pragma once

namespace cellrelief::bench {
namespace backends_program { int run(int argc, char** argv); }
namespace cells_program { int run(int argc, char** argv); }
namespace geotex_program { int run(int argc, char** argv); }
namespace indirection_program { int run(int argc, char** argv); }
namespace polycube_program { int run(int argc, char** argv); }
namespace polycube_render_program { int run(int argc, char** argv); }
namespace relief_program { int run(int argc, char** argv); }
namespace silhouettes_program { int run(int argc, char** argv); }
namespace trace_program { int run(int argc, char** argv); }
}  // namespace cellrelief::bench
