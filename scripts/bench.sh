#!/usr/bin/env bash
# The accuracy and stability lab: same set-up as scripts/test.sh (packages, configure,
# build), then bench_accuracy writes one CSV per scene, the stability and stress tables and a
# summary into output/bench/, and scripts/plot_accuracy.py draws run time against error per scene
# (log-log, one curve per method, the Pareto front marked) when matplotlib is there.
#
#   scripts/bench.sh                    every scene (about 8 minutes on 2 shared cores)
#   scripts/bench.sh --quick            reduced sweeps, ~40 s, into output/bench/quick (CTest runs
#                                       bench_accuracy --quick, without the plots)
#   scripts/bench.sh bar stability      only these: freefall bar cantilever restitution incline
#                                       spot jelly frequency stability stress
#   scripts/bench.sh --no-plots ...     CSVs and tables only
#
# A complete run (no scene named, not --quick, default output folder) then writes its tables
# into docs/accuracy.md (scripts/update_docs_tables.py) with bench_error_control's, copies its
# plots to docs/bench/, and runs bench_tet_elasticity, bench_collision, bench_collision_scenes,
# bench_implicit, bench_mass_spring and bench_conditions, whose tables go into
# docs/performance.md.
#
# SOFTBODY_BENCH_OUT overrides output/bench; SOFTBODY_DATA_DIR the public meshes (../shared/data).
set -euo pipefail
plots=1
quick=0
args=()
for arg in "$@"; do
  case "${arg}" in
    --no-plots) plots=0 ;;
    --quick) quick=1; args+=("${arg}") ;;
    *) args+=("${arg}") ;;
  esac
done
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
softbody_setup

# --quick writes beside the full run's results, not over them.
default_out="${SOFTBODY_ROOT}/output/bench"
[[ ${quick} -eq 1 ]] && default_out="${default_out}/quick"
out="${SOFTBODY_BENCH_OUT:-${default_out}}"
data="${SOFTBODY_DATA_DIR:-${SOFTBODY_ROOT}/../shared/data}"
mkdir -p "${out}"
softbody_log "running bench_accuracy ${args[*]:-} into ${out}"
status=0
"${SOFTBODY_BUILD_DIR}/bin/bench_accuracy" --data "${data}" --out "${out}" ${args[@]+"${args[@]}"} \
  | tee "${out}/bench_accuracy.log" || status=$?

if [[ ${plots} -eq 1 ]]; then
  # Debian's matplotlib is for Debian's python3 (/usr/bin/python3), not a pyenv or venv one.
  python=/usr/bin/python3
  [[ -x "${python}" ]] || python="$(command -v python3)"
  if ! "${python}" -c "import matplotlib" >/dev/null 2>&1; then
    if [[ "$(id -u)" == "0" && "${SOFTBODY_SKIP_APT:-0}" != "1" ]]; then
      softbody_log "installing python3-matplotlib for the plots (apt-get, as root)"
      apt-get install -y --no-install-recommends python3-matplotlib >&2 || true
    fi
  fi
  if "${python}" -c "import matplotlib" >/dev/null 2>&1; then
    "${python}" "${SOFTBODY_ROOT}/scripts/plot_accuracy.py" "${out}"
  else
    softbody_log "matplotlib is missing: no plots (sudo apt-get install python3-matplotlib); the CSVs are in ${out}"
  fi
fi
# A complete run (every scene, not --quick) writes its tables into docs/accuracy.md and its
# four plots the page shows into docs/bench/: the documentation's numbers are this run's.
scenes_given=0
for arg in ${args[@]+"${args[@]}"}; do
  [[ "${arg}" != --* ]] && scenes_given=1
done
if [[ ${status} -eq 0 && ${quick} -eq 0 && ${scenes_given} -eq 0 && -z "${SOFTBODY_BENCH_OUT:-}" ]]; then
  # Error-controlled steps against the best fixed step in hindsight, into docs/accuracy.md.
  "${SOFTBODY_BUILD_DIR}/bin/bench_error_control" --csv "${out}/error_control.csv" \
    | tee "${out}/bench_error_control.log" || status=$?
  pvpython "${SOFTBODY_ROOT}/tests/bench/plot_error_control.py" "${out}/error_control.csv" \
    "${SOFTBODY_ROOT}/docs/bench/error_control.png" || status=$?
  "${python:-python3}" "${SOFTBODY_ROOT}/scripts/update_docs_tables.py" "${out}" \
    "${SOFTBODY_ROOT}/docs/accuracy.md" || status=$?
  # The finite-element materials' cost per tet, into docs/performance.md.
  "${SOFTBODY_BUILD_DIR}/bin/bench_tet_elasticity" --data "${data}" --csv "${out}/tet_elasticity.csv" \
    | tee "${out}/bench_tet_elasticity.log" || status=$?
  # Collision detection's broad phases (the PBD thesis's figures 5.1 and 5.2), into
  # docs/performance.md.
  "${SOFTBODY_BUILD_DIR}/bin/bench_collision" --repeat 7 --csv "${out}/broad_phases.csv" \
    | tee "${out}/bench_collision.log" || status=$?
  # Collision scenes through the whole step (detection, contact solve, edge contacts), into
  # docs/performance.md.
  "${SOFTBODY_BUILD_DIR}/bin/bench_collision_scenes" --repeat 3 --csv "${out}/collision_scenes.csv" \
    | tee "${out}/bench_collision_scenes.log" || status=$?
  # The implicit integrators' linear solvers on the 157k-tet TetGen ellipsoid, into
  # docs/performance.md.
  "${SOFTBODY_BUILD_DIR}/bin/bench_implicit" --data "${data}" --mesh ellipsoid157k \
    --csv "${out}/implicit_solvers.csv" | tee "${out}/bench_implicit.log" || status=$?
  # The mass-spring step on boxes and real meshes, in input and Morton order, into
  # docs/performance.md.
  "${SOFTBODY_BUILD_DIR}/bin/bench_mass_spring" --data "${data}" --repeat 3 --csv "${out}/mass_spring.csv" \
    | tee "${out}/bench_mass_spring.log" || status=$?
  # What loads and boundary conditions cost per step, into docs/performance.md.
  "${SOFTBODY_BUILD_DIR}/bin/bench_conditions" --data "${data}" --csv "${out}/conditions.csv" \
    | tee "${out}/bench_conditions.log" || status=$?
  "${python:-python3}" "${SOFTBODY_ROOT}/scripts/update_docs_tables.py" "${out}" \
    "${SOFTBODY_ROOT}/docs/performance.md" || status=$?
  for plot in bar spot jelly incline_stick; do
    [[ -f "${out}/${plot}.png" ]] && cp "${out}/${plot}.png" "${SOFTBODY_ROOT}/docs/bench/${plot}.png"
  done
fi
if [[ ${status} -ne 0 ]]; then
  softbody_log "FAILED: bench_accuracy exit status ${status} (its failed checks are listed above)"
fi
exit "${status}"
