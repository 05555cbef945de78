#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs ON the device machine after gpu_bench.sh's first run showed OpenGL hanging on relief models
# (cell complexes) while Vulkan renders them: how long does the NVIDIA GL driver take to compile
# and run the traversal shader, and what do the relief models cost on Vulkan at 1920x1080?
set -uo pipefail
OUT=${OUT:-/tmp/out}; W=/tmp/glprobe; D=/tmp/devrt; mkdir -p "$OUT" "$W"
# shellcheck source=device_env.sh
source "$(dirname "${BASH_SOURCE[0]}")/device_env.sh"
device_loaders
device_unpack_runtime "$D" cellrelief || exit 1
device_nvidia_files
cr=$D/bin/cellrelief; m=$D/data/meshes
t() { local s=$SECONDS; echo "=== $*"; timeout -k 5 "${T:-60}" "$@" 2>&1 | grep -E "rendered|device time|error|converted|wrote  "; echo "--- exit ${PIPESTATUS[0]} in $((SECONDS - s)) s"; }
{
$cr convert $m/small/spot__common-3d-test-models.obj --texture $m/small/spot_texture__cinolib.png -o $W/spot.crm --no-error --quiet >/dev/null
$cr convert $m/medium/armadillo__libigl-tutorial-data.obj -o $W/arm.crm --no-error --quiet >/dev/null
for s in spot arm; do
  T=40 t $cr render $W/$s.crm --backend vulkan --size 1920x1080 -o $W/$s.png
  T=40 t $cr render $W/$s.crm --backend cpu --size 1920x1080 -o $W/${s}_cpu.png
done
T=200 t $cr render $W/spot.crm --backend opengl --size 64x64 --no-shadows -o $W/gl_small.png
T=60 t $cr render $W/spot.crm --backend opengl --size 1920x1080 -o $W/gl_spot.png
} 2>&1 | tee $OUT/gl_probe.log
