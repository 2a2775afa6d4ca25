#!/usr/bin/env bash
# Runs every test: installs what is missing (Debian bookworm), builds, then runs CTest (unit,
# filter, pvpython and benchmark-smoke tests). The exit status is CTest's. Extra arguments go to
# ctest (e.g. scripts/test.sh -R python).
#
#   scripts/test.sh --asan [ctest args]   the same in build-asan/, built with AddressSanitizer
#                                         (+ LeakSanitizer) via -DSOFTBODY_SANITIZER=address
#   scripts/test.sh --tsan [ctest args]   the same in build-tsan/, with ThreadSanitizer
#                                         (-DSOFTBODY_SANITIZER=thread: core's loops on std::thread)
#
# In a sanitizer build the pvpython tests run pvpython with the sanitizer's runtime preloaded
# (tests/python/CMakeLists.txt); any sanitizer report fails its test. Expect long builds and
# runs (several times slower than Release). SOFTBODY_BUILD_DIR overrides the folder.
set -euo pipefail
sanitizer=""
args=()
for arg in "$@"; do
  case "${arg}" in
    --asan) sanitizer=address ;;
    --tsan) sanitizer=thread ;;
    *) args+=("${arg}") ;;
  esac
done
if [[ -n "${sanitizer}" ]]; then
  folder=build-asan
  [[ "${sanitizer}" == "thread" ]] && folder=build-tsan
  SOFTBODY_BUILD_DIR="${SOFTBODY_BUILD_DIR:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/${folder}}"
  SOFTBODY_CMAKE_ARGS=("-DSOFTBODY_SANITIZER=${sanitizer}")
fi
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
softbody_setup

softbody_log "running ctest in ${SOFTBODY_BUILD_DIR}"
status=0
ctest --test-dir "${SOFTBODY_BUILD_DIR}" --output-on-failure -j"${SOFTBODY_TEST_JOBS:-2}" \
  ${args[@]+"${args[@]}"} \
  || status=$?
if [[ ${status} -ne 0 ]]; then
  softbody_log "FAILED (ctest exit status ${status}); the failed tests are listed above and in"
  softbody_log "${SOFTBODY_BUILD_DIR}/Testing/Temporary/LastTestsFailed.log:"
  sed 's/^/    /' "${SOFTBODY_BUILD_DIR}/Testing/Temporary/LastTestsFailed.log" >&2 2>/dev/null || true
else
  softbody_log "all tests passed"
fi
exit "${status}"
