#!/bin/bash
# Runs a ParaView Python script under a virtual X server of its own: ParaView 5.11's pvpython needs an X server to
# render (it crashes with --force-offscreen-rendering). The one way jobs/garment_outputs.sh, postprocess/movie.py
# and the tests start pvpython for pictures.
#
#   bash postprocess/pvpython_xvfb.sh postprocess/render.py ARGS...
#
# PVPYTHON: the pvpython to run [pvpython on PATH, else /usr/bin/pvpython]. Without xvfb-run, pvpython runs on the
# display there is.
#
# Two races, both ending in pvpython's "bad X server connection" and an abort:
# - Xvfb resets when its last client disconnects, and pvpython connects twice in a row (the probe of the OpenGL
#   capabilities, then the render window): a connection that arrives during the reset is hung up. -noreset keeps
#   the server as it is (measured on the loaded 2-core VM: 4 of 5 renders of the fitted dress aborted without it,
#   0 of 5 with it; an strace showed the second connection hung up 4 ms after the first closed).
# - xvfb-run -a can lose the race for a display number to another X server starting at the same moment: a random
#   start and up to three tries.
set -u
PVPYTHON=${PVPYTHON:-$(command -v pvpython || echo /usr/bin/pvpython)}
command -v xvfb-run > /dev/null || exec "$PVPYTHON" "$@"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
status=1
for try in 1 2 3; do
  xvfb-run -a -n $((200 + RANDOM % 2000)) -s "-screen 0 1280x1024x24 -noreset" "$PVPYTHON" "$@" < /dev/null > "$log" 2>&1
  status=$?
  [ "$status" = 0 ] && break
  grep -q "bad X server connection\|Xvfb failed to start" "$log" || break
  echo "pvpython_xvfb: try $try: no X server connection, trying again" >&2
  sleep "$try"
done
cat "$log"
exit "$status"
