#!/bin/sh
# Runs a command under a fresh X server, once more if the first attempt
# fails. The servers are searched from a display number of this process's
# own (xvfb-run -a starts at :99 otherwise): a test started right after
# another one's server on :99 went away can meet that server's leftovers and
# lose its connection ("bad X server connection"), which says nothing about
# the code.
#   run_under_xvfb.sh XVFB_RUN COMMAND [ARGS...]
xvfb_run="$1"
shift
first=$((200 + $$ % 500))
"$xvfb_run" -a -n "$first" -s "-screen 0 1280x1024x24" "$@" && exit 0
echo "retrying once under a new X server"
sleep 2
exec "$xvfb_run" -a -n $((first + 500)) -s "-screen 0 1280x1024x24" "$@"
