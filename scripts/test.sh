#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The test command: the same set-up as scripts/demo.sh, then the whole test suite through CTest:
#   1. the release build and every test (unit, verify, stress, backend, bench-smoke);
#   2. the fuzz preset (clang-14, libFuzzer, ASan, UBSan): each reader's target for a short fixed
#      number of executions (label fuzz; scripts/fuzz.sh runs them long);
#   3. the debug-asan preset (GCC, Debug, ASan, UBSan): the unit and stress labels again.
# Extra arguments run step 1 only, with the arguments given to ctest (e.g. -L unit, -R MeshIO).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
bash scripts/setup-debian.sh
jobs="$(nproc)"
step() { echo; echo "== cellrelief tests: $* ($(date +%H:%M:%S))"; }

step "release build and every test"
cmake --preset release
cmake --build --preset release -j"$jobs"
ctest --preset release -j"$jobs" "$@"
[[ $# -eq 0 ]] || exit 0

step "fuzz targets, short runs under ASan and UBSan"
cmake --preset fuzz
cmake --build --preset fuzz -j"$jobs"
ctest --preset fuzz -j"$jobs"

step "unit and stress tests under ASan and UBSan (Debug)"
cmake --preset debug-asan
cmake --build --preset debug-asan-unit-stress -j"$jobs"
ctest --preset debug-asan-unit-stress -j"$jobs"
