#!/usr/bin/env bash
# ./run.sh: install missing Debian packages, build (Release), run the default
# study pipeline into output/.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh
BIN=build/bin
echo "magenc: all executables built into $BIN"
