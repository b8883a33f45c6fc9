#!/bin/sh
# Runs a command (a test that renders) under a fresh X server, and once
# more under another one if the first attempt fails.
#
# -noreset: by default Xvfb resets itself whenever its last client
# disconnects, and the reset drops any client that connected in the
# meantime. pvbatch closes one X connection and opens its render window's
# right after, so under load the window's XOpenDisplay could land in the
# reset and fail ("bad X server connection"), as seen in full runs.
# Servers are searched from a display number of this process's own, not
# from xvfb-run's :99.
#   run_under_xvfb.sh XVFB_RUN COMMAND [ARGS...]
xvfb_run="$1"
shift
first=$((200 + $$ % 500))
server="-screen 0 1600x1200x24 -noreset"
"$xvfb_run" -a -n "$first" -s "$server" "$@" && exit 0
echo "retrying once under a new X server"
sleep 2
exec "$xvfb_run" -a -n $((first + 500)) -s "$server" "$@"
