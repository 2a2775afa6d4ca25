#!/usr/bin/env bash
# Writes the results a refactoring must leave unchanged: the benchmarks' state hashes
# (bench_mass_spring, bench_implicit, bench_pbd, bench_collision_scenes, smoke runs) and the
# accuracy lab's quick CSVs. Compare two runs with scripts/compare_reference_runs.py.
#
#   scripts/reference_run.sh <build dir> <output dir>
#
# Takes about two minutes on 2 cores. SOFTBODY_DATA_DIR overrides ../shared/data.
set -uo pipefail
if [[ $# -ne 2 ]]; then
  echo "usage: $0 <build dir> <output dir>" >&2
  exit 2
fi
build="$(cd "$1" && pwd)"
mkdir -p "$2"
out="$(cd "$2" && pwd)"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data="${SOFTBODY_DATA_DIR:-${root}/../shared/data}"
status=0
for bench in bench_mass_spring bench_implicit bench_pbd; do
  "${build}/bin/${bench}" --smoke --data "${data}" --csv "${out}/${bench}.csv" \
    > "${out}/${bench}.log" 2>&1 || { echo "${bench} failed (see ${out}/${bench}.log)" >&2; status=1; }
done
"${build}/bin/bench_collision_scenes" --smoke --csv "${out}/bench_collision_scenes.csv" \
  > "${out}/bench_collision_scenes.log" 2>&1 || { echo "bench_collision_scenes failed" >&2; status=1; }
"${build}/bin/bench_accuracy" --quick --data "${data}" --out "${out}/accuracy" \
  > "${out}/bench_accuracy.log" 2>&1 || { echo "bench_accuracy failed" >&2; status=1; }
exit "${status}"
