#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs ON the device machine (one NVIDIA GPU, no network, root), from the repository root: the
# figures that need a real GPU.
#   geotex    bench_geotex --sections figure7: the paper's Fig. 7 (issue 16), geometry textures ray cast
#             by OpenGL and Vulkan against the mesh rasterized by OpenGL, up to 4096 x 3072, on
#             bunny, armadillo, fertility_9k, Igea and the Igea after one Loop step
#   polycube  bench_polycube_render: PolyCube-Maps texturing's frame cost per backend (issue 15)
#   backends  bench_backends without OpenGL (whose relief shader the NVIDIA driver compiles for
#             minutes, docs/backends.md): the relief models on the CPU and Vulkan, each entry
# FIGURES_STEPS chooses (default: all three, in that order). Pack first, here:
#   PROGRAMS="bench_geotex bench_polycube_render bench_backends" \
#     DATA_FILES="$(scripts/device/figures.sh --data-files)" scripts/device/collect_runtime.sh
#   run tool: command "bash scripts/device/figures.sh", carry [".gl", ".devrt"], timeout_s 480
# FIGURES_SIZES overrides Fig. 7's sizes; DEVICE_SKIP_LOADERS=1 and FIGURES_DEVRT make a dry run here.
# Files in $OUT: figures.log, geotex_fig7.csv, geotex_fig7.png, polycube_render.csv, backends.csv,
# gpu_clocks.csv.
set -uo pipefail

if [[ ${1:-} == --data-files ]]; then
  # Licences: ../shared/data/SOURCES.md; a transient copy for the lent machine, never committed.
  echo meshes/medium/stanford-bunny__common-3d-test-models.obj meshes/medium/armadillo__libigl-tutorial-data.obj \
    meshes/small/fertility_9k__libigl-tutorial-data.off meshes/large/igea__common-3d-test-models.ply \
    meshes/small/3holes__cinolib.obj meshes/small/spot__common-3d-test-models.obj \
    meshes/medium/bumpy-cube__libigl-tutorial-data.obj
  exit 0
fi

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
OUT=${OUT:-$ROOT/out/figures}
WORK=${FIGURES_WORK:-/tmp/figures}
DEVRT=${FIGURES_DEVRT:-/tmp/devrt}
STEPS=${FIGURES_STEPS:-geotex polycube backends}
SIZES=${FIGURES_SIZES:-80x60,160x120,320x240,640x480,800x600,1024x768,1600x1200,2048x1536,3200x2400,4096x3072}
START=$SECONDS
mkdir -p "$OUT" "$WORK"
# shellcheck source=device_env.sh
source "$ROOT/scripts/device/device_env.sh"

say() { printf '\n=== [%3ds] %s\n' "$((SECONDS - START))" "$*"; }

main() {
  say "setup"
  grep -E '^PRETTY_NAME=' /etc/os-release 2>/dev/null
  nproc
  timeout 20 nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,clocks.mem --format=csv
  device_sample_clocks "$OUT/gpu_clocks.csv"
  device_loaders
  device_nvidia_files
  device_unpack_runtime "$DEVRT" bench_geotex || return 1
  local threads
  threads=$(nproc)

  local step
  for step in $STEPS; do
    case $step in
      geotex)
        say "geotex: Fig. 7 at $SIZES"
        timeout -k 5 "${FIGURES_GEOTEX_S:-270}" "$DEVRT/bin/bench_geotex" --sections figure7 --figure7-loop \
          --figure7-sizes "$SIZES" --threads "$threads" --data "$DEVRT/data" --out "$WORK/geotex"
        echo "--- geotex: exit $?"
        cp "$WORK/geotex/geotex_fig7.csv" "$WORK/geotex/geotex_fig7.png" "$OUT/" 2>/dev/null ;;
      polycube)
        say "polycube: texturing's frame cost"
        timeout -k 5 "${FIGURES_POLYCUBE_S:-150}" "$DEVRT/bin/bench_polycube_render" --threads "$threads" \
          --data "$DEVRT/data" --out "$WORK/polycube"
        echo "--- polycube: exit $?"
        cp "$WORK/polycube/polycube_render.csv" "$OUT/" 2>/dev/null ;;
      backends)
        say "backends: relief models on the CPU and Vulkan at 1920x1080"
        timeout -k 5 "${FIGURES_BACKENDS_S:-240}" "$DEVRT/bin/bench_backends" --skip opengl --size 1920x1080 \
          --threads "$threads" --data "$DEVRT/data" --out "$WORK/backends"
        echo "--- backends: exit $?"
        cp "$WORK/backends/backends.csv" "$OUT/" 2>/dev/null ;;
      *) echo "figures: unknown step '$step' (geotex, polycube, backends)"; return 2 ;;
    esac
  done

  say "done; files in $OUT:"
  ls -l "$OUT"
}

device_run main "$OUT/figures.log"
