#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The test command: the same set-up as scripts/demo.sh, then the whole test suite through CTest.
# Extra arguments go to ctest (e.g. -L unit, -R MeshIO).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
bash scripts/setup-debian.sh
cmake --preset release
cmake --build --preset release -j"$(nproc)"
ctest --preset release -j"$(nproc)" "$@"
