#!/usr/bin/env bash
# scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]: builds the libFuzzer targets (tests/fuzz/) in the
# instrumented build build-san/ (scripts/san_build.sh: clang-14 + ASan + UBSan) and runs each for SECONDS_PER_TARGET (default 25) on a copy
# of its seed corpus tests/fuzz/corpus/<target>/ and the fixed findings tests/fuzz/regressions/ (new inputs go to build-san/corpus/<target>/, not
# into the repo). Exit status non-zero when a target finds a crash, a sanitizer report or an uncaught
# exception other than magenc::InputError; the reproducer is build-san/artifacts/<target>/.
# Statistics (executions, coverage) of each run: build-san/logs/<target>.log, summary on stdout.
# CI (.ci/run) calls it with 20 s per target; docs/reliability.md has a 5-minute run's figures.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET="${1:-25}"
shift || true
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(toml cases_csv vti solve_json field_table measured_curve text_table comsol_table ansys_fld
                                     points_csv scan_csv correction_csv bh_csv)
scripts/san_build.sh "${TARGETS[@]/#/fuzz_}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}"
status=0
printf "%-12s %6s %12s %8s %6s %s\n" target secs executions exec/s cov result
for t in "${TARGETS[@]}"; do
  mkdir -p "build-san/corpus/$t" "build-san/artifacts/$t" build-san/logs
  cp -n tests/fuzz/corpus/"$t"/* "build-san/corpus/$t/" 2>/dev/null || true
  cp -n tests/fuzz/regressions/"$t"_* "build-san/corpus/$t/" 2>/dev/null || true
  log="build-san/logs/$t.log"
  set +e
  "build-san/fuzz/fuzz_$t" -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb=4096 -timeout=30 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="build-san/artifacts/$t/" \
    "build-san/corpus/$t" >"$log" 2>&1
  rc=$?
  set -e
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo "?")
  if [ $rc -eq 0 ]; then result=ok; else result="FINDING (exit $rc, see $log)"; status=1; fi
  printf "%-12s %6s %12s %8s %6s %s\n" "$t" "$SECONDS_PER_TARGET" "$execs" "$speed" "$cov" "$result"
  [ $rc -eq 0 ] || tail -40 "$log"
done
exit $status
