#!/usr/bin/env bash
# Runs every test: installs what is missing (Debian bookworm), builds, then runs CTest (unit,
# filter, pvpython and benchmark-smoke tests). The exit status is CTest's. Extra arguments go to
# ctest (e.g. scripts/test.sh -R python).
set -euo pipefail
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
softbody_setup

softbody_log "running ctest in ${SOFTBODY_BUILD_DIR}"
status=0
ctest --test-dir "${SOFTBODY_BUILD_DIR}" --output-on-failure -j"${SOFTBODY_TEST_JOBS:-2}" "$@" \
  || status=$?
if [[ ${status} -ne 0 ]]; then
  softbody_log "FAILED (ctest exit status ${status}); the failed tests are listed above and in"
  softbody_log "${SOFTBODY_BUILD_DIR}/Testing/Temporary/LastTestsFailed.log:"
  sed 's/^/    /' "${SOFTBODY_BUILD_DIR}/Testing/Temporary/LastTestsFailed.log" >&2 2>/dev/null || true
else
  softbody_log "all tests passed"
fi
exit "${status}"
