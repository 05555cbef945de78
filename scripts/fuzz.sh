#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the fuzz preset (clang-14, libFuzzer, ASan, UBSan) and runs every reader's target for
# RUNS executions (default 1e6), one after another, each input limited to 1 s. New inputs go to
# build/fuzz/long/<target>; a crash, leak or timeout leaves its input in build/fuzz/long/artifacts
# and makes the script exit 1 after the other targets have run. Add such an input to
# tests/fuzz/regressions/<target>/ when it is fixed.
#   scripts/fuzz.sh [RUNS] [target ...]      e.g. scripts/fuzz.sh 100000 obj ply_binary
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
runs="${1:-1000000}"
shift || true
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(obj ply_ascii ply_binary off stl_ascii stl_binary png jpeg tga bmp crm polycube polycube_map geotex)
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j"$(nproc)"
# A smaller quarantine: recycling the default 256 MB one stalls single inputs past the 1 s limit.
export ASAN_OPTIONS=detect_leaks=1:quarantine_size_mb=32
export LSAN_OPTIONS="suppressions=$root/tests/lsan_suppressions.txt"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
failed=0
for t in "${targets[@]}"; do
  work="build/fuzz/long/$t"
  artifacts="build/fuzz/long/artifacts/$t/"
  mkdir -p "$work" "$artifacts"
  start=$(date +%s)
  if "build/fuzz/tests/fuzz/fuzz_$t" -runs="$runs" -timeout=1 -rss_limit_mb=2048 -max_len=8192 \
       -print_final_stats=1 -artifact_prefix="$artifacts" "$work" "tests/fuzz/corpus/$t" \
       > "build/fuzz/long/$t.log" 2>&1; then
    echo "fuzz $t: $(grep -m1 'stat::number_of_executed_units' "build/fuzz/long/$t.log" | awk '{print $2}') executions, no failure, $(( $(date +%s) - start )) s"
  else
    echo "fuzz $t: FAILED after $(( $(date +%s) - start )) s: $(grep -m1 -E 'ERROR|SUMMARY' "build/fuzz/long/$t.log")"
    failed=1
  fi
done
exit $failed
