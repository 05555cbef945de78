// SPDX-License-Identifier: MIT
/// @file bench_main.cpp
/// The main of every benchmark executable: CELLRELIEF_BENCH_PROGRAM names the program's namespace.
#include "bench_programs.h"

int main(int argc, char** argv) { return cellrelief::bench::CELLRELIEF_BENCH_PROGRAM::run(argc, argv); }
