#!/usr/bin/env bash
# Configures and builds magenc (Release) into build/; reuses an existing build.
# MAGENC_WERROR=ON (set by .ci/run): compiler warnings are errors. MAGENC_NATIVE=ON: -march=native.
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache, when installed, shares compiled objects between build trees (a developer's worktrees).
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
  -DMAGENC_WERROR="${MAGENC_WERROR:-OFF}" -DMAGENC_NATIVE="${MAGENC_NATIVE:-OFF}" >/dev/null
cmake --build build -j"$(nproc)"
