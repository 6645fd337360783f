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
set -euo pipefail
cd "$(dirname "$0")"
scripts/install_deps.sh
scripts/build.sh
BIN=build/bin
mkdir -p output
step() { echo; echo "== $*"; local t0=$SECONDS; "$@"; echo "   ($((SECONDS - t0)) s)"; }
step "$BIN/solve_field" --set output.mesh_vtu=true --out output/field   # mesh.vtu: fem sources, ParaView
step "$BIN/linear_model" --out output/linear_model
step "$BIN/exact_field" --out output/exact_field
step "$BIN/real_field" --out output/real_field
step "$BIN/airgap" --out output/airgap
# FE artefacts against mesh size and order: harmonic_provenance solves its variants (coarse P1, coarse P2,
# medium P2, mu_r = 1; seconds each) itself and adds the default solve.
step "$BIN/harmonic_provenance" --set provenance.fem_dirs=output/field --out output/harmonic_provenance
step "$BIN/radius" --out output/radius
step "$BIN/error_sources" --config studies/error_sources/error_sources.toml --out output/error_sources
step "$BIN/sensor_principles" --config studies/sensor_principles/sensor_principles.toml --out output/sensor_principles
step "$BIN/calibration" --config studies/calibration/calibration.toml --out output/calibration
step "$BIN/stray_field" --config studies/stray_field/stray_field.toml --out output/stray_field
step "$BIN/temperature" --config studies/temperature/temperature.toml --out output/temperature
step "$BIN/steel_parts" --config studies/steel_parts/steel_parts.toml --out output/steel_parts
step "$BIN/design" --config studies/design/design.toml --out output/design
step "$BIN/speed" --config studies/speed/speed.toml --out output/speed
step "$BIN/off_axis" --config studies/off_axis/off_axis.toml --out output/off_axis
step "$BIN/multipole" --config studies/multipole/multipole.toml --out output/multipole
# Probe paths for ParaView's probe_paths.pvsm (exaggerated case so the paths show): sx 0.3, dx 0.2 mm.
step "$BIN/error_spectrum" --field grid:output/field/plane.vti --array two --r0 2.4 --sx 0.3 --dx 0.2 \
  --paths output/probe_paths/paths_example.vtp --out output/probe_paths/spectrum.csv
step "$BIN/diagnosis" --set fem_field.dir=output/field --set roundtrip.fem_cases=5 --out output/diagnosis
if [ "${MAGENC_CONVERGENCE:-0}" = 1 ]; then
  step "$BIN/fem_convergence" --out output/fem_convergence
fi
echo
echo "magenc: results in $(pwd)/output/ (each study: summary.md, CSV tables, PNG plots);"
echo "        ParaView states in paraview_states/ (see paraview_states/README.md)."
