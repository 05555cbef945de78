#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main command: install missing Debian packages, build in Release, and run the embedded default
# job (`cellrelief demo`) on the built-in model, or on the mesh given as argument.
#   scripts/demo.sh                 built-in model, results in out/demo
#   scripts/demo.sh my_mesh.obj     your mesh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
input=()
if [[ $# -gt 0 ]]; then
  input=("$(realpath -m "$1")")
  shift
fi
cd "$root"
bash scripts/setup-debian.sh
mkdir -p build
log=build/demo-build.log
echo "cellrelief: configuring and building in Release (log: $log)"
if ! { cmake --preset release && cmake --build --preset release -j"$(nproc)"; } >"$log" 2>&1; then
  tail -n 60 "$log"
  echo "cellrelief: the build failed; the whole log is in $log" >&2
  exit 1
fi
grep -E "^--   " "$log" | head -20 || true
exec build/release/bin/cellrelief demo "${input[@]}" "$@"
