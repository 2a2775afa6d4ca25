#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz in build-fuzz (clang, -fsanitize=fuzzer,address,
# core only: no ParaView) and runs each for the given number of seconds (default 600):
#
#   scripts/fuzz.sh [seconds] [target...]     e.g. scripts/fuzz.sh 60 fuzz_gmsh_msh
#
# Targets: fuzz_tetgen_files (TetGen .node/.ele reader), fuzz_gmsh_msh (Gmsh .msh reader),
# fuzz_validation (mesh checks + mass-spring / PBD set-up and two steps). Each starts from its
# seed corpus tests/fuzz/corpus/<target> (read only) and grows build-fuzz/corpus/<target>;
# crashes, leaks and hangs (> 10 s per input) are written to build-fuzz/artifacts/<target>/ and
# stop that target; the script's exit status is 1 when any target found something. The seeds
# alone run as a CTest: ctest --test-dir build-fuzz. Reproduce a finding with
#   build-fuzz/bin/<target> build-fuzz/artifacts/<target>/crash-...
# Environment: SOFTBODY_JOBS (build jobs, default nproc), SOFTBODY_SKIP_APT=1 (no package check),
# SOFTBODY_FUZZ_ARGS (extra libFuzzer flags, e.g. "-jobs=2 -workers=2").
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

seconds="${1:-600}"
shift || true
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
  targets=(fuzz_tetgen_files fuzz_gmsh_msh fuzz_validation)
fi
build="${SOFTBODY_ROOT}/build-fuzz"

# Only what the fuzz build needs (no ParaView): clang with its libFuzzer runtime, core's libraries.
SOFTBODY_PACKAGES=(cmake ninja-build clang libclang-rt-14-dev libtbb-dev libeigen3-dev libtet1.5-dev libsuitesparse-dev libopenblas0-serial)
cd "${SOFTBODY_ROOT}"
softbody_check_packages

if [[ ! -f "${build}/build.ninja" ]]; then
  softbody_log "configuring ${build} (clang, SOFTBODY_FUZZ=ON)"
  CC=clang CXX=clang++ cmake -S "${SOFTBODY_ROOT}" -B "${build}" -G Ninja \
    -DCMAKE_BUILD_TYPE=Release -DSOFTBODY_FUZZ=ON
fi
cmake --build "${build}" -j"${SOFTBODY_JOBS:-$(nproc)}"

status=0
for target in "${targets[@]}"; do
  corpus="${build}/corpus/${target}"
  artifacts="${build}/artifacts/${target}"
  mkdir -p "${corpus}" "${artifacts}"
  softbody_log "fuzzing ${target} for ${seconds} s (corpus ${corpus})"
  rc=0
  # shellcheck disable=SC2086 # SOFTBODY_FUZZ_ARGS is a list of flags
  "${build}/bin/${target}" -max_total_time="${seconds}" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="${artifacts}/" ${SOFTBODY_FUZZ_ARGS:-} \
    "${corpus}" "${SOFTBODY_ROOT}/tests/fuzz/corpus/${target}" >"${build}/${target}.log" 2>&1 \
    || rc=$?
  # The summary: corpus loaded, the last coverage line, the final stats and any report.
  grep -E 'INITED|DONE|ERROR|SUMMARY|stat::|Test unit written' "${build}/${target}.log" >&2 || true
  if [[ ${rc} -ne 0 ]]; then
    softbody_log "${target}: FOUND SOMETHING (exit ${rc}), see ${build}/${target}.log and ${artifacts}/"
    status=1
  fi
done
exit "${status}"
