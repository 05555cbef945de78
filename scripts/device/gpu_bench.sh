#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Runs ON the device machine (one NVIDIA GPU, no network, root), from the repository root, after
# scripts/device/collect_runtime.sh filled .devrt/ here and the GL/Vulkan loader debs sit in .gl/:
#
#   run tool: command "bash scripts/device/gpu_bench.sh", carry [".gl", ".devrt"], timeout_s 360
#
# It unpacks the loaders and .devrt/runtime.tar.xz, then benchmarks the OpenGL (EGL) and Vulkan
# backends against the CPU reference at 1920x1080:
#   probe        compare-backends on spot at 256x256: do both GPU backends come up on the NVIDIA
#                driver? If not, it sets the driver's own ICD/vendor files (README of the device
#                tool) and tries again.
#   rocks        a height map with its Gauss-Newton indirection map (parallax occlusion mapping),
#                compare-backends from above and at a grazing angle
#   geotex       the armadillo as geometry textures, compare-backends
#   torus        the demo's generated model (`cellrelief demo`: no input file), compare-backends
#   spot         spot with its texture, compare-backends
#   bench        bench_backends (Igea, armadillo, 1M Igea; every variant and entry; Embree; CSV)
#   armadillo, igea   compare-backends
# Every step has a timeout, and the whole script stops starting steps at GPU_BENCH_BUDGET_S
# (default 300 s), so it ends within 5.5 minutes. At most 8 files land in $OUT:
#   gpu_bench.log, compare_backends.csv, backends.csv, backends.png, gpu_clocks.csv,
#   rocks_side_by_side.png, torus_side_by_side.png, spot_side_by_side.png
set -uo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
OUT=${OUT:-$ROOT/out/gpu_bench}
WORK=${GPU_BENCH_WORK:-/tmp/gpu_bench}
DEVRT=${GPU_BENCH_DEVRT:-/tmp/devrt}
BUDGET=${GPU_BENCH_BUDGET_S:-300}
SIZE=${GPU_BENCH_SIZE:-1920x1080}
EXPECT=${GPU_BENCH_EXPECT:-NVIDIA}  # what the GPU backends' device names must contain
START=$SECONDS
mkdir -p "$OUT" "$WORK/logs"
# shellcheck source=device_env.sh
source "$ROOT/scripts/device/device_env.sh"

say() { printf '\n=== [%3ds] %s\n' "$((SECONDS - START))" "$*"; }

# step NAME MAX_SECONDS COMMAND...: runs it under timeout (capped by what is left of the budget),
# its output also in $WORK/logs/NAME.txt; returns its status (124: timed out, 125: skipped).
step() {
  local name=$1 max=$2 left
  shift 2
  left=$((BUDGET - (SECONDS - START)))
  if ((left < 8)); then
    say "$name: skipped, the budget of ${BUDGET}s is spent"
    return 125
  fi
  ((max > left)) && max=$left
  say "$name (timeout ${max}s): $*"
  local t0=$SECONDS
  timeout -k 5 "$max" "$@" 2>&1 | tee "$WORK/logs/$name.txt"
  local rc=${PIPESTATUS[0]}
  echo "--- $name: exit $rc in $((SECONDS - t0))s"
  return "$rc"
}

main() {
  say "setup"
  uname -a
  grep -E '^(PRETTY_NAME|VERSION_ID)=' /etc/os-release 2>/dev/null
  ldd --version 2>&1 | head -1
  nproc
  # GPU_BENCH_SKIP_LOADERS=1: a dry run elsewhere.
  DEVICE_SKIP_LOADERS=${GPU_BENCH_SKIP_LOADERS:-} device_loaders
  ldconfig -p | grep -E 'libvulkan\.so|libEGL\.so|libOpenGL\.so|libEGL_nvidia|libGLX_nvidia|libnvidia-glcore|libnvidia-eglcore' | sort

  say "nvidia-smi"
  timeout 20 nvidia-smi -L
  timeout 20 nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm,clocks.mem,power.limit --format=csv
  device_sample_clocks "$OUT/gpu_clocks.csv" timestamp,clocks.sm,clocks.mem,utilization.gpu,memory.used,power.draw,temperature.gpu
  echo "ICD and vendor files:"
  ls -l /usr/share/vulkan/icd.d /etc/vulkan/icd.d /usr/share/glvnd/egl_vendor.d /etc/glvnd/egl_vendor.d \
    /usr/local/nvidia/share/vulkan/icd.d /usr/local/nvidia/share/glvnd/egl_vendor.d 2>&1

  say "runtime"
  device_unpack_runtime "$DEVRT" cellrelief || return 1
  "$DEVRT/bin/cellrelief" --version
  ldd "$DEVRT/bin/cellrelief" | grep -E 'not found|libstdc|libEGL|libOpenGL|libGLdispatch'
  ldd "$DEVRT/bin/bench_backends" | grep 'not found'

  local cr=$DEVRT/bin/cellrelief data=$DEVRT/data/meshes w=$WORK
  step convert_spot 60 "$cr" convert "$data/small/spot__common-3d-test-models.obj" \
    --texture "$data/small/spot_texture__cinolib.png" -o "$w/spot.crm" --no-error --quiet
  step probe 60 "$cr" compare-backends "$w/spot.crm" --size 256x256 --repeat 1 -o "$w/probe"
  # A backend missing or not on the NVIDIA GPU: the driver's own files (device tool README).
  local retry= icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  local vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  if ! grep -q "^vulkan .*$EXPECT" "$WORK/logs/probe.txt"; then
    echo "Vulkan is not on the NVIDIA GPU: VK_DRIVER_FILES=$icd"
    export VK_DRIVER_FILES=$icd VK_ICD_FILENAMES=$icd
    retry=1
  fi
  if ! grep -q "^opengl .*$EXPECT" "$WORK/logs/probe.txt"; then
    echo "OpenGL is not on the NVIDIA GPU: __EGL_VENDOR_LIBRARY_FILENAMES=$vendor"
    export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
    retry=1
  fi
  local last=probe
  if [[ -n $retry ]]; then
    step probe_nvidia_files 60 "$cr" compare-backends "$w/spot.crm" --size 256x256 --repeat 1 -o "$w/probe2"
    last=probe_nvidia_files
  fi
  # compare-backends and bench_backends run every backend in one process: if that died, each GPU
  # backend alone (render; Vulkan prints its device clock), so one driver cannot hide the other.
  if ! grep -q '^wrote .*side_by_side' "$WORK/logs/$last.txt"; then
    step render_opengl 30 "$cr" render "$w/spot.crm" --backend opengl --size "$SIZE" -o "$w/render_opengl.png"
    step render_vulkan 30 "$cr" render "$w/spot.crm" --backend vulkan --size "$SIZE" -o "$w/render_vulkan.png"
  fi

  # Parallax occlusion mapping with an indirection map (issue 17): the DirectX SDK rocks, tiling,
  # the map from Gauss-Newton on this machine's cores; from above and at a grazing angle.
  local hm=$DEVRT/data/heightmaps/pom_dxsdk
  if step indirect_rocks 60 "$cr" indirect "$hm/rocks_NM_height.tga" --wrap repeat -o "$w/rocks_I.png"; then
    step compare_rocks 45 "$cr" compare-backends "$hm/rocks_NM_height.tga" --indirection "$w/rocks_I.png" \
      --texture "$hm/rocks.jpg" --wrap repeat --size "$SIZE" --repeat 5 -o "$w/cmp_rocks" &&
      cp "$w/cmp_rocks/side_by_side.png" "$OUT/rocks_side_by_side.png"
    step compare_rocks_grazing 45 "$cr" compare-backends "$hm/rocks_NM_height.tga" --indirection "$w/rocks_I.png" \
      --texture "$hm/rocks.jpg" --wrap repeat --size "$SIZE" --repeat 5 --camera 0.5,-0.9,0.25,0.5,0.6,0,40 -o "$w/cmp_rocks_grazing"
  fi
  # Geometry textures (issue 16): the armadillo as VSA charts.
  step geotex_armadillo 60 "$cr" geotex "$data/medium/armadillo__libigl-tutorial-data.obj" -o "$w/armadillo.cgt" &&
    step compare_geotex_armadillo 45 "$cr" compare-backends "$w/armadillo.cgt" --size "$SIZE" --repeat 5 -o "$w/cmp_geotex"

  # The generated scene: the demo's displaced torus (327,680 triangles, no input file).
  if step demo 90 "$cr" demo -o "$w/demo"; then
    step compare_torus 45 "$cr" compare-backends "$w/demo/displaced_torus.crm" --size "$SIZE" --repeat 5 -o "$w/cmp_torus" &&
      cp "$w/cmp_torus/side_by_side.png" "$OUT/torus_side_by_side.png"
  fi
  step compare_spot 45 "$cr" compare-backends "$w/spot.crm" --size "$SIZE" --repeat 5 -o "$w/cmp_spot" &&
    cp "$w/cmp_spot/side_by_side.png" "$OUT/spot_side_by_side.png"

  # bench_backends: Igea, armadillo and Igea after one Loop step at default settings; cpu, opengl
  # and vulkan (scene variant, general shader, compute pass) and Embree; device clock for Vulkan.
  step bench_backends 150 "$DEVRT/bin/bench_backends" --data "$DEVRT/data" --out "$w/bench" --size "$SIZE"
  cp "$w/bench/backends.csv" "$w/bench/backends.png" "$OUT/" 2>/dev/null

  step convert_armadillo 40 "$cr" convert "$data/medium/armadillo__libigl-tutorial-data.obj" -o "$w/armadillo.crm" --no-error --quiet &&
    step compare_armadillo 45 "$cr" compare-backends "$w/armadillo.crm" --size "$SIZE" --repeat 5 -o "$w/cmp_armadillo"
  step convert_igea 40 "$cr" convert "$data/large/igea__common-3d-test-models.ply" -o "$w/igea.crm" --no-error --quiet &&
    step compare_igea 45 "$cr" compare-backends "$w/igea.crm" --size "$SIZE" --repeat 5 -o "$w/cmp_igea"

  say "compare-backends table -> compare_backends.csv"
  python3 - "$WORK/logs" "$OUT/compare_backends.csv" "$SIZE" <<'EOF' || echo "gpu_bench: no CSV"
import csv, pathlib, re, sys
logs, out, size = pathlib.Path(sys.argv[1]), sys.argv[2], sys.argv[3]
row_re = re.compile(r"^(cpu|opengl|vulkan)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)x\s+([\d.]+ \S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)°\s+(\S+)\s+(.*)$")
clock_re = re.compile(r"^\s+device clock ([\d.]+) s \(([\d.]+) Mrays/s\)")
rows = []
for path in sorted(logs.glob("compare_*.txt")):
    for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
        if m := row_re.match(line):
            rows.append([path.stem[len("compare_"):], size, *m.groups()[:10], "", "", m.group(11)])
        elif (m := clock_re.match(line)) and rows:
            rows[-1][12:14] = [m.group(1), m.group(2)]
with open(out, "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "size", "backend", "time_s", "mrays_per_s", "vs_cpu", "scene_bytes", "mask_disagreement",
                "depth_median_samples", "depth_p95_samples", "normal_p95_deg", "color_mean", "device_clock_s",
                "device_mrays_per_s", "device"])
    w.writerows(rows)
for r in rows:
    print(",".join(r[:6] + r[12:14]))
EOF
  say "done in $((SECONDS - START))s; files in $OUT:"
  ls -l "$OUT"
}

device_run main "$OUT/gpu_bench.log"
