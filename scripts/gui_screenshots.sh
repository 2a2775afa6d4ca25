#!/usr/bin/env bash
# Usage: scripts/gui_screenshots.sh [output folder, default docs/gui]
# Takes the README's screenshots of the ParaView GUI (section "Using it in the ParaView GUI")
# from the real GUI under Xvfb, so they stay true: each scene of tests/gui/gui_screenshot_scene.py
# runs in a fresh `paraview` with the built plugin (tests/gui/run_gui.sh) and is saved as
# <folder>/<scene>.png. Needs the build (scripts/test.sh or scripts/demo.sh make it) and Debian's
# paraview, libqt5svg5, xvfb and xauth (scripts/common.sh installs them).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SOFTBODY_BUILD_DIR:-${root}/build}"
plugin="${build}/lib/paraview-5.11/plugins/SoftBody/SoftBody.so"
out="$(realpath -m "${1:-${root}/docs/gui}")"
if [[ ! -f "${plugin}" ]]; then
  echo "gui_screenshots.sh: ${plugin} is missing: build first (scripts/test.sh or scripts/demo.sh)" >&2
  exit 1
fi
mkdir -p "${out}"
for scene in jelly torus convergence; do
  echo "gui_screenshots.sh: ${scene} -> ${out}/${scene}.png"
  SOFTBODY_GUI_SCENE="${scene}" "${root}/tests/gui/run_gui.sh" \
    "${root}/tests/gui/gui_screenshot_scene.py" "${plugin}" "${root}/data" "${out}/${scene}.png"
done
