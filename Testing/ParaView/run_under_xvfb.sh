#!/bin/sh
# Runs a command (a test that renders) under a fresh X server, and once
# more under another one if the first attempt fails. Full runs on a loaded
# machine have lost the X connection at the first render ("bad X server
# connection"), which says nothing about the code. Servers are searched from
# a display number of this process's own, not from xvfb-run's :99.
#   run_under_xvfb.sh XVFB_RUN COMMAND [ARGS...]
xvfb_run="$1"
shift
first=$((200 + $$ % 500))
"$xvfb_run" -a -n "$first" -s "-screen 0 1280x1024x24" "$@" && exit 0
echo "retrying once under a new X server"
sleep 2
exec "$xvfb_run" -a -n $((first + 500)) -s "-screen 0 1280x1024x24" "$@"
