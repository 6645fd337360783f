#!/usr/bin/env bash
# ParaView 5.11 Python (pvbatch + paraview.simple) for the ParaView state tests,
# next to libvtk9-dev on Debian 12.
#
# Why not simply `apt-get install python3-paraview`: on Debian 12 it Conflicts
# with python3-vtk9 (both ship /usr/lib/python3/dist-packages/vtkmodules), and
# libvtk9-dev, which the C++ build needs, Depends on python3-vtk9. Installing
# python3-paraview therefore REMOVES libvtk9-dev. Instead this script installs
# the `paraview` package (pvbatch, the ParaView libraries; no conflict), and
# unpacks the python3-paraview .deb of the same version into a private prefix,
# $MAGENC_PV_PREFIX (default /opt/magenc/paraview-python), which
# paraview_states/pvbatch.sh puts first on PYTHONPATH. Xvfb provides the X
# display that Debian's X-only ParaView build needs to render offscreen.
# Idempotent; runs as root (or with sudo).
set -euo pipefail
PREFIX="${MAGENC_PV_PREFIX:-/opt/magenc/paraview-python}"
SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive

. "$(dirname "$0")/apt_packages.sh"
install_missing_packages install_paraview_python paraview xvfb xauth python3-numpy

# python3-paraview installed system-wide (a machine without libvtk9-dev): use it.
if dpkg-query -W -f='${Status}' python3-paraview 2>/dev/null | grep -q "install ok installed"; then
  exit 0
fi

version="$(dpkg-query -W -f='${Version}' paraview)"
stamp="$PREFIX/.python3-paraview-version"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$version" ] &&
   [ -f "$PREFIX/usr/lib/python3/dist-packages/paraview/simple.py" ]; then
  exit 0
fi
echo "install_paraview_python: unpacking python3-paraview=$version into $PREFIX"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
chmod 755 "$work"   # apt's _apt user downloads into it
( cd "$work" && $SUDO apt-get download -qq "python3-paraview=$version" >/dev/null 2>&1 ||
  { $SUDO apt-get update -qq && $SUDO apt-get download -qq "python3-paraview=$version"; } )
$SUDO rm -rf "$PREFIX.tmp"
$SUDO mkdir -p "$PREFIX.tmp"
$SUDO dpkg -x "$work"/python3-paraview_*.deb "$PREFIX.tmp"
echo "$version" | $SUDO tee "$PREFIX.tmp/.python3-paraview-version" >/dev/null
$SUDO rm -rf "$PREFIX"
$SUDO mv "$PREFIX.tmp" "$PREFIX"
