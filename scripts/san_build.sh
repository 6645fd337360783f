#!/usr/bin/env bash
# scripts/san_build.sh [TARGET...]: the one instrumented build, build-san/, shared by the sanitizer
# suite (scripts/test_sanitize.sh) and the fuzz runs (scripts/fuzz.sh), so CI compiles the project
# once more, not twice. clang-14, AddressSanitizer + UndefinedBehaviorSanitizer (float-cast-overflow
# listed explicitly), -fno-sanitize-recover=all (the first report aborts: a report is a failed test),
# RelWithDebInfo at -O1 with line tables only (stack traces name file:line; full -g only makes the
# objects bigger). Every object also carries libFuzzer's coverage hooks (-fsanitize=fuzzer-no-link);
# only the fuzz targets link libFuzzer itself (tests/fuzz/CMakeLists.txt). Without TARGET: everything
# (libraries, executables, tests, fuzz targets).
set -euo pipefail
cd "$(dirname "$0")/.."
SAN="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer"
launcher=(); command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-san -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMAGENC_FUZZ=ON "${launcher[@]}" \
  -DMAGENC_TEST_TIMEOUT=1500 -DMAGENC_SLOW_TEST_TIMEOUT=3000 \
  -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DCMAKE_CXX_FLAGS="$SAN -fsanitize=fuzzer-no-link" -DCMAKE_EXE_LINKER_FLAGS="$SAN" >/dev/null
if [ $# -gt 0 ]; then
  cmake --build build-san -j"$(nproc)" --target "$@"
else
  cmake --build build-san -j"$(nproc)"
fi
