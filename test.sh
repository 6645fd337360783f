#!/usr/bin/env bash
# ./test.sh: install missing Debian packages, build (Release), run every test via ctest.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)"   # per-test timeouts: tests/CMakeLists.txt
