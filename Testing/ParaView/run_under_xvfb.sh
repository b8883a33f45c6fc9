#!/bin/sh
# Runs a command under a fresh X server (xvfb-run -a), once more if the
# first attempt fails: under load an X server can be lost before the first
# render ("bad X server connection"), which says nothing about the code.
#   run_under_xvfb.sh XVFB_RUN COMMAND [ARGS...]
xvfb_run="$1"
shift
"$xvfb_run" -a -s "-screen 0 1280x1024x24" "$@" && exit 0
echo "retrying once under a new X server"
exec "$xvfb_run" -a -s "-screen 0 1280x1024x24" "$@"
