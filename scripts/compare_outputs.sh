#!/usr/bin/env bash
# Proof that a refactoring leaves study outputs unchanged: run the studies with
# one build, run them again with another, and compare every output file.
#
#   scripts/compare_outputs.sh run  BIN_DIR OUT_ROOT FIELD_DIR [--quick]
#       runs linear_model, exact_field, real_field, airgap, harmonic_provenance,
#       error_sources, radius and diagnosis with small configurations (suffix
#       _small) and, unless --quick, the first four's
#       default configurations (suffix _default) into OUT_ROOT/<study>_<size>.
#       FIELD_DIR is a solve_field output directory of the default magnet, e.g.
#         build/bin/solve_field --config meshes/coarse.toml --out /tmp/field
#   scripts/compare_outputs.sh diff OUT_ROOT_A OUT_ROOT_B [--tol REL]
#       compares every file of every run folder: CSV, summary.md, config.toml and
#       plot data (.dat, .gp) byte for byte, except what is run metadata:
#         run.json                        (version, git revision, date, wall time)
#         in summary.md, times: harmonic_provenance's in-process solves ("solve s"),
#         columns headed "[s]", diagnosis's fit times, "wall time N s"
#       PNGs are compared too but listed separately (gnuplot output).
#       With --tol REL, a file whose bytes differ still matches when only its numbers
#       differ, each within REL of its column's scale (tables) or within REL or the
#       last printed digit (summary.md): scripts/compare_numbers.py. This is the check
#       for builds whose floating-point code differs (compiler flags, summation order).
#       Exit 0 when everything matches, 1 otherwise.
#
# Example (before/after a change, same FIELD_DIR for both):
#   git stash; scripts/build.sh; cp -r build/bin /tmp/bin_before; git stash pop; scripts/build.sh
#   scripts/compare_outputs.sh run /tmp/bin_before /tmp/out_before /tmp/field
#   scripts/compare_outputs.sh run build/bin /tmp/out_after /tmp/field
#   scripts/compare_outputs.sh diff /tmp/out_before /tmp/out_after
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,28p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }

run_one() {  # bin out_root name study args...
  local bin=$1 root=$2 name=$3 study=$4
  shift 4
  echo "== $name: $study $*" >&2
  rm -rf "${root:?}/$name"
  "$bin/$study" --out "$root/$name" "$@" >"$root/$name.log" 2>&1 || {
    echo "FAILED: $study (see $root/$name.log)" >&2
    return 1
  }
}

cmd_run() {
  [[ $# -ge 3 ]] || usage
  local bin root field quick=0
  bin=$(realpath "$1"); root=$2; field=$(realpath "$3")
  [[ ${4:-} == --quick ]] && quick=1
  mkdir -p "$root"
  root=$(realpath "$root")
  local coarse; coarse=$(realpath meshes/coarse.toml)
  local fem=(--set "fem_field.dir=$field")

  run_one "$bin" "$root" linear_model_small linear_model --config studies/linear_model/linear_model.toml \
    --set sensor.steps=360 --set sweep.points=6 --set sweep.offsets=sx_mm,dx_mm,dz_mm
  run_one "$bin" "$root" exact_field_small exact_field --config studies/exact_field/exact_field.toml \
    --set sensor.steps=360 --set sweep.points=6 --set dz_sweep.points=5 --set study.arrays=two,ring:5
  run_one "$bin" "$root" real_field_small real_field --config studies/real_field/real_field.toml "${fem[@]}" \
    --set sensor.steps=360 --set sweep.points=6 --set study.arrays=two,diff4
  run_one "$bin" "$root" airgap_small airgap --config studies/airgap/airgap.toml "${fem[@]}" \
    --set sensor.steps=360 --set dz_sweep.points=5 --set study.arrays=two,diff4
  run_one "$bin" "$root" harmonic_provenance_small harmonic_provenance \
    --config studies/harmonic_provenance/harmonic_provenance.toml --set sensor.steps=360 \
    --set provenance.spacings_mm=0.2,0.1 --set provenance.interps=nearest,cubic \
    --set "provenance.fem_variants=[{ label = \"coarse P1\", config = \"$coarse\", set = { fem.order = 1 } }]" \
    --set "provenance.fem_dirs=$field"
  # The 0.6.0 sources of error_sources (later sources add files, not changes).
  run_one "$bin" "$root" error_sources_small error_sources --set study.arrays=two,diff4,ring:8 \
    --set study.sources=tilt_x_deg,tilt_y_deg,magnet_tilt_deg,magnetization_elevation_deg,offset_cos_mT,offset_sin_mT,gain_mismatch,phase_error_deg \
    --set sweep.points=4 --set sensor.steps=360
  run_one "$bin" "$root" radius_small radius --config studies/radius/radius.toml --set radius.fem_dir= \
    --set radius.r0_min_mm=1.5 --set radius.r0_max_mm=2.5 --set radius.r0_step_mm=0.25 --set radius.samples=500 \
    --set sensor.steps=720
  run_one "$bin" "$root" diagnosis_small diagnosis --config studies/diagnosis/diagnosis.toml "${fem[@]}" \
    --set roundtrip.cases=4 --set roundtrip.fem_cases=2 --set roundtrip.all_free_cases=1
  # No FE variants and no directories: the FE section is absent.
  run_one "$bin" "$root" harmonic_provenance_nofe harmonic_provenance \
    --config studies/harmonic_provenance/harmonic_provenance.toml --set sensor.steps=360 \
    --set provenance.spacings_mm=0.2,0.1,0.05 --set provenance.fem_variants= \
    --set provenance.fem_grid_interp=none
  [[ $quick == 1 ]] && return 0
  run_one "$bin" "$root" linear_model_default linear_model --config studies/linear_model/linear_model.toml
  run_one "$bin" "$root" exact_field_default exact_field --config studies/exact_field/exact_field.toml
  run_one "$bin" "$root" real_field_default real_field --config studies/real_field/real_field.toml "${fem[@]}"
  run_one "$bin" "$root" airgap_default airgap --config studies/airgap/airgap.toml "${fem[@]}"
}

# summary.md with the run's times blanked: table columns headed "solve s" or "... [s]"
# (harmonic_provenance's in-process solves, radius's timing table), diagnosis's fit times
# ("fit 0.401 s mean, 0.503 s max") and "wall time 20.5 s".
normalized() {
  python3 - "$1" <<'EOF'
import re
import sys
cols = None
for line in open(sys.argv[1], encoding="utf-8"):
    line = re.sub(r"fit [0-9.]+ s mean, [0-9.]+ s max", "fit <time>", line.rstrip("\n"))
    line = re.sub(r"wall time [0-9.]+ s", "wall time <time>", line)
    if line.startswith("|"):
        cells = line.split("|")
        if cols is None:
            cols = [i for i, c in enumerate(cells) if c.strip() == "solve s" or c.strip().endswith("[s]")]
        elif not all(set(c.strip()) <= set("-:") for c in cells[1:-1]):
            for i in cols:
                if i < len(cells):
                    cells[i] = " <time> "
        line = "|".join(cells)
    else:
        cols = None
    print(line)
EOF
}

# Files $1 and $2 differ in bytes: with a tolerance, do they agree in numbers? ($3: label)
# On a failure the differences are left in $num_out (printed after the file's name).
numbers_agree() {
  num_out=""
  [[ -n $tol ]] || return 1
  local out
  if out=$(python3 scripts/compare_numbers.py "$1" "$2" --rel "$tol"); then
    echo "numbers agree: $3:$out"; return 0
  fi
  num_out=$out; return 1
}

cmd_diff() {
  [[ $# -eq 2 || ( $# -eq 4 && $3 == --tol ) ]] || usage
  local a=$1 b=$2 bad=0 same=0 close=0 png_diff=0 tol=${4:-}
  for da in "$a"/*/; do
    local name; name=$(basename "$da")
    local db="$b/$name"
    if [[ ! -d $db ]]; then echo "MISSING in $b: $name"; bad=1; continue; fi
    # Same file names on both sides.
    if ! diff <(cd "$da" && ls) <(cd "$db" && ls) >/dev/null; then
      echo "FILES DIFFER in $name:"; diff <(cd "$da" && ls) <(cd "$db" && ls) || true; bad=1
    fi
    # (diff exits 1 on a difference: "|| true" below keeps set -e from ending the comparison at the first one.)
    for fa in "$da"*; do
      local f; f=$(basename "$fa")
      local fb="$db/$f"
      [[ -f $fb ]] || continue
      case $f in
        run.json) continue ;;
        *.png)
          if ! cmp -s "$fa" "$fb"; then echo "png differs: $name/$f"; png_diff=1; fi
          continue ;;
        summary.md)
          local tmp; tmp=$(mktemp -d)
          normalized "$fa" >"$tmp/a.md"; normalized "$fb" >"$tmp/b.md"
          if cmp -s "$tmp/a.md" "$tmp/b.md"; then same=$((same + 1))
          elif numbers_agree "$tmp/a.md" "$tmp/b.md" "$name/$f"; then close=$((close + 1))
          else echo "DIFFERS: $name/$f"; if [[ -n $tol ]]; then echo "$num_out"; else diff "$tmp/a.md" "$tmp/b.md" | head -20 || true; fi; bad=1; fi
          rm -rf "$tmp" ;;
        *)
          if cmp -s "$fa" "$fb"; then same=$((same + 1))
          elif numbers_agree "$fa" "$fb" "$name/$f"; then close=$((close + 1))
          else echo "DIFFERS: $name/$f"; if [[ -n $tol ]]; then echo "$num_out"; else diff "$fa" "$fb" | head -20 || true; fi; bad=1; fi ;;
      esac
    done
  done
  echo "compare_outputs: $same files identical (CSV, summary.md, config.toml, plot data)" \
       "$([[ -n $tol ]] && echo "; $close equal in numbers within $tol")" \
       "$([[ $png_diff == 0 ]] && echo '; PNGs identical' || echo '; some PNGs differ (listed above)')"
  [[ $bad == 0 ]] && echo "compare_outputs: OK, no differences" || echo "compare_outputs: DIFFERENCES found"
  return $bad
}

case ${1:-} in
  run) shift; cmd_run "$@" ;;
  diff) shift; cmd_diff "$@" ;;
  *) usage ;;
esac
