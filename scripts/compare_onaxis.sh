#!/usr/bin/env bash
# Proof that the on-axis outputs of a previous version are unchanged: error_spectrum's
# spectra of one build against another's on the same mounting cases (every array, every
# principle, the signal chain, magnetization errors, another magnet and gap, the linear
# model), and solve_field on meshes/coarse.toml (plane.vti and box.vti compared byte for
# byte, then read by error_spectrum --field fem:DIR).
#
#   scripts/compare_onaxis.sh OLD_BIN NEW_BIN WORK_DIR
#
# Columns present in both builds' CSVs are compared (a new version may add columns; they
# are listed). Prints one line per configuration with the largest absolute difference and
# exits 1 when any differs, a run fails or a VTI differs.
# Example: git worktree add /tmp/old v0.7.0-commit; (cd /tmp/old && scripts/build.sh);
#          scripts/compare_onaxis.sh /tmp/old/build/bin build/bin /tmp/onaxis
set -uo pipefail
[[ $# -eq 3 ]] || { echo "usage: $0 OLD_BIN NEW_BIN WORK_DIR" >&2; exit 2; }
old=$1; new=$2; w=$3
rm -rf "$w"; mkdir -p "$w"; status=0
printf '%s\n' sx_mm,sy_mm,dx_mm,dy_mm,dz_mm,tilt_x_deg,tilt_y_deg,magnet_tilt_deg,magnet_tilt_azimuth_deg \
  0,0,0,0,0,0,0,0,0 0.1,0,0,0,0,0,0,0,0 0,0.2,0,0,0,0,0,0,0 0,0,0.05,0,0,0,0,0,0 0,0,0,0.1,0,0,0,0,0 \
  0,0,0,0,0.3,0,0,0,0 0,0,0,0,-0.3,0,0,0,0 0,0,0,0,0,1,0,0,0 0,0,0,0,0,0,1,0,0 0,0,0,0,0,0,0,1,30 \
  0.1,-0.05,0.03,0.02,0.2,0.5,-0.5,0.5,120 > "$w/cases.csv"
cut -d, -f1-5 "$w/cases.csv" > "$w/cases_no_tilt.csv"   # the linear model has no tilts

compare() {   # compare OLD.csv NEW.csv NAME
  python3 - "$@" <<'PY' || status=1
import csv, math, sys
a = list(csv.DictReader(open(sys.argv[1]))); b = list(csv.DictReader(open(sys.argv[2])))
if len(a) != len(b): sys.exit(f"{sys.argv[3]}: {len(a)} rows against {len(b)}")
common = [k for k in a[0] if k in b[0]]; added = [k for k in b[0] if k not in a[0]]
worst = 0.0
for ra, rb in zip(a, b):
    for k in common:
        try: worst = max(worst, abs(float(ra[k]) - float(rb[k])))
        except ValueError: worst = worst if ra[k] == rb[k] else math.inf
print(f"{sys.argv[3]}: {len(a)} cases, {len(common)} columns, largest difference {worst:.3g}"
      + (f", new columns {added}" if added else ""))
sys.exit(0 if worst == 0 else 1)
PY
}

i=0
while read -r name args; do
  i=$((i + 1)); cases=$w/cases.csv; [[ $args == *linear* ]] && cases=$w/cases_no_tilt.csv
  for v in old new; do
    bin=$old; [[ $v == new ]] && bin=$new
    # shellcheck disable=SC2086
    "$bin/error_spectrum" --cases "$cases" $args --out "$w/${v}_$i.csv" > /dev/null 2> "$w/${v}_$i.err" \
      || { echo "$name: $v build failed: $(head -1 "$w/${v}_$i.err")"; status=1; }
  done
  [[ -f $w/old_$i.csv && -f $w/new_$i.csv ]] && compare "$w/old_$i.csv" "$w/new_$i.csv" "$name"
done <<'CASES'
two --array two
diff4 --array diff4
ring:8 --array ring:8
ring:3,r0_3mm --array ring:3 --r0 3
linear_model --field linear --array two
inplane --principle inplane --array point
xmr --principle xmr --array point
amr --principle amr --array point
signal_chain --array diff4 --set sensor.offset_cos_mT=1 --set sensor.gain_mismatch=0.02 --set sensor.phase_error_deg=1
magnetization_errors --array two --set magnet.magnetization_deg=3 --set magnet.magnetization_elevation_deg=2
R3mm,gap_1.5mm --array ring:4 --set sensor.plane_height_mm=1.5 --set magnet.radius_mm=3
CASES

here=$(cd "$(dirname "$0")/.." && pwd)
for v in old new; do
  bin=$old; [[ $v == new ]] && bin=$new
  "$bin/solve_field" --config "$here/meshes/coarse.toml" --set output.mesh_vtu=true --out "$w/fem_$v" \
    > /dev/null 2>&1 || { echo "solve_field: $v build failed"; status=1; }
done
for f in plane.vti box.vti; do
  if cmp -s "$w/fem_old/$f" "$w/fem_new/$f"; then echo "coarse mesh $f: byte-identical"
  else echo "coarse mesh $f: differs"; status=1; fi
done
for arr in two diff4 ring:8; do
  "$old/error_spectrum" --field "fem:$w/fem_old" --array "$arr" --cases "$w/cases.csv" --out "$w/fem_old_$arr.csv" > /dev/null 2>&1
  "$new/error_spectrum" --field "fem:$w/fem_new" --array "$arr" --cases "$w/cases.csv" --out "$w/fem_new_$arr.csv" > /dev/null 2>&1
  compare "$w/fem_old_$arr.csv" "$w/fem_new_$arr.csv" "fem:DIR $arr"
done
exit $status
