#!/usr/bin/env bash
# Usage: xvfb_run.sh <xvfb-run> <command> [args...]
# Runs the command under `xvfb-run -a` with a 24-bit screen (xvfb-run's default depth of 8 is too
# little for GLX). If it fails because of the X display itself (the virtual server vanished or
# refused the connection, seen on machines where several test runs start Xvfb servers at once:
# `-a` takes the first free number, so two servers started together pick the same one), it runs
# again on a randomly chosen display number, twice at most; any other failure is returned as it
# is.
set -uo pipefail
xvfb_run="$1"
shift
log="$(mktemp)"
trap 'rm -f "${log}"' EXIT
status=1
display=(-a)
for attempt in 1 2 3; do
  "${xvfb_run}" "${display[@]}" -s "-screen 0 1280x1024x24" "$@" 2>&1 | tee "${log}"
  status=${PIPESTATUS[0]}
  if [[ ${status} -eq 0 ]] ||
     ! grep -qE 'bad X server connection|X Error of failed request|Xvfb failed to start|cannot open display|Can.t open display' "${log}"; then
    exit "${status}"
  fi
  echo "xvfb_run.sh: attempt ${attempt} failed because of the X display (status ${status})" >&2
  display=(-n "$((200 + RANDOM % 700))")
done
exit "${status}"
