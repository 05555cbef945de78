#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Packs the built programs for the device machine (one NVIDIA GPU, another Linux image, no
# network): cellrelief and bench_backends from build/release/bin, the shared libraries `ldd` says
# they need, and a few test meshes, into .devrt/runtime.tar.xz (ignored through .git/info/exclude;
# never commit it). scripts/device/gpu_bench.sh unpacks it there.
#
#   scripts/device/collect_runtime.sh        # then: run tool, carry [".gl", ".devrt"]
#
# Left out: the C library (ld-linux, libc, libm, libpthread, libdl, librt, ...), which the device
# image has, and the GL/EGL/Vulkan loaders (libGL, libEGL, libGLX, libGLdispatch, libOpenGL,
# libGLES, libvulkan), which come from the .gl debs and the NVIDIA driver there.
#
# lib/      the project's dependencies, always first on LD_LIBRARY_PATH there.
# lib-sys/  libraries nearly every image has in a newer version (libstdc++, libgcc_s, libgomp,
#           zlib, xz, zstd, bzip2): gpu_bench.sh takes the device's own where it has them, since
#           the copies from here need GLIBC_2.36 and an older libstdc++ would also be forced on the
#           NVIDIA driver's libraries; it falls back to these if the programs do not load.
#
# The GLSL and SPIR-V are embedded in the programs (backends/gpu: shader_sources.h; backends/vulkan:
# spirv_modules.h), so no shader files travel. CELLRELIEF_SHADER_OVERRIDE is the only run-time read.
#
# Why xz: libopenvdb.so (57 MB) and libembree3.so (44 MB) are already stripped; the working tree
# that travels must stay under 64 MiB, and they compress to about 5 and 9 MB.
#
# Environment: BIN_DIR (build/release/bin), PROGRAMS ("cellrelief bench_backends"),
# DATA_DIR (../shared/data), DATA_FILES (paths under DATA_DIR; "" for none), XZ_LEVEL (9).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BIN_DIR=${BIN_DIR:-$ROOT/build/release/bin}
PROGRAMS=${PROGRAMS:-cellrelief bench_backends}
DATA_DIR=${DATA_DIR:-$ROOT/../shared/data}
# Licences (../shared/data/SOURCES.md): spot and its texture: public domain (Keenan Crane);
# armadillo: Stanford 3D Scanning Repository (via libigl-tutorial-data); Igea: Cyberware (via
# common-3d-test-models), no terms stated. A transient copy for a benchmark on the lent machine,
# never committed. bench_backends reads the armadillo and Igea at these exact paths.
# The DirectX SDK rocks height+normal map and its colour map: MIT.
DATA_FILES=${DATA_FILES-meshes/small/spot__common-3d-test-models.obj meshes/small/spot_texture__cinolib.png meshes/medium/armadillo__libigl-tutorial-data.obj meshes/large/igea__common-3d-test-models.ply heightmaps/pom_dxsdk/rocks_NM_height.tga heightmaps/pom_dxsdk/rocks.jpg}
XZ_LEVEL=${XZ_LEVEL:-9}
DEST=$ROOT/.devrt

for pattern in /.gl/ /.devrt/; do
  exclude=$(git -C "$ROOT" rev-parse --git-path info/exclude)
  case $exclude in /*) ;; *) exclude=$ROOT/$exclude ;; esac
  mkdir -p "$(dirname "$exclude")"
  grep -qxF "$pattern" "$exclude" 2>/dev/null || echo "$pattern" >>"$exclude"
done

stage=$(mktemp -d "${TMPDIR:-/tmp}/devrt.XXXXXX")
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib" "$stage/lib-sys" "$stage/data"

# Sonames left to the device image: glibc's libraries and the GL/Vulkan loaders.
skip_re='^(linux-vdso\.so|ld-linux|libc\.so|libm\.so|libmvec\.so|libpthread\.so|libdl\.so|librt\.so|libresolv\.so|libutil\.so|libanl\.so|libnsl\.so|libGL\.so|libEGL\.so|libGLX\.so|libGLdispatch\.so|libOpenGL\.so|libGLES|libGLESv[12]_CM\.so|libvulkan\.so)'
# Sonames the device image most likely has in a newer version (see lib-sys above).
sys_re='^(libstdc\+\+\.so|libgcc_s\.so|libgomp\.so|libz\.so|liblzma\.so|libzstd\.so|libbz2\.so)'

declare -A seen=()
copy_lib() {  # soname path
  local soname=$1 path=$2 dir=lib
  [[ -n ${seen[$soname]:-} ]] && return 0
  seen[$soname]=1
  [[ $soname =~ $sys_re ]] && dir=lib-sys
  cp -L "$path" "$stage/$dir/$soname"
  chmod u+w "$stage/$dir/$soname"
  strip --strip-unneeded "$stage/$dir/$soname" 2>/dev/null || true
}

for program in $PROGRAMS; do
  src=$BIN_DIR/$program
  [[ -x $src ]] || { echo "collect_runtime: no $src (build first)" >&2; exit 1; }
  cp -L "$src" "$stage/bin/$program"
  # `ldd` lists the whole closure; "not found" is fatal (the device would miss it too).
  if ldd "$src" | grep -q "not found"; then
    ldd "$src" | grep "not found" >&2
    echo "collect_runtime: $program has unresolved libraries here" >&2
    exit 1
  fi
  while read -r soname path; do
    [[ $soname =~ $skip_re ]] && continue
    copy_lib "$soname" "$path"
  done < <(ldd "$src" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}')
done

# TBB opens its scalable allocator with dlopen (ldd does not list it); without it TBB uses malloc.
if [[ -n ${seen[libtbb.so.12]:-} ]]; then
  tbbmalloc=$(ldconfig -p | awk '$1 == "libtbbmalloc.so.2" && /x86-64/ {print $NF; exit}')
  if [[ -n $tbbmalloc ]]; then copy_lib libtbbmalloc.so.2 "$tbbmalloc"; fi
fi

for file in $DATA_FILES; do
  [[ -f $DATA_DIR/$file ]] || { echo "collect_runtime: no $DATA_DIR/$file" >&2; exit 1; }
  mkdir -p "$stage/data/$(dirname "$file")"
  cp -L "$DATA_DIR/$file" "$stage/data/$file"
done

{
  echo "# cellrelief device runtime, collected $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(uname -m)"
  echo "# git: $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null)$(git -C "$ROOT" diff --quiet 2>/dev/null || echo ' (dirty)')"
  echo "# local glibc: $(ldd --version | head -1)"
  for program in $PROGRAMS; do
    echo "# $program: built $(date -u -r "$BIN_DIR/$program" +%Y-%m-%dT%H:%M:%SZ), $("$BIN_DIR/$program" --version 2>/dev/null || true)"
  done
  echo "# highest symbol versions needed (objdump -T):"
  for f in "$stage"/bin/* "$stage"/lib/* "$stage"/lib-sys/*; do
    glibc=$(objdump -T "$f" | grep -o 'GLIBC_[0-9.]*' | sort -uV | tail -1 || true)
    glibcxx=$(objdump -T "$f" | grep -o 'GLIBCXX_[0-9.]*' | sort -uV | tail -1 || true)
    printf '%-40s %-12s %s\n' "${f#"$stage"/}" "$glibc" "$glibcxx"
  done
  echo "# files:"
  (cd "$stage" && find . -type f -printf '%10s %P\n' | sort -k2)
} >"$stage/MANIFEST.txt"

mkdir -p "$DEST"
rm -f "$DEST/runtime.tar.xz" "$DEST/MANIFEST.txt"
# One thread at low priority: this machine may be building.
tar -C "$stage" -cf - MANIFEST.txt bin lib lib-sys data | nice -n 19 xz -T1 "-$XZ_LEVEL" >"$DEST/runtime.tar.xz"
cp "$stage/MANIFEST.txt" "$DEST/MANIFEST.txt"

unpacked=$(du -sb "$stage" | cut -f1)
packed=$(stat -c %s "$DEST/runtime.tar.xz")
gl=$(du -sb "$ROOT/.gl" 2>/dev/null | cut -f1 || echo 0)
devrt=$(du -sb "$DEST" | cut -f1)
tree=$(cd "$ROOT" && git ls-files -z --cached --others --exclude-standard | xargs -0 -r stat -c %s -- 2>/dev/null |
  awk '{s += $1} END {print s + 0}')
mib() { awk -v b="$1" 'BEGIN {printf "%.2f MiB", b / 1048576}'; }
echo "collect_runtime: $(grep -c '' <(cd "$stage" && find bin lib lib-sys -type f)) programs and libraries, $(find "$stage/data" -type f | wc -l) data files"
echo "  unpacked:                    $(mib "$unpacked")"
echo "  .devrt/runtime.tar.xz:        $(mib "$packed")"
echo "  .devrt (carried):            $(mib "$devrt")"
echo "  .gl (carried):               $(mib "${gl:-0}")"
echo "  working tree (git would send): $(mib "$tree")"
total=$((devrt + ${gl:-0} + tree))
echo "  all that travels:            $(mib "$total") (limit 64 MiB)"
if ((devrt + ${gl:-0} > 50 * 1048576)); then
  echo "collect_runtime: .devrt and .gl together are over 50 MiB" >&2
  exit 1
fi
