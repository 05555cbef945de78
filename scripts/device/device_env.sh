#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Sourced ON the device machine by the scripts beside it: puts the GL/Vulkan loaders from .gl/ in
# place and unpacks .devrt/runtime.tar.xz (scripts/device/collect_runtime.sh) so its programs load.
#
#   source scripts/device/device_env.sh
#   device_loaders                      # the .gl debs into /, then ldconfig
#   device_unpack_runtime DIR PROGRAM   # unpack into DIR, set LD_LIBRARY_PATH, check PROGRAM loads
#   device_nvidia_files                 # the NVIDIA driver's own Vulkan ICD and EGL vendor files

# The GL and Vulkan loaders (device tool README). DEVICE_SKIP_LOADERS=1: a dry run elsewhere.
device_loaders() {
  [[ -n ${DEVICE_SKIP_LOADERS:-} ]] && return 0
  local f
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
}

# lib/ always; of lib-sys/ (libstdc++, libgcc_s, zlib...) only what the image lacks, so the image's
# newer copies serve us and the NVIDIA driver alike; all of lib-sys/ if PROGRAM does not load so.
device_unpack_runtime() {
  local dir=$1 program=$2 f so
  rm -rf "$dir" && mkdir -p "$dir"
  if command -v xz >/dev/null; then
    tar -C "$dir" -xJf .devrt/runtime.tar.xz
  else  # no xz-utils on the image: Python's lzma
    python3 -c 'import sys, tarfile
t = tarfile.open(sys.argv[1])
t.extractall(sys.argv[2], **({"filter": "tar"} if hasattr(tarfile, "tar_filter") else {}))' .devrt/runtime.tar.xz "$dir"
  fi || { echo "device_env: cannot unpack .devrt/runtime.tar.xz"; return 1; }
  head -5 "$dir/MANIFEST.txt"
  mkdir -p "$dir/lib-missing"
  for f in "$dir"/lib-sys/*; do
    so=${f##*/}
    if ! ldconfig -p | awk -v s="$so" '$1 == s && /x86-64/ {found = 1} END {exit !found}'; then
      ln -sf "$f" "$dir/lib-missing/$so"
      echo "not on the image, taken from the bundle: $so"
    fi
  done
  local base=${LD_LIBRARY_PATH:-}
  export LD_LIBRARY_PATH=$dir/lib:$dir/lib-missing${base:+:$base}
  if ! "$dir/bin/$program" --help >/dev/null; then
    echo "device_env: $program does not load with the image's libstdc++ and friends; taking all of lib-sys/"
    export LD_LIBRARY_PATH=$dir/lib:$dir/lib-sys${base:+:$base}
    "$dir/bin/$program" --help >/dev/null || { ldd "$dir/bin/$program" | grep -v '=> /'; return 1; }
  fi
  echo "LD_LIBRARY_PATH=$LD_LIBRARY_PATH"
}

# Where the loaders find no NVIDIA driver by themselves (device tool README).
device_nvidia_files() {
  local icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  local vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  [[ -f $icd ]] && export VK_DRIVER_FILES=$icd VK_ICD_FILENAMES=$icd
  [[ -f $vendor ]] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
  echo "VK_DRIVER_FILES=${VK_DRIVER_FILES:-} __EGL_VENDOR_LIBRARY_FILENAMES=${__EGL_VENDOR_LIBRARY_FILENAMES:-}"
}

# Samples the GPU's clocks every half second into FILE (CSV) while the script runs; device_run
# stops it. FIELDS: nvidia-smi's --query-gpu list.
device_sample_clocks() {
  local file=$1 fields=${2:-timestamp,clocks.sm,clocks.mem,utilization.gpu,power.draw}
  command -v nvidia-smi >/dev/null || return 0
  nvidia-smi --query-gpu="$fields" --format=csv -lms 500 >"$file" 2>&1 </dev/null &
  echo $! >"$DEVICE_SAMPLER_PID"
}

# Runs the function MAIN with its output also in LOG, then stops the clock sampler it started (its
# own process id only); returns MAIN's status.
DEVICE_SAMPLER_PID=${TMPDIR:-/tmp}/device_sampler.$$.pid
device_run() {
  local main=$1 log=$2 rc
  rm -f "$DEVICE_SAMPLER_PID"
  "$main" 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  [[ -s $DEVICE_SAMPLER_PID ]] && kill "$(cat "$DEVICE_SAMPLER_PID")" 2>/dev/null
  rm -f "$DEVICE_SAMPLER_PID"
  return "$rc"
}
