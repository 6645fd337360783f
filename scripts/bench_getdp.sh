#!/usr/bin/env bash
# Benchmark: GetDP 3.2 and magenc on the same problem, one core each, time and
# accuracy side by side (docs/fem.md). The problem: the default magnet (R = 2 mm,
# L = 4 mm, Br = 1.2 T along x, mu_r = 1) in an air sphere of 60 mm with the
# dipole Robin condition; Bz on the 81 x 81 grid -4..4 mm (step 0.1 mm) of the
# sensing plane z = 4.55 mm, compared with the exact field (magenc's
# AnalyticField, through fem_vs_exact --other-bz): RMS and max error in % of
# the peak |Bz| on the grid.
#
#   GetDP: gmsh meshes scripts/bench_getdp/magnet.geo with curved second-order
#          tets (h in the magnet and in the sensing-plane box), GetDP solves
#          scripts/bench_getdp/magnet.pro (isoparametric P2, CG + PETSc GAMG,
#          relative residual 1e-8) and prints Bz on the grid.
#   magenc: fem_vs_exact with mesh.h_zone_mm = mesh.h_core_mm = mesh.h_magnet_mm
#          = the magenc h (its mesh pipeline: D16-symmetric quadrant solve,
#          P2, the default solver and tolerance, fem.potential = total: with
#          mu_r = 1 the default reduced potential would be the exact field).
# Times are wall and CPU (user + sys) of whole processes (GetDP: gmsh + getdp;
# magenc: mesh, assembly, solve, post and the error grid), pinned to one core
# (taskset) with OMP_NUM_THREADS=1. Under load the ratio stays meaningful
# only if both run under the same load; the CPU-time ratio is the robust one.
#
# Usage: scripts/bench_getdp.sh [--getdp-h MM] [--magenc-h MM[,MM...]] [--work DIR]
#   defaults: --getdp-h 0.25 --magenc-h 0.5 --work output/bench_getdp
# Needs build/bin/fem_vs_exact (scripts/build.sh) and, for the GetDP half,
# the Debian packages getdp and gmsh (scripts/install_deps.sh --with-getdp);
# without them only magenc runs.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
getdp_h=0.25
magenc_h=0.5
work=output/bench_getdp
while [[ $# -gt 0 ]]; do
  case "$1" in
    --getdp-h) getdp_h=$2; shift 2 ;;
    --magenc-h) magenc_h=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    -h|--help) sed -n '2,28p' "$0"; exit 0 ;;
    *) echo "bench_getdp.sh: unknown argument $1 (allowed --getdp-h, --magenc-h, --work)" >&2; exit 2 ;;
  esac
done
positive='^[0-9]*\.?[0-9]+$'
[[ $getdp_h =~ $positive ]] || { echo "bench_getdp.sh: --getdp-h $getdp_h must be a positive number (mm)" >&2; exit 2; }
for h in ${magenc_h//,/ }; do
  [[ $h =~ $positive ]] || { echo "bench_getdp.sh: --magenc-h $h must be a positive number (mm)" >&2; exit 2; }
done
fve=$root/build/bin/fem_vs_exact
[[ -x $fve ]] || { echo "bench_getdp.sh: $fve not found: run scripts/build.sh first" >&2; exit 2; }
mkdir -p "$work"
work=$(cd "$work" && pwd)
pin=(); command -v taskset >/dev/null && pin=(taskset -c 0)
export OMP_NUM_THREADS=1
tv() { /usr/bin/time -f "%e %U %S %M" -o "$1" "${@:2}"; }  # wall user sys maxrss_kb
fmt_time() { awk '{printf "%.1f %.1f %.0f\n", $1, $2 + $3, $4 / 1024}' "$1"; }

rows=()
getdp_ok=0
if command -v getdp >/dev/null && command -v gmsh >/dev/null; then
  getdp_ok=1
  gd=$work/getdp_h$getdp_h
  mkdir -p "$gd"
  cp scripts/bench_getdp/magnet.geo scripts/bench_getdp/magnet.pro "$gd/"
  echo "GetDP: meshing (gmsh, h = $getdp_h mm) and solving ..." >&2
  (cd "$gd" && tv t_gmsh.txt "${pin[@]}" gmsh -3 magnet.geo -nt 1 -setnumber h_zone "$getdp_h" -setnumber h_magnet "$getdp_h" \
      -o mesh.msh > gmsh.log 2>&1)
  (cd "$gd" && rm -f bz.txt && tv t_getdp.txt "${pin[@]}" getdp magnet.pro -msh mesh.msh -solve MagSta -pos Bz \
      -ksp_type cg -pc_type gamg -ksp_rtol 1e-8 -v 3 > getdp.log 2>&1)
  [[ -s $gd/bz.txt ]] || { echo "bench_getdp.sh: GetDP wrote no bz.txt (see $gd/getdp.log)" >&2; exit 1; }
  read -r w1 c1 m1 < <(fmt_time "$gd/t_gmsh.txt")
  read -r w2 c2 m2 < <(fmt_time "$gd/t_getdp.txt")
  gdofs=$(grep -o '[0-9]* Dofs' "$gd/getdp.log" | head -1 | cut -d' ' -f1)
  getdp_wall=$(awk -v a="$w1" -v b="$w2" 'BEGIN{printf "%.1f", a + b}')
  getdp_cpu=$(awk -v a="$c1" -v b="$c2" 'BEGIN{printf "%.1f", a + b}')
  getdp_mem=$(( m1 > m2 ? m1 : m2 ))
  # Its accuracy through the same exact field (a tiny magenc solve carries the comparison).
  "$fve" --plane-half-mm 4 --plane-step-mm 0.1 --other-bz "$gd/bz.txt" --config meshes/coarse.toml magnet.mu_r=1 \
      > "$gd/accuracy.txt"
  read -r grms gmax < <(awk '/^other/ {for (i = 1; i <= NF; ++i) {split($i, kv, "="); if (kv[1] == "rms_rel") r = kv[2]; if (kv[1] == "max_rel") m = kv[2]} printf "%.4f %.3f\n", 100 * r, 100 * m}' "$gd/accuracy.txt")
  rows+=("GetDP 3.2 (gmsh + getdp)|h $getdp_h mm, $gdofs DOFs (P2, whole domain)|$getdp_wall|$getdp_cpu|$getdp_mem|$grms|$gmax")
else
  echo "bench_getdp.sh: getdp or gmsh not installed (scripts/install_deps.sh --with-getdp): magenc only" >&2
fi

for h in ${magenc_h//,/ }; do
  echo "magenc: h = $h mm ..." >&2
  out=$work/magenc_h$h.txt
  tv "$work/t_magenc_h$h.txt" "${pin[@]}" "$fve" --plane-half-mm 4 --plane-step-mm 0.1 magnet.mu_r=1 fem.potential=total fem.threads=1 \
      fem.progress_every=0 mesh.h_zone_mm="$h" mesh.h_core_mm="$h" mesh.h_magnet_mm="$h" > "$out"
  read -r w c m < <(fmt_time "$work/t_magenc_h$h.txt")
  read -r dofs solved < <(awk '/^P2 el=/ {for (i = 1; i <= NF; ++i) {split($i, kv, "="); if (kv[1] == "dofs") d = kv[2]}} END {print d}' "$out")
  read -r mrms mmax < <(awk '/^grid / {for (i = 1; i <= NF; ++i) {split($i, kv, "="); if (kv[1] == "rms_rel") r = kv[2]; if (kv[1] == "max_rel") x = kv[2]} printf "%.4f %.3f\n", 100 * r, 100 * x}' "$out")
  rows+=("magenc $(git describe --always --dirty 2>/dev/null || echo '?')|h $h mm, $dofs DOFs (P2, quadrant solved)|$w|$c|$m|$mrms|$mmax")
done

echo
echo "Bz on the 81 x 81 grid -4..4 mm of the sensing plane vs the exact field, mu_r = 1, one core ($(nproc --all) on this machine, load $(cut -d' ' -f1 /proc/loadavg))"
printf '%-28s | %-42s | %8s | %8s | %8s | %10s | %10s\n' solver mesh "wall s" "CPU s" "RSS MiB" "RMS % pk" "max % pk"
for r in "${rows[@]}"; do
  IFS='|' read -r a b c d e f g <<< "$r"
  printf '%-28s | %-42s | %8s | %8s | %8s | %10s | %10s\n' "$a" "$b" "$c" "$d" "$e" "$f" "$g"
done
if [[ $getdp_ok == 1 ]]; then
  for r in "${rows[@]:1}"; do
    IFS='|' read -r a b c d e f g <<< "$r"
    awk -v gw="$getdp_wall" -v gc="$getdp_cpu" -v mw="$c" -v mc="$d" -v b="$b" -v gr="$grms" -v mr="$f" \
      'BEGIN {printf "GetDP / magenc (%s): wall %.1fx, CPU %.1fx; RMS error GetDP %.4f %% vs magenc %.4f %% of peak\n", b, gw / mw, gc / mc, gr, mr}'
  done
fi
echo "(outputs and logs in $work)"
