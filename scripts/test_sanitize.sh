#!/usr/bin/env bash
# scripts/test_sanitize.sh: AddressSanitizer + UndefinedBehaviorSanitizer build of the library, the
# executables and the tests into build-asan/ (RelWithDebInfo at -O1, frame pointers kept), then the
# ctest suite there. -fno-sanitize-recover=all: the first UB report aborts the process, so a report
# is a failed test, not a line in a log. float-cast-overflow is not in -fsanitize=undefined on GCC
# by default: it is listed explicitly. Called by .ci/run after ./test.sh.
# Not instrumented (system libraries): VTK, TetGen, libgomp, toml++/CLI11 are header-only and ARE.
# ParaView state tests (label "paraview") only drive pvbatch on files the executables write; they
# are excluded here (they are run by ./test.sh).
# Extra arguments go to ctest (e.g. -R test_config).
set -euo pipefail
cd "$(dirname "$0")/.."
SAN="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g -DNDEBUG" \
  -DCMAKE_CXX_FLAGS="$SAN" -DCMAKE_EXE_LINKER_FLAGS="$SAN" >/dev/null
cmake --build build-asan -j"$(nproc)"
# detect_leaks: leaks are findings too. Suppressions (scripts/sanitize.supp) only for reports inside
# uninstrumented third-party libraries; each entry says why.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0:strict_string_checks=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}"
cd build-asan
ctest --output-on-failure -j"$(nproc)" --timeout 3000 -LE paraview "$@"
