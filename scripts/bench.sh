#!/usr/bin/env bash
# The accuracy and stability lab and the performance benchmarks: same set-up as scripts/test.sh
# (packages, configure, build), then the benchmarks write their CSVs and Markdown tables into
# output/bench/, and the documentation's tables are rewritten from them.
#
#   scripts/bench.sh                    everything: the lab (about 8 minutes on 2 shared cores),
#                                       then the performance benchmarks; rewrites the tables of
#                                       docs/accuracy.md and docs/performance.md and the lab's
#                                       plots in docs/bench/
#   scripts/bench.sh --performance      only the performance benchmarks and docs/performance.md
#   scripts/bench.sh --quick            reduced lab sweeps, ~40 s, into output/bench/quick (CTest
#                                       runs bench_accuracy --quick, without the plots)
#   scripts/bench.sh bar stability      only these lab scenes: freefall bar cantilever restitution
#                                       incline spot jelly frequency stability stress
#   scripts/bench.sh --no-plots ...     CSVs and tables only
#
# Only a complete run (no scene named, not --quick, default output folder) writes into docs/. Each
# such run also writes machine.md (date, CPU, cores, memory, load, commit), the table
# docs/performance.md opens with. The lab: bench_accuracy (one CSV per scene, the stability and
# stress tables, a summary; scripts/plot_accuracy.py draws run time against error per scene when
# matplotlib is there) and bench_error_control, into docs/accuracy.md. The performance benchmarks
# (bench_mass_spring, bench_wide_kernels, bench_pbd, bench_implicit, bench_tet_elasticity,
# bench_collision, bench_collision_scenes, bench_conditions, bench_voxelize_skin), into
# docs/performance.md, and bench_gpu_mass_spring into docs/gpu.md.
#
# SOFTBODY_BENCH_OUT overrides output/bench; SOFTBODY_DATA_DIR the public meshes (../shared/data).
set -euo pipefail
plots=1
quick=0
performance_only=0
args=()
for arg in "$@"; do
  case "${arg}" in
    --no-plots) plots=0 ;;
    --performance) performance_only=1 ;;
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
bin="${SOFTBODY_BUILD_DIR}/bin"
mkdir -p "${out}"
status=0
# Debian's matplotlib is for Debian's python3 (/usr/bin/python3), not a pyenv or venv one.
python=/usr/bin/python3
[[ -x "${python}" ]] || python="$(command -v python3)"

# The tables' own record of where and when they were measured.
write_machine_table() {
  local cpu memory
  cpu="$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1)"
  memory="$(awk '/^MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo)"
  {
    printf '| measured (UTC) | CPU | cores | memory | load average at the start | commit |\n'
    printf '|---|---|---:|---:|---|---|\n'
    printf '| %s | %s | %s | %s | %s | %s |\n' "$(date -u '+%Y-%m-%d %H:%M')" "${cpu:-unknown}" \
      "$(nproc)" "${memory}" "$(cut -d' ' -f1-3 /proc/loadavg)" \
      "$(git -C "${SOFTBODY_ROOT}" describe --always --dirty 2>/dev/null || echo unknown)"
  } >"${out}/machine.md"
}

# Runs one benchmark program, its output into the terminal and <log>.log.
run_bench() {
  local log="$1"
  shift
  softbody_log "running $*"
  "$@" | tee "${out}/${log}.log" || status=$?
}

run_lab() {
  softbody_log "running bench_accuracy ${args[*]:-} into ${out}"
  run_bench bench_accuracy "${bin}/bench_accuracy" --data "${data}" --out "${out}" ${args[@]+"${args[@]}"}
  if [[ ${plots} -eq 1 ]]; then
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
}

# Error-controlled steps against the best fixed step in hindsight, and the lab's tables and
# plots, into docs/accuracy.md and docs/bench/.
document_lab() {
  run_bench bench_error_control "${bin}/bench_error_control" --csv "${out}/error_control.csv"
  pvpython "${SOFTBODY_ROOT}/tests/bench/plot_error_control.py" "${out}/error_control.csv" \
    "${SOFTBODY_ROOT}/docs/bench/error_control.png" || status=$?
  "${python}" "${SOFTBODY_ROOT}/scripts/update_docs_tables.py" "${out}" \
    "${SOFTBODY_ROOT}/docs/accuracy.md" || status=$?
  for plot in bar spot jelly incline_stick; do
    [[ -f "${out}/${plot}.png" ]] && cp "${out}/${plot}.png" "${SOFTBODY_ROOT}/docs/bench/${plot}.png"
  done
}

# The performance benchmarks, each writing a CSV and a Markdown table, into docs/performance.md.
document_performance() {
  # The mass-spring step on boxes and real meshes, in input and Morton order.
  run_bench bench_mass_spring "${bin}/bench_mass_spring" --data "${data}" --repeat 3 --csv "${out}/mass_spring.csv"
  # XPBD and mass-spring kernels, one constraint at a time against four lanes.
  run_bench bench_wide_kernels "${bin}/bench_wide_kernels" --data "${data}" --repeat 5 --csv "${out}/wide_kernels.csv"
  # PBD/XPBD solvers: the thesis's convergence figures and throughput on the tet meshes.
  run_bench bench_pbd "${bin}/bench_pbd" --data "${data}" --repeat 3 --csv "${out}/pbd"
  # The implicit integrators' linear solvers on the 157k-tet TetGen ellipsoid.
  run_bench bench_implicit "${bin}/bench_implicit" --data "${data}" --mesh ellipsoid157k \
    --csv "${out}/implicit_solvers.csv"
  # The finite-element materials' cost per tet.
  run_bench bench_tet_elasticity "${bin}/bench_tet_elasticity" --data "${data}" --csv "${out}/tet_elasticity.csv"
  # Collision detection's broad phases (the PBD thesis's figures 5.1 and 5.2).
  run_bench bench_collision "${bin}/bench_collision" --repeat 7 --csv "${out}/broad_phases.csv"
  # Collision scenes through the whole step (detection, contact solve, edge contacts).
  run_bench bench_collision_scenes "${bin}/bench_collision_scenes" --repeat 3 --csv "${out}/collision_scenes.csv"
  # What loads and boundary conditions cost per step.
  run_bench bench_conditions "${bin}/bench_conditions" --data "${data}" --csv "${out}/conditions.csv"
  # Voxelization and skinning against particle and vertex counts.
  run_bench bench_voxelize_skin "${bin}/bench_voxelize_skin" --csv "${out}/voxelize_skin.csv"
  "${python}" "${SOFTBODY_ROOT}/scripts/update_docs_tables.py" "${out}" \
    "${SOFTBODY_ROOT}/docs/performance.md" || status=$?
  document_gpu
}

# The GPU mass-spring step against the CPU, into docs/gpu.md: on Mesa's llvmpipe where the
# machine has no GPU (a correctness run; the table names the renderer). Exit status 77: no
# OpenGL 4.3 context at all, so the page keeps its table.
document_gpu() {
  [[ -x "${bin}/bench_gpu_mass_spring" ]] || return 0
  local gpu_status=0
  softbody_log "running bench_gpu_mass_spring"
  "${bin}/bench_gpu_mass_spring" --data "${data}" --csv "${out}/gpu_mass_spring.csv" \
    | tee "${out}/bench_gpu_mass_spring.log" || gpu_status=$?
  if [[ ${gpu_status} -eq 77 ]]; then
    softbody_log "no OpenGL 4.3 context: docs/gpu.md keeps its table"
  elif [[ ${gpu_status} -ne 0 ]]; then
    status=${gpu_status}
  else
    "${python}" "${SOFTBODY_ROOT}/scripts/update_docs_tables.py" "${out}" \
      "${SOFTBODY_ROOT}/docs/gpu.md" || status=$?
  fi
}

scenes_given=0
for arg in ${args[@]+"${args[@]}"}; do
  [[ "${arg}" != --* ]] && scenes_given=1
done
complete=0
[[ ${quick} -eq 0 && ${scenes_given} -eq 0 && -z "${SOFTBODY_BENCH_OUT:-}" ]] && complete=1
if [[ ${performance_only} -eq 1 && ${complete} -eq 0 ]]; then
  softbody_log "--performance goes with no scene, no --quick and no SOFTBODY_BENCH_OUT (it writes into docs/)"
  exit 2
fi
[[ ${complete} -eq 1 ]] && write_machine_table
if [[ ${performance_only} -eq 0 ]]; then
  run_lab
  [[ ${status} -eq 0 && ${complete} -eq 1 ]] && document_lab
fi
if [[ ${status} -eq 0 && ${complete} -eq 1 ]]; then
  document_performance
fi
if [[ ${status} -ne 0 ]]; then
  softbody_log "FAILED: a benchmark exited with status ${status} (its failed checks are listed above)"
fi
exit "${status}"
