#!/usr/bin/env bash
# Usage: run_gui.sh <script.py> <plugin.so> <data dir> [screenshot.png]
# Runs <script.py> inside the real ParaView GUI (`paraview --script`) under Xvfb and returns its
# verdict: 0 passed, 1 failed, 77 (CTest's skip code) when `paraview`, `xvfb-run` or `pvpython` is
# missing (Debian: paraview, python3-paraview, libqt5svg5, xvfb, xauth; scripts/common.sh installs
# them).
# The script learns its arguments from the environment (tests/gui/gui_support.py), writes its
# verdict and has the GUI ended (gui_finish.py); a GUI still running after SOFTBODY_GUI_TIMEOUT
# seconds (default 120) has failed.
set -uo pipefail
script="$1" plugin="$2" data_dir="$3" shot="${4:-}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# pvpython runs the helper that ends the GUI (gui_finish.py); SOFTBODY_PVPYTHON may name it.
pvpython="${SOFTBODY_PVPYTHON:-pvpython}"
for tool in paraview xvfb-run "${pvpython}"; do
  if ! command -v "${tool}" >/dev/null 2>&1; then
    echo "SKIP: '${tool}' not found (Debian: apt-get install paraview python3-paraview libqt5svg5 xvfb xauth)"
    exit 77
  fi
done
export SOFTBODY_PVPYTHON="${pvpython}"
work="$(mktemp -d)"
trap 'rm -rf "${work}"' EXIT
export SOFTBODY_GUI_DIR="${here}" SOFTBODY_PLUGIN_FILE="${plugin}" SOFTBODY_DATA_DIR="${data_dir}"
export SOFTBODY_GUI_RESULT="${work}/result.txt" SOFTBODY_GUI_SHOT="${shot}"
# --dr: the user's ParaView settings must not change what Apply does. HOME and the runtime dir
# in the scratch folder, so nothing is written to (or read from) the real ones.
export HOME="${work}" XDG_RUNTIME_DIR="${work}"
# Three tries, as tests/python/xvfb_run.sh: only when the X display itself failed, then on a
# random display number (another test run's server may hold the one `-a` picks).
display=(-a)
for attempt in 1 2 3; do
  timeout "${SOFTBODY_GUI_TIMEOUT:-120}" xvfb-run "${display[@]}" -s "-screen 0 1280x800x24" \
    paraview --dr --script="${script}" >"${work}/log.txt" 2>&1
  status=$?
  if [[ -f "${SOFTBODY_GUI_RESULT}" ]] ||
     ! grep -qE 'bad X server connection|Xvfb failed to start|cannot open display|could not connect to display' "${work}/log.txt"; then
    break
  fi
  echo "run_gui.sh: attempt ${attempt}: the X display failed (status ${status})" >&2
  display=(-n "$((200 + RANDOM % 700))")
done
if [[ ! -f "${SOFTBODY_GUI_RESULT}" ]]; then
  echo "FAIL: the GUI ended (status ${status}) without a verdict; its output:"
  cat "${work}/log.txt" "${SOFTBODY_GUI_RESULT}".finish.log 2>/dev/null
  exit 1
fi
cat "${SOFTBODY_GUI_RESULT}"
# Anything ParaView logged as an error or warning (what the Output Messages window shows, echoed
# to the terminal) fails the run, including what came after the script, while the GUI painted.
if grep -E ' (ERR|WARN)\| ' "${work}/log.txt"; then
  echo "FAIL: ParaView logged the error(s) or warning(s) above"
  echo "FAIL" >"${SOFTBODY_GUI_RESULT}"
fi
if [[ "$(head -n1 "${SOFTBODY_GUI_RESULT}")" != "PASS" ]]; then
  echo "--- the GUI's output:"
  cat "${work}/log.txt" "${SOFTBODY_GUI_RESULT}".finish.log 2>/dev/null
  exit 1
fi
exit 0
