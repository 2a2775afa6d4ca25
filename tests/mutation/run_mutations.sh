#!/usr/bin/env bash
# Mutation checks: applies each one-line mutation of mutations.txt to the sources, rebuilds only
# the targets its suite needs (in a separate build folder, with ccache), runs that suite and
# reports whether a test failed (killed) or all passed (survived). The file is restored after
# each mutation, and on any exit (trap).
#
#   tests/mutation/run_mutations.sh [--source DIR] [--build DIR] [--list FILE] [--only ID,ID]
#                                   [--report FILE] [--jobs N] [--no-baseline]
#
# Suites: unit   = ctest -L unit (core's GoogleTest suite) with EGL hidden;
#         gpu    = the GPU unit tests (unit.gpu_*) on whatever EGL driver there is (Mesa's
#                  llvmpipe here; without a context they skip and the mutation survives);
#         filter = ctest -L filter -LE gpu (the VTK filter programs) with EGL hidden;
#         gui    = ctest -L gui (the real ParaView GUI under Xvfb).
# First each suite needed runs on the unmutated sources (the baseline): a suite that already
# fails would "kill" every mutation, so the run stops there. Every suite stops at its first
# failure. A mutation that does not compile is reported as
# "invalid", not as killed. Exit status: 0 when every mutation is killed or documented (note:),
# 1 otherwise.
set -u -o pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source_dir="$(cd "$here/../.." && pwd)"
build_dir=""
list="$here/mutations.txt"
only=""
report=""
jobs=2
baseline=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --source) source_dir="$(cd "$2" && pwd)"; shift 2 ;;
    --build) build_dir="$2"; shift 2 ;;
    --list) list="$2"; shift 2 ;;
    --only) only=",$2,"; shift 2 ;;
    --report) report="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --no-baseline) baseline=0; shift ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
build_dir="${build_dir:-$source_dir/build-mutation}"
report="${report:-$build_dir/mutation_report.txt}"
apply="python3 $here/apply_mutation.py $list"

# EGL hidden: glvnd finds no vendor library, so no GPU context can be made (the CPU suite must
# not depend on one).
no_egl=(env __EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json)

suite_targets() {
  case "$1" in
    unit) echo softbody_unit_tests ;;
    gpu) echo softbody_gpu_unit_tests softbody_gpu_lifetimes_test ;;
    gui) echo SoftBody ;;
    filter)
      ninja -C "$build_dir" -t targets all 2>/dev/null | sed -n 's/^\(softbody_filter_test_[a-z_]*\): .*/\1/p' | sort -u | tr '\n' ' ' ;;
  esac
}

run_suite() { # suite -> 0 when every test passed; writes the log
  local suite="$1" log="$2"
  local common=(--test-dir "$build_dir" --stop-on-failure --timeout 300 -j "$jobs" --output-on-failure)
  case "$suite" in
    unit) "${no_egl[@]}" ctest "${common[@]}" -L unit >"$log" 2>&1 ;;
    gpu) ctest "${common[@]}" -R '^unit\.gpu_' >"$log" 2>&1 ;;
    filter) "${no_egl[@]}" ctest "${common[@]}" -L filter -LE gpu >"$log" 2>&1 ;;
    gui) ctest "${common[@]}" -L gui >"$log" 2>&1 ;;
  esac
}

if [[ ! -f "$build_dir/build.ninja" ]]; then
  cmake -S "$source_dir" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache \
    -DSOFTBODY_BUILD_BENCHMARKS=OFF >"$build_dir.configure.log" 2>&1 || {
    echo "configure failed: $build_dir.configure.log" >&2; exit 2; }
fi

mapfile -t entries < <($apply list)
backup=""
target_file=""
restore() {
  if [[ -n "$backup" && -f "$backup" ]]; then
    cp "$backup" "$target_file" && touch "$target_file" # newer than the mutated object: rebuilt
    rm -f "$backup"
  fi
  backup=""
}
trap 'restore; exit 130' INT TERM
trap restore EXIT

mkdir -p "$build_dir/mutation_logs"
if [[ $baseline -eq 1 ]]; then
  for suite in $(printf '%s\n' "${entries[@]}" | while IFS=$'\t' read -r id file suite note; do
                   [[ -z "$only" || "$only" == *",$id,"* ]] && echo "$suite"; done | sort -u); do
    log="$build_dir/mutation_logs/baseline-$suite.log"
    if ! cmake --build "$build_dir" -j "$jobs" --target $(suite_targets "$suite") >"$log" 2>&1 ||
      ! run_suite "$suite" "$log.ctest"; then
      echo "baseline: the $suite suite fails without any mutation (see $log*); fix that first" >&2
      exit 2
    fi
    echo "baseline: the $suite suite passes"
  done
fi
: >"$report"
killed=0; survived=0; documented=0; invalid=0
for entry in "${entries[@]}"; do
  IFS=$'\t' read -r id file suite note <<<"$entry"
  [[ -n "$only" && "$only" != *",$id,"* ]] && continue
  target_file="$source_dir/$file"
  if [[ ! -f "$target_file" ]]; then
    # A file that moved: reported, never created (restoring an empty backup would make one).
    printf '%-36s %-7s %4ds  %s\n' "$id" "$suite" 0 "invalid (no such file)" | tee -a "$report"
    invalid=$((invalid + 1))
    continue
  fi
  backup="$(mktemp)"
  cp "$target_file" "$backup"
  log="$build_dir/mutation_logs/$id.log"
  start=$SECONDS
  if ! $apply apply "$id" "$source_dir" >"$log" 2>&1; then
    result="invalid (not applied)"; invalid=$((invalid + 1))
  elif ! cmake --build "$build_dir" -j "$jobs" --target $(suite_targets "$suite") >>"$log" 2>&1; then
    result="invalid (does not build)"; invalid=$((invalid + 1))
  elif run_suite "$suite" "$log.ctest"; then
    if [[ -n "$note" ]]; then
      result="survived (documented)"; documented=$((documented + 1))
    else
      result="SURVIVED"; survived=$((survived + 1))
    fi
  else
    first="$(sed -n 's/^ *[0-9]*\/[0-9]* Test *#[0-9]*: \([^ ]*\) .*\*\*\*\(Failed\|Timeout\|Exception\).*/\1/p' "$log.ctest" | head -1)"
    result="killed by ${first:-?}"; killed=$((killed + 1))
  fi
  restore
  line="$(printf '%-36s %-7s %4ds  %s' "$id" "$suite" $((SECONDS - start)) "$result")"
  echo "$line" | tee -a "$report"
done
# Leave the build folder matching the restored sources.
cmake --build "$build_dir" -j "$jobs" --target softbody_unit_tests >/dev/null 2>&1 || true
total=$((killed + survived + documented + invalid))
echo "mutations: $total, killed: $killed, survived: $survived, survived but documented: $documented, invalid: $invalid" | tee -a "$report"
[[ $survived -eq 0 && $invalid -eq 0 ]]
