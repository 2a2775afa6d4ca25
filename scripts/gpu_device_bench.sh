#!/usr/bin/env bash
# The GPU benchmark for a lent NVIDIA device (the workplace's `device` tool), in two halves,
# because the device machine is bare: no ParaView, TBB, CHOLMOD or TetGen packages, no network.
#
#   scripts/gpu_device_bench.sh prepare [BUILD]
#       Here: builds bench_gpu_mass_spring (Release, in BUILD, default build/) and packs it with
#       the shared libraries it loads (glvnd's EGL/OpenGL excepted) into .gpubench/bench.tar.xz,
#       and glvnd's packages into .gl/ (apt-get download), both ignored by git.
#   scripts/gpu_device_bench.sh run
#       There, with `carry: [".gpubench", ".gl"]`: unpacks, checks that the GPU context is the
#       NVIDIA one, runs the smoke parity check (GPU against CPU on the landing boxes), then ms
#       per step, GPU against CPU in the same run, for the Spring Network, Stable Neo-Hookean and
#       Corotated on the ~150k-tet TetGen ellipsoid and a ~1M-tet one. CSVs and the logs go to $OUT (or
#       ./gpubench-out), each written as it runs, so a run cut short keeps what it measured. Its
#       run time on a device is not measured yet (none was lent when this was written): here,
#       the smoke part takes about a minute on llvmpipe; the 1M-tet mesh (TetGen) and its CPU
#       set-up are the long part.
#
# A device run, once prepared:
#   run(command="scripts/gpu_device_bench.sh run", carry=[".gpubench", ".gl"], timeout_s=540)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

prepare() {
  local build="${1:-build}"
  cmake --build "$build" --target bench_gpu_mass_spring -j "${SOFTBODY_JOBS:-2}"
  local bench="$build/bin/bench_gpu_mass_spring"
  local stage
  stage="$(mktemp -d)"
  mkdir -p "$stage/bin" "$stage/lib"
  cp "$bench" "$stage/bin/"
  # Every library the program loads but the C library and glvnd's GL libraries, which must be
  # the device's own (the NVIDIA driver plugs into them).
  ldd "$bench" | awk '$3 ~ /^\// {print $3}' |
    grep -v -E '/(libc|libm|libdl|libpthread|librt|ld-linux[^/]*|libEGL|libOpenGL|libGLdispatch|libGLX|libGL)\.so' |
    while read -r lib; do cp -L "$lib" "$stage/lib/"; done
  mkdir -p .gpubench
  tar -C "$stage" -cJf .gpubench/bench.tar.xz bin lib
  rm -rf "$stage"
  grep -qx '/.gpubench/' .git/info/exclude 2>/dev/null || echo /.gpubench/ >>.git/info/exclude
  grep -qx '/.gl/' .git/info/exclude 2>/dev/null || echo /.gl/ >>.git/info/exclude
  if ! ls .gl/*.deb >/dev/null 2>&1; then
    mkdir -p .gl /tmp/amd64/partial
    local o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
    # shellcheck disable=SC2086
    apt-get $o update >/dev/null
    # shellcheck disable=SC2086
    (cd .gl && apt-get $o download libegl1 libglvnd0 libopengl0 libgl1 libglx0)
  fi
  du -sh .gpubench .gl
  echo "prepared: carry .gpubench and .gl, then run 'scripts/gpu_device_bench.sh run' on the device"
}

run() {
  local out="${OUT:-$PWD/gpubench-out}"
  mkdir -p "$out"
  for deb in .gl/*.deb; do dpkg -x "$deb" /; done
  ldconfig
  local root
  root="$(mktemp -d)"
  tar -C "$root" -xJf .gpubench/bench.tar.xz
  export LD_LIBRARY_PATH="$root/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  local vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  [[ -f "$vendor" ]] && export __EGL_VENDOR_LIBRARY_FILENAMES="$vendor"
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | tee "$out/gpu.txt" || true
  local bench="$root/bin/bench_gpu_mass_spring"
  # Parity first: a wrong kernel fails here in seconds, before the long runs.
  "$bench" --smoke --data /nonexistent --csv "$out/smoke.csv" 2>&1 | tee "$out/smoke.log"
  if ! grep -q "GL renderer: NVIDIA" "$out/smoke.log"; then
    echo "error: the GL context is not NVIDIA's (see smoke.log): the timings would not be the GPU's" >&2
    exit 1
  fi
  for mesh in ellipsoid150k ellipsoid1000k; do
    "$bench" --mesh "$mesh" --csv "$out/$mesh.csv" 2>&1 | tee "$out/$mesh.log"
  done
}

case "${1:-}" in
  prepare) shift; prepare "$@" ;;
  run) run ;;
  *) echo "usage: $0 prepare [BUILD] | run" >&2; exit 2 ;;
esac
