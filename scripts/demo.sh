#!/usr/bin/env bash
# Soft Body demo: installs what the build and the demo need (Debian bookworm; not the tests'
# frameworks), builds the plugin, then in pvpython drops a jelly onto a floor (mass-spring,
# Stable Neo-Hookean; output/demo/softbody.*), a voxelized torus whose surface is skinned onto its particles (XPBD;
# output/demo/torus.*) and three jellies onto a block obstacle and each other (mass-spring,
# Collisions = Obstacles + Bodies; output/demo/pile.*). Each writes its run as data (.pvd, with
# the floor and obstacles), a picture (.png), an animation (.gif) and a ParaView state (.pvsm).
# Extra arguments go to every run of scripts/demo.py (see --help).
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
softbody_setup demo

# Debian's ParaView renders through GLX only: give it a virtual X display (24-bit; xvfb-run's
# default of 8 bits is too little for GLX).
for example in jelly torus pile; do
  softbody_log "running the ${example} demo (pvpython under xvfb-run)"
  xvfb-run -a -s "-screen 0 1280x1024x24" \
    pvpython "${SOFTBODY_ROOT}/scripts/demo.py" \
      --example "${example}" \
      --plugin "${SOFTBODY_PLUGIN_FILE}" \
      --data-dir "${SOFTBODY_ROOT}/data" \
      --output-dir "${SOFTBODY_ROOT}/output/demo" \
      "$@"
done
