#!/usr/bin/env bash
# scripts/test_debug.sh: Debug build into build-debug/ and every test through ctest there.
# Debug builds trap FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW (src/core/fp_trap.hpp, style.md item 11),
# in the test executables and in the executables they run, so a NaN or inf produced anywhere is a
# SIGFPE at the operation that produced it. Not part of test.sh / .ci/run (CI time budget): run it
# by hand after touching numerics. Extra arguments go to ctest (e.g. -L paraview, -R test_grid).
# Assumes the dependencies are installed (scripts/install_deps.sh, as root).
set -euo pipefail
cd "$(dirname "$0")/.."
# Unoptimized: per-test timeouts (tests/CMakeLists.txt) raised.
cmake -S . -B build-debug -DCMAKE_BUILD_TYPE=Debug -DMAGENC_TEST_TIMEOUT=900 -DMAGENC_SLOW_TEST_TIMEOUT=1500 >/dev/null
cmake --build build-debug -j"$(nproc)"
cd build-debug
ctest --output-on-failure -j"$(nproc)" "$@"
