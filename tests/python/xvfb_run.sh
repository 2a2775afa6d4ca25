#!/usr/bin/env bash
# Usage: xvfb_run.sh <xvfb-run> <command> [args...]
# Runs the command under `xvfb-run -a` with a 24-bit screen (xvfb-run's default depth of 8 is too
# little for GLX). If it fails because of the X display itself (the virtual server vanished or
# refused the connection, seen on machines where several users start Xvfb servers at once), it
# runs once more; any other failure is returned as it is.
set -uo pipefail
xvfb_run="$1"
shift
log="$(mktemp)"
trap 'rm -f "${log}"' EXIT
status=1
for attempt in 1 2; do
  "${xvfb_run}" -a -s "-screen 0 1280x1024x24" "$@" 2>&1 | tee "${log}"
  status=${PIPESTATUS[0]}
  if [[ ${status} -eq 0 ]] ||
     ! grep -qE 'bad X server connection|X Error of failed request|Xvfb failed to start|cannot open display|Can.t open display' "${log}"; then
    exit "${status}"
  fi
  echo "xvfb_run.sh: attempt ${attempt} failed because of the X display (status ${status})" >&2
done
exit "${status}"
