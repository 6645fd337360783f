#!/usr/bin/env bash
# Runs ParaView's pvbatch (5.11) on a headless machine:
#  * uses the python3-paraview unpacked by scripts/install_paraview_python.sh
#    (PYTHONPATH) unless python3-paraview is installed system-wide;
#  * wraps pvbatch in xvfb-run when there is no X display (Debian's ParaView
#    build renders through X only; no EGL/OSMesa).
# Usage: paraview_states/pvbatch.sh script.py [args...]
set -euo pipefail
PREFIX="${MAGENC_PV_PREFIX:-/opt/magenc/paraview-python}"
if ! dpkg-query -W -f='${Status}' python3-paraview 2>/dev/null | grep -q "install ok installed"; then
  site="$PREFIX/usr/lib/python3/dist-packages"
  if [ ! -f "$site/paraview/simple.py" ]; then
    echo "pvbatch.sh: ParaView Python not found in $site; run scripts/install_paraview_python.sh" >&2
    exit 2
  fi
  export PYTHONPATH="$site${PYTHONPATH:+:$PYTHONPATH}"
fi
command -v pvbatch >/dev/null || { echo "pvbatch.sh: pvbatch not found (apt-get install paraview)" >&2; exit 2; }
if [ -n "${DISPLAY:-}" ]; then
  exec pvbatch "$@"
fi
command -v xvfb-run >/dev/null || { echo "pvbatch.sh: no DISPLAY and no xvfb-run (apt-get install xvfb xauth)" >&2; exit 2; }
# Two X servers started at the same moment (parallel ctest, other users) can
# race for one display number and pvbatch then aborts with "bad X server
# connection". Start the free-number search at a random display and retry on
# that X failure only (up to 3 times); any other failure is returned as is.
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
rc=0
for attempt in 1 2 3; do
  rc=0
  xvfb-run -a -n $((100 + RANDOM % 800)) -s "-screen 0 1600x1200x24 -nolisten tcp" pvbatch "$@" 2>"$log" || rc=$?
  cat "$log" >&2
  if [ "$rc" = 0 ] || ! grep -q -E "bad X server connection|Xvfb failed to start|cannot open display" "$log"; then
    exit "$rc"
  fi
  echo "pvbatch.sh: X server not usable (attempt $attempt of 3), retrying on another display" >&2
done
exit "$rc"
