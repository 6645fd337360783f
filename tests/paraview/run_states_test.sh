#!/usr/bin/env bash
# ctest driver for the ParaView states (paraview_states/*.pvsm):
#  1. a small field solve into WORK/output/field (solve_field with coarse mesh
#     keys), or, with --synthetic, the synthetic stand-in
#     (make_synthetic_field.py: exact field on a tetrahedralized box);
#  1b. the steel_parts study (its default configuration, a few seconds) into
#     WORK/output/steel_parts (steel_cup/: the field files of steel_parts_B.pvsm),
#     or, with --synthetic, the stand-in of steel_cup/;
#  2. probe paths of one mounting case through magenc::write_probe_paths_vtp
#     (helper magenc_write_test_paths) into WORK/output/probe_paths/paths_example.vtp;
#  3. check_states.py: loads each state against WORK/output (data directory
#     search, restricted to it), checks sources/arrays/ranges, renders PNGs
#     into WORK/images and checks they are not blank.
# Usage: run_states_test.sh --source DIR --work DIR --helper EXE
#                           (--solve-field EXE --steel-parts EXE | --synthetic [--omit ARRAY|part])
set -euo pipefail
src="" work="" helper="" solve="" steel="" synthetic=0 omit=""
while [ $# -gt 0 ]; do
  case "$1" in
    --source) src="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --helper) helper="$2"; shift 2 ;;
    --solve-field) solve="$2"; shift 2 ;;
    --steel-parts) steel="$2"; shift 2 ;;
    --synthetic) synthetic=1; shift ;;
    --omit) omit="$2"; shift 2 ;;
    *) echo "run_states_test.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
[ -n "$src" ] && [ -n "$work" ] && [ -n "$helper" ] || { echo "run_states_test.sh: --source, --work, --helper required" >&2; exit 2; }
pv="$src/paraview_states/pvbatch.sh"
rm -rf "$work"
mkdir -p "$work/output"

# 1. Field.
if [ "$synthetic" = 1 ]; then
  echo "== synthetic field (NOT a FEM solve)"
  "$pv" "$src/tests/paraview/make_synthetic_field.py" --out "$work/output/field" \
        --steel-cup "$work/output/steel_parts/steel_cup" ${omit:+--omit "$omit"}
  field_spec="analytic"
else
  [ -x "$solve" ] || { echo "run_states_test.sh: solve_field not found: $solve" >&2; exit 2; }
  echo "== small solve: $solve"
  "$solve" --set output.mesh_vtu=true --set mesh.segments=32 --set mesh.h_magnet_mm=1.0 --set mesh.h_zone_mm=0.8 --set mesh.core_radius_mm=0 \
           --set mesh.h_air_mm=15 --set mesh.outer_radius_mm=40 --set mesh.sphere_subdivisions=2 \
           --set fem.order=1 --set fem.tolerance=1e-8 --set fem.progress_every=0 \
           --set grid.plane_step_mm=0.1 --set grid.box_step_mm=0.2 --out "$work/output/field"
  field_spec="grid:$work/output/field/plane.vti"
  [ -x "$steel" ] || { echo "run_states_test.sh: steel_parts not found: $steel" >&2; exit 2; }
  echo "== steel_parts study: $steel"
  "$steel" --config "$src/studies/steel_parts/steel_parts.toml" --out "$work/output/steel_parts"
fi

# 2. Probe paths of one mounting case (exaggerated so the picture shows it).
echo "== probe paths ($field_spec)"
"$helper" --field "$field_spec" --set mount.sx_mm=0.3 --set mount.dx_mm=0.2 --set sensor.steps=720 \
          --out "$work/output/probe_paths/paths_example.vtp"

# 3. States.
echo "== states"
"$pv" "$src/tests/paraview/check_states.py" --states "$src/paraview_states" \
      --data "$work/output" --images "$work/images"
