#!/usr/bin/env bash
# ./run.sh: install missing Debian packages, build (Release), then run the
# default study pipeline into output/. No configuration needed.
#   1. solve_field        FEM field of the default magnet   -> output/field
#   2. linear_model       the study's linear model          -> output/linear_model
#   3. exact_field        exact field, all arrays           -> output/exact_field
#   4. real_field         FEM field vs exact, sweeps        -> output/real_field
#   5. airgap             dz on FEM + exact                 -> output/airgap
#   6. harmonic_provenance artefact vs physics harmonics    -> output/harmonic_provenance
#      (solves its own quick mu_r = 1 FE variants in-process; adds output/field)
#   7. radius             choosing r0, tolerance analysis   -> output/radius
#   8. error_sources      tilts, elevation, signal chain    -> output/error_sources
#      sensor_principles  Bz arrays vs inplane/xmr/amr      -> output/sensor_principles
#      calibration        residual of factory corrections   -> output/calibration
#      stray_field        homogeneous fields, a conductor   -> output/stray_field
#      temperature        -40 to 150 C: spectra, field margin -> output/temperature
#      steel_parts        steel/brass cup, shaft, end shield (FEM, ~1 min) -> output/steel_parts
#      design             magnet, gap, sensor, r0 from requirements -> output/design
#      speed              the turning encoder: delay, filter, hold, prediction -> output/speed
#      off_axis           ring magnet: side-shaft chip and bore arrays (< 1 min) -> output/off_axis
#      multipole          32-pole-pair code ring, read heads, nonius (< 1 min) -> output/multipole
#   9. error_spectrum --paths  probe paths for ParaView       -> output/probe_paths
#  10. diagnosis          diagnose round trip + anomalies    -> output/diagnosis
#      (exact field, 100 cases per array; FE field 5 cases per array from output/field)
# fem_convergence (several solves, a few minutes) runs with MAGENC_CONVERGENCE=1.
# Two lanes run side by side, so that both cores stay busy while one step runs serially (TetGen, the
# single-threaded studies): the FE lane (1, then the steps that read output/field: 4-7, 9, 10) and the
# exact lane (2, 3, 8). Each step's console output goes to output/logs/<step>.log; a failed step prints
# its log's tail, and run.sh exits non-zero once both lanes have stopped.
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh
BIN=build/bin
mkdir -p output/logs
# Two lanes share the cores: OpenMP threads waiting at a barrier sleep instead of spinning (the results do
# not depend on it; about 7 % less CPU for the whole run, docs/benchmarks.md).
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
t_start=$SECONDS
# step NAME COMMAND...: runs COMMAND with its output in output/logs/NAME.log; prints its time or its log's tail.
step() {
  local name=$1; shift
  local t0=$SECONDS
  if "$@" >"output/logs/$name.log" 2>&1; then
    echo "== $name ($((SECONDS - t0)) s)"
  else
    echo "== $name FAILED after $((SECONDS - t0)) s; the end of output/logs/$name.log:"
    tail -n 20 "output/logs/$name.log" | sed 's/^/   /'
    return 1
  fi
}
study() { step "$1" "$BIN/$1" --config "studies/$1/$1.toml" --out "output/$1"; }

fe_lane() {
  step solve_field "$BIN/solve_field" --set output.mesh_vtu=true --out output/field || return 1  # mesh.vtu: fem sources, ParaView
  step real_field "$BIN/real_field" --out output/real_field || return 1
  step airgap "$BIN/airgap" --out output/airgap || return 1
  # FE artefacts against mesh size and order: harmonic_provenance solves its variants (coarse P1, coarse P2,
  # medium P2, mu_r = 1; seconds each) itself and adds the default solve.
  step harmonic_provenance "$BIN/harmonic_provenance" --set provenance.fem_dirs=output/field \
    --out output/harmonic_provenance || return 1
  step radius "$BIN/radius" --out output/radius || return 1
  # Probe paths for ParaView's probe_paths.pvsm (exaggerated case so the paths show): sx 0.3, dx 0.2 mm.
  step error_spectrum "$BIN/error_spectrum" --field grid:output/field/plane.vti --array two --r0 2.4 --sx 0.3 \
    --dx 0.2 --paths output/probe_paths/paths_example.vtp --out output/probe_paths/spectrum.csv || return 1
  step diagnosis "$BIN/diagnosis" --set fem_field.dir=output/field --set roundtrip.fem_cases=5 \
    --out output/diagnosis || return 1
  if [ "${MAGENC_CONVERGENCE:-0}" = 1 ]; then
    step fem_convergence "$BIN/fem_convergence" --out output/fem_convergence || return 1
  fi
}

exact_lane() {
  step linear_model "$BIN/linear_model" --out output/linear_model || return 1
  step exact_field "$BIN/exact_field" --out output/exact_field || return 1
  for s in error_sources sensor_principles calibration stray_field temperature steel_parts design speed off_axis \
    multipole; do
    study "$s" || return 1
  done
}

exact_lane &
exact_pid=$!
status=0
fe_lane || status=1
wait "$exact_pid" || status=1
echo
if [ "$status" != 0 ]; then
  echo "magenc: a step failed (above); the other steps' results are in $(pwd)/output/." >&2
  exit 1
fi
echo "magenc: every step done in $((SECONDS - t_start)) s; results in $(pwd)/output/ (each study: summary.md,"
echo "        CSV tables, PNG plots; each step's console output in output/logs/);"
echo "        ParaView states in paraview_states/ (see paraview_states/README.md)."
