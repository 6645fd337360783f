#!/usr/bin/env bash
# scripts/test_sanitize.sh [CTEST_ARGS...]: the whole ctest suite in the instrumented build build-san/
# (scripts/san_build.sh: clang-14, AddressSanitizer + UndefinedBehaviorSanitizer incl.
# float-cast-overflow, -fno-sanitize-recover=all, -O1). Called by .ci/run after ./test.sh; the same
# build then serves scripts/fuzz.sh.
# Not instrumented (system libraries): VTK, TetGen, PETSc, OpenMPI, libomp; toml++/CLI11/Eigen are
# header-only and ARE. ParaView state tests (label "paraview") only drive pvbatch on files the
# executables write; they are excluded here (they are run by ./test.sh), as is the Python module
# tests (label "python": an ASan-instrumented extension cannot load into an uninstrumented python3) and
# the serve tests (label "browser": Chromium and selenium drive an uninstrumented page; serve is fuzzed
# through its configuration parser).
# Extra arguments go to ctest (e.g. -R test_config).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/san_build.sh
# detect_leaks: leaks are findings too. Suppressions (scripts/sanitize.supp) only for reports inside
# uninstrumented third-party libraries; each entry says why.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0:strict_string_checks=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}"
cd build-san
status=0
ctest --output-on-failure -j"$(nproc)" -LE "paraview|python|browser" -E "^mpirun -n" "$@" || status=1
# The mpirun tests: their ranks' stacks must unwind through OpenMPI without frame pointers to be named
# (fast_unwind_on_malloc=0, slow, so only here); scripts/lsan_mpi.supp says what is OpenMPI's.
LSAN_OPTIONS="suppressions=$PWD/../scripts/lsan_mpi.supp:print_suppressions=0:fast_unwind_on_malloc=0" \
  ctest --output-on-failure -j"$(nproc)" -R "^mpirun -n" "$@" || status=1
exit $status
