#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian 12 packages cellrelief builds against, only those that are missing.
# Idempotent and silent when nothing is missing; needs root (or sudo) only when it installs.
set -euo pipefail

# Required: the core, io and the command line. Optional ones (CELLRELIEF_WITH_<DEP>=AUTO) are
# installed too so that the full project and its verification tests build on a fresh machine.
packages=(
  build-essential cmake ninja-build pkg-config
  libgtest-dev libbenchmark-dev
  libglm-dev libtbb-dev libopenmesh-dev libstb-dev libpng-dev libcli11-dev nlohmann-json3-dev
  libopenvdb-dev libboost-iostreams-dev
  libceres-dev libcgal-dev libeigen3-dev libembree-dev
  libegl-dev libegl1-mesa-dev libgl1-mesa-dri libglfw3-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslc
  xvfb xauth
  libhwy-dev
  clang-14 libfuzzer-14-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "cellrelief setup: installing ${#missing[@]} Debian package(s): ${missing[*]}"
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "cellrelief setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq "${missing[@]}" >/dev/null
echo "cellrelief setup: done"
