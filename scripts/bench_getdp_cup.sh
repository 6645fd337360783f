#!/usr/bin/env bash
# Benchmark: magenc's FEM against GetDP 3.2 with the steel_parts study's steel cup around the
# default magnet (docs/fem.md, "Steel cup against GetDP"). The problem, the same for both:
# magnet R = 2 mm, L = 4 mm, Br = 1.2 T along x, mu_r 1.05 (magenc's default, the study's);
# cup bore r 2.0 mm on the magnet's curved face, wall and base 0.5 mm, rim 0.5 mm below the
# magnet's top face (r 2.0..2.5 mm, z -2.5..1.5 mm, base z -2.5..-2.0), touching the magnet;
# air sphere of 40 mm with the dipole Robin condition; total scalar potential, P2.
#   linear: the cup's mu_r is magenc's structural_steel (read back from its solve.json);
#   bh:     the cup follows materials/structural_steel_bh.csv (magenc: bh:FILE, Newton;
#           GetDP: the same table through magenc's monotone cubic, resampled by
#           scripts/bench_getdp/bh_table.py, Newton with the exact tangent), both to
#           |R|/|f| < 1e-6.
#   GetDP: gmsh meshes scripts/bench_getdp/cup.geo (curved 10-node tets, h in the magnet and the
#          cup and in the sensing-plane box), getdp solves scripts/bench_getdp/cup.pro (CG + PETSc
#          GAMG, relative residual 1e-10) and prints Bz on the grid.
#   magenc: solve_field with [[parts]] (meshes/coarse.toml with mesh.h_magnet_mm = mesh.h_zone_mm
#          = h, 64 segments, symmetry order 8, h_air 12 mm), field_at --field fem:DIR on the grid;
#          one solve per h of --magenc-h (a refinement pair shows magenc's own discretization change).
# Bz on the grid -half..half mm (step) of the sensing plane z = 4.55 mm; differences are RMS and
# max over the grid in % of GetDP's peak |Bz| there. Times: wall and CPU of whole processes
# (GetDP: gmsh + getdp incl. its grid output; magenc: solve_field + field_at), OMP_NUM_THREADS=1,
# pinned to core 0 when taskset exists.
#
# Usage: scripts/bench_getdp_cup.sh [--case linear|bh|both] [--getdp-h MM] [--magenc-h MM,MM]
#                                  [--half MM] [--step MM] [--bin DIR] [--work DIR] [--reuse-getdp]
#                                  [--no-getdp] [--scale-air]
#   --scale-air: magenc's air mesh size follows h (h_air = 15 h instead of 12 mm), so a refinement
#   refines every region (with h_air fixed the air between the magnet and the plane stays coarse
#   and the changes stall at ~0.2 % RMS).
#   --reuse-getdp: keep a finished GetDP solve of the same case and h in --work (its bz.txt, logs
#   and times) and run only magenc against it.
#   --no-getdp: magenc alone (no getdp or gmsh needed). With three or more --magenc-h values
#   (either mode) a refinement table follows: the change between successive meshes and the
#   observed order p = ln(d_i / d_i+1) / ln(h_i / h_i+1) of those changes (d: RMS change).
#   defaults: --case both --getdp-h 0.25 --magenc-h 0.5,0.3 --half 4 --step 0.2
#             --bin build/bin --work output/bench_getdp_cup
# Needs getdp, gmsh (scripts/install_deps.sh --with-getdp), python3, and solve_field, field_at.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
case_=both
getdp_h=0.25
magenc_h=0.5,0.3
half=4
step=0.2
bin=build/bin
work=output/bench_getdp_cup
reuse=0
nogetdp=0
scale_air=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --case) case_=$2; shift 2 ;;
    --getdp-h) getdp_h=$2; shift 2 ;;
    --magenc-h) magenc_h=$2; shift 2 ;;
    --half) half=$2; shift 2 ;;
    --step) step=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --reuse-getdp) reuse=1; shift ;;
    --no-getdp) nogetdp=1; shift ;;
    --scale-air) scale_air=1; shift ;;
    -h|--help) sed -n '2,30p' "$0"; exit 0 ;;
    *) echo "bench_getdp_cup.sh: unknown argument $1 (allowed --case, --getdp-h, --magenc-h, --half, --step, --bin, --work, --reuse-getdp, --no-getdp, --scale-air)" >&2; exit 2 ;;
  esac
done
case $case_ in
  linear) cases=(linear) ;; bh) cases=(bh) ;; both) cases=(linear bh) ;;
  *) echo "bench_getdp_cup.sh: --case $case_ must be one of linear, bh, both" >&2; exit 2 ;;
esac
positive='^[0-9]*\.?[0-9]+$'
for v in "$getdp_h" "$half" "$step" ${magenc_h//,/ }; do
  [[ $v =~ $positive ]] && awk -v v="$v" 'BEGIN{exit !(v > 0)}' || {
    echo "bench_getdp_cup.sh: $v (--getdp-h, --magenc-h, --half, --step) must be a positive number (mm)" >&2; exit 2; }
done
tools=(python3); [[ $nogetdp == 1 ]] || tools+=(getdp gmsh)
for t in "${tools[@]}"; do
  command -v $t >/dev/null || { echo "bench_getdp_cup.sh: $t not found (scripts/install_deps.sh --with-getdp)" >&2; exit 2; }
done
bin=$(cd "$bin" 2>/dev/null && pwd) || { echo "bench_getdp_cup.sh: --bin directory not found" >&2; exit 2; }
for t in solve_field field_at; do
  [[ -x $bin/$t ]] || { echo "bench_getdp_cup.sh: $bin/$t not found: run scripts/build.sh first" >&2; exit 2; }
done
mkdir -p "$work"
work=$(cd "$work" && pwd)
pin=(); command -v taskset >/dev/null && pin=(taskset -c 0)
export OMP_NUM_THREADS=1
tv() { /usr/bin/time -f "%e %U %S %M" -o "$1" "${@:2}"; }  # wall user sys maxrss_kb
wall_cpu() { awk '{printf "%.1f %.1f\n", $1, $2 + $3}' "$@" | awk '{w += $1; c += $2} END {printf "%.1f %.1f\n", w, c}'; }
bh_csv=materials/structural_steel_bh.csv
mu_magnet=1.05

# The grid, in GetDP's OnGrid order (x outer, y inner), as field_at's points file.
awk -v h="$half" -v s="$step" 'BEGIN {print "x_mm,y_mm,z_mm"; n = int(2 * h / s + 0.5);
  for (i = 0; i <= n; ++i) for (j = 0; j <= n; ++j) printf "%.6f,%.6f,4.55\n", -h + i * s, -h + j * s}' > "$work/points.csv"
npts=$(( $(wc -l < "$work/points.csv") - 1 ))

# GetDP's bz.txt (x y z bz, blank lines between rows) -> "x,y,bz" with the same rounding as points.csv.
getdp_xyb() { awk 'NF >= 4 {printf "%.6f,%.6f,%.17g\n", $1, $2, $4}' "$1"; }
# field_at's CSV -> "x,y,bz".
magenc_xyb() { awk -F, 'NR > 1 {printf "%.6f,%.6f,%.17g\n", $1, $2, $6}' "$1"; }
# diff A B (x,y,bz files, same points): "rms_% max_% peakA_mT peakB_mT n" in % of A's peak |Bz|.
diff_pct() {
  awk -F, 'NR == FNR {a[$1 "," $2] = $3; next}
    ($1 "," $2) in a {d = $3 - a[$1 "," $2]; s += d * d; if (d < 0) d = -d; if (d > mx) mx = d; ++n;
      v = a[$1 "," $2]; if (v < 0) v = -v; if (v > pa) pa = v; w = $3; if (w < 0) w = -w; if (w > pb) pb = w}
    END {if (n == 0) {print "nan nan nan nan 0"; exit}
      printf "%.3f %.3f %.3f %.3f %d\n", 100 * sqrt(s / n) / pa, 100 * mx / pa, 1000 * pa, 1000 * pb, n}' "$1" "$2"
}

summary=()
for c in "${cases[@]}"; do
  echo "== case $c ==" >&2
  # magenc first: its resolved linear mu_r is GetDP's.
  if [[ $c == linear ]]; then material=structural_steel; else material="bh:$root/$bh_csv"; fi
  part="parts=[{name = \"cup\", shape = \"cup\", r_inner_mm = 2.0, r_outer_mm = 2.5, z_min_mm = -2.5, z_max_mm = 1.5, base_mm = 0.5, material = \"$material\"}]"
  mags=()
  for h in ${magenc_h//,/ }; do
    md=$work/magenc_${c}_h$h
    mkdir -p "$md"
    h_air=12; [[ $scale_air == 1 ]] && h_air=$(awk -v h="$h" 'BEGIN {printf "%.4g", 15 * h}')
    echo "magenc: h = $h mm (h_air $h_air mm) ..." >&2
    tv "$md/t_solve.txt" "${pin[@]}" "$bin/solve_field" --config meshes/coarse.toml --set fem.order=2 --set fem.potential=total \
        --set fem.nonlinear_method=newton --set fem.threads=1 --set magnet.mu_r=$mu_magnet --set mesh.segments=64 \
        --set mesh.symmetry_order=8 --set mesh.h_air_mm=$h_air --set mesh.h_magnet_mm=$h --set mesh.h_zone_mm=$h \
        --set output.mesh_vtu=true --set "$part" --out "$md/field" > "$md/solve.log" 2>&1 \
      || { echo "bench_getdp_cup.sh: solve_field failed (see $md/solve.log)" >&2; exit 1; }
    tv "$md/t_at.txt" "${pin[@]}" "$bin/field_at" --field "fem:$md/field" --points "$work/points.csv" --out "$md/bz.csv" \
        > "$md/field_at.log" 2>&1 || { echo "bench_getdp_cup.sh: field_at failed (see $md/field_at.log)" >&2; exit 1; }
    magenc_xyb "$md/bz.csv" > "$md/xyb.csv"
    mags+=("$h")
  done
  md0=$work/magenc_${c}_h${mags[0]}
  mu_steel=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['parts'][0]['mu_r'])" "$md0/field/solve.json")

  if [[ $nogetdp == 0 ]]; then
  gd=$work/getdp_${c}_h$getdp_h
  mkdir -p "$gd"
  if [[ $reuse == 1 && -s $gd/bz.txt && -s $gd/t_getdp.txt && -s $gd/t_gmsh.txt ]]; then
    echo "GetDP: reusing $gd" >&2
  else
  cp scripts/bench_getdp/cup.geo scripts/bench_getdp/cup.pro "$gd/"
  bhflag=0
  if [[ $c == bh ]]; then python3 scripts/bench_getdp/bh_table.py "$bh_csv" "$gd/bh_table.pro"; bhflag=1; fi
  echo "GetDP: meshing (gmsh, h = $getdp_h mm) and solving ..." >&2
  (cd "$gd" && tv t_gmsh.txt "${pin[@]}" gmsh -3 cup.geo -nt 1 -setnumber h_zone "$getdp_h" -setnumber h_magnet "$getdp_h" \
      -o mesh.msh > gmsh.log 2>&1)
  (cd "$gd" && rm -f bz.txt && tv t_getdp.txt "${pin[@]}" getdp cup.pro -msh mesh.msh -setnumber bh $bhflag \
      -setnumber mu_steel "$mu_steel" -setnumber mu_magnet $mu_magnet -setnumber half "$half" -setnumber step "$step" \
      -solve MagSta -pos Bz -ksp_type cg -pc_type gamg -ksp_rtol 1e-10 -v 3 > getdp.log 2>&1)
  [[ -s $gd/bz.txt ]] || { echo "bench_getdp_cup.sh: GetDP wrote no bz.txt (see $gd/getdp.log)" >&2; exit 1; }
  fi
  getdp_xyb "$gd/bz.txt" > "$gd/xyb.csv"
  read -r gw gc < <(wall_cpu "$gd/t_gmsh.txt" "$gd/t_getdp.txt")
  gdofs=$(grep -o '[0-9]* Dofs' "$gd/getdp.log" | head -1 | cut -d' ' -f1)
  giter=$(grep -o 'nonlinear done: [0-9]* iterations, |R|/|f| = [0-9.e+-]*' "$gd/getdp.log" | sed 's/nonlinear done: //' || true)
  gbmax=$(awk '{for (i = 13; i <= 16; ++i) if ($i > m) m = $i} END {printf "%.2f", m}' "$gd/cup_bnorm.txt")
  echo "GetDP: largest |B| at the cup's mesh vertices (per-element values) $gbmax T" >&2

  echo
  echo "Steel cup, $c (mu_r $([[ $c == linear ]] && echo "$mu_steel" || echo "B-H $bh_csv")): Bz on the $npts points -$half..$half mm (step $step) of z = 4.55 mm"
  printf '%-8s | %-6s | %-9s | %-30s | %8s | %8s | %-12s | %s\n' solver "h mm" DOFs "nonlinear iterations, |R|/|f|" "wall s" "CPU s" "peak|Bz| mT" "vs GetDP: RMS / max % of GetDP peak"
  read -r _ _ gpk _ _ < <(diff_pct "$gd/xyb.csv" "$gd/xyb.csv")
  printf '%-8s | %-6s | %-9s | %-30s | %8s | %8s | %-12s | %s\n' GetDP "$getdp_h" "$gdofs" "${giter:--}" "$gw" "$gc" "$gpk" "-"
  for h in "${mags[@]}"; do
    md=$work/magenc_${c}_h$h
    read -r mw mc < <(wall_cpu "$md/t_solve.txt" "$md/t_at.txt")
    read -r mdofs miter mres < <(python3 -c "
import json, sys
j = json.load(open(sys.argv[1]))
r = j.get('nonlinear_residuals') or []
print(j.get('dofs', '?'), j.get('nonlinear_iterations') or '-', ('%.1e' % r[-1]) if r else '-')" "$md/field/solve.json")
    read -r rms mx _ mpk n < <(diff_pct "$gd/xyb.csv" "$md/xyb.csv")
    printf '%-8s | %-6s | %-9s | %-30s | %8s | %8s | %-12s | %s\n' magenc "$h" "$mdofs" "$miter, $mres" "$mw" "$mc" "$mpk" "$rms / $mx ($n points)"
    summary+=("$c|$h|$rms|$mx")
  done
  fi
  if (( ${#mags[@]} >= 3 )); then
    echo "Refinement, $c: RMS / max change between successive meshes in % of the finer one's peak, observed order p"
    prev=
    for ((i = 0; i + 1 < ${#mags[@]}; ++i)); do
      ha=${mags[i]}; hb=${mags[i + 1]}
      read -r rms mx _ _ _ < <(diff_pct "$work/magenc_${c}_h$hb/xyb.csv" "$work/magenc_${c}_h$ha/xyb.csv")
      p=-
      [[ -n $prev ]] && p=$(awk -v d1="$prev" -v d2="$rms" -v h1="$hp" -v h2="$ha" 'BEGIN {printf "%.2f", log(d1 / d2) / log(h1 / h2)}')
      printf '  h %s -> %s mm: %s / %s %%, p %s\n' "$ha" "$hb" "$rms" "$mx" "$p"
      prev=$rms; hp=$ha
    done
    echo "Against the finest mesh (h ${mags[-1]} mm): RMS / max % of its peak, peak |Bz| mT"
    for h in "${mags[@]::${#mags[@]}-1}"; do
      read -r rms mx _ pk _ < <(diff_pct "$work/magenc_${c}_h${mags[-1]}/xyb.csv" "$work/magenc_${c}_h$h/xyb.csv")
      printf '  h %s mm: %s / %s %%, peak %s\n' "$h" "$rms" "$mx" "$pk"
    done
  fi
  if (( ${#mags[@]} >= 2 )); then
    read -r rms mx _ _ n < <(diff_pct "$work/magenc_${c}_h${mags[-1]}/xyb.csv" "$work/magenc_${c}_h${mags[0]}/xyb.csv")
    echo "magenc's own change h ${mags[0]} -> ${mags[-1]} mm: RMS $rms % / max $mx % of the finer solve's peak"
  fi
done
echo "(outputs and logs in $work; load $(cut -d' ' -f1 /proc/loadavg))"
