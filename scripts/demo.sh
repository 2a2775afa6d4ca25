#!/usr/bin/env bash
# Soft Body demo: installs what is missing (Debian bookworm), builds the plugin, then drops a jelly
# onto a floor in pvpython and writes output/demo/softbody.pvd (+ one .vtu per frame) and
# output/demo/softbody.png. Extra arguments go to scripts/demo.py (see --help).
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
softbody_setup

# Debian's ParaView renders through GLX only: give it a virtual X display (24-bit; xvfb-run's
# default of 8 bits is too little for GLX).
softbody_log "running the demo (pvpython under xvfb-run)"
xvfb-run -a -s "-screen 0 1280x1024x24" \
  pvpython "${SOFTBODY_ROOT}/scripts/demo.py" \
    --plugin "${SOFTBODY_PLUGIN_FILE}" \
    --data-dir "${SOFTBODY_ROOT}/data" \
    --output-dir "${SOFTBODY_ROOT}/output/demo" \
    "$@"
