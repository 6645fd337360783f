#!/usr/bin/env bash
# The steel hollow shaft through a ring magnet (docs/studies/off_axis.md "The steel hollow shaft (FEM)"):
# solves the off_axis study's ring (R 16, Ri 11, L 4 mm, Br 1.2 T, mu_r 1.05) bare and with a steel tube
# through its bore (r 8..10.5 mm, z -40..10 mm), linear (mu_r 1000) and nonlinear (low_carbon_steel: the
# hot-rolled steel's B-H curve, materials/low_carbon_steel_hot_rolled_bh.csv), once
# for the side-shaft chip (inplane spot at [18, 0] on the mid-plane) and once for the bore arrays (r0 13.5 mm,
# 1 mm above the top face); writes the field on both read circles (field_at), the angle errors under single
# mount offsets (error_spectrum) and the figure docs/studies/off_axis_steel_shaft.png (gnuplot).
# Usage: scripts/ring_shaft_figure.sh [WORK_DIR]   (default /tmp/ring_shaft; solves already there are reused)
# Cost: 6 solves of 0.7-1.3M P2 tets (10-40 s each on 2 cores, the B-H ones a few minutes: Newton steps).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/bin
work=${1:-/tmp/ring_shaft}
mkdir -p "$work"
ring='[magnet]
radius_mm = 16.0
inner_radius_mm = 11.0
height_mm = 4.0
br_T = 1.2'
cat > "$work/side_es.toml" <<EOF
$ring
[sensor]
principle = "inplane"
array = "point"
center_mm = [18.0, 0.0]
plane_height_mm = -2.0
EOF
cat > "$work/bore_es.toml" <<EOF
$ring
[sensor]
principle = "bz"
array = "ring:8"
r0_mm = 13.5
plane_height_mm = 1.0
EOF
mesh='[mesh]
h_magnet_mm = 0.8
h_zone_mm = 0.4
core_radius_mm = 0.0
[fem]
order = 2
progress_every = 0
[output]
mesh_vtu = true'
for lay in side bore; do
  { cat "$work/${lay}_es.toml"; echo "$mesh"; } > "$work/$lay.toml"
done
tube() { echo "parts=[{name = \"hollow_shaft\", shape = \"tube\", r_inner_mm = 8.0, r_outer_mm = 10.5, z_min_mm = -40.0, z_max_mm = 10.0, material = \"$1\"}]"; }
solve() {  # layout, variant, extra --set arguments
  local dir="$work/${1}_$2"
  [ -f "$dir/solve.json" ] || "$bin/solve_field" --config "$work/$1.toml" "${@:3}" --out "$dir"
}
for lay in side bore; do
  solve "$lay" bare
  solve "$lay" steel --set "$(tube mu_r:1000)"
  solve "$lay" bh --set "$(tube low_carbon_steel)"
done
# The read circles (360 points): side r 18 mm on the mid-plane z = 0, bore r 13.5 mm at z = 3 mm.
python3 - "$work" <<'EOF'
import math, sys
for name, r, z in (("side", 18.0, 0.0), ("bore", 13.5, 3.0)):
    with open(f"{sys.argv[1]}/{name}_circle.csv", "w") as f:
        f.write("x_mm,y_mm,z_mm\n")
        for k in range(360):
            a = 2 * math.pi * k / 360
            f.write(f"{r * math.cos(a):.12g},{r * math.sin(a):.12g},{z:.12g}\n")
EOF
printf 'sx_mm,sy_mm,dx_mm,dy_mm,dz_mm\n0,0,0,0,0\n0,0,0.05,0,0\n0.2,0,0,0,0\n0,0,0,0,0.5\n' > "$work/side_cases.csv"
printf 'sx_mm,sy_mm,dx_mm,dy_mm,dz_mm\n0,0,0,0,0\n0.1,0,0,0,0\n0,0,0.1,0,0\n0,0,0,0,0.5\n' > "$work/bore_cases.csv"
side_keys=(--set sensor.direction=-1 --set sensor.zero_deg=180)
for v in analytic bare steel bh; do
  field=analytic
  [ "$v" = analytic ] || field="fem:$work/side_$v"
  "$bin/field_at" --config "$work/side_es.toml" --field "$field" --points "$work/side_circle.csv" --out "$work/side_field_$v.csv"
  "$bin/error_spectrum" --config "$work/side_es.toml" "${side_keys[@]}" --field "$field" --out "$work/side_raw_$v.csv"
  "$bin/error_spectrum" --config "$work/side_es.toml" "${side_keys[@]}" --set sensor.gain_trim=auto --field "$field" \
    --cases "$work/side_cases.csv" --out "$work/side_trim_$v.csv"
  [ "$v" = analytic ] || field="fem:$work/bore_$v"
  "$bin/field_at" --config "$work/bore_es.toml" --field "$field" --points "$work/bore_circle.csv" --out "$work/bore_field_$v.csv"
  for a in ring:8 diff4; do
    "$bin/error_spectrum" --config "$work/bore_es.toml" --array "$a" --field "$field" --cases "$work/bore_cases.csv" \
      --out "$work/bore_${a/:/}_$v.csv"
  done
done
# The figure: in-plane components beside the ring (radial, tangential) and Bz around the bore, per angle.
python3 - "$work" <<'EOF'
import csv, math, sys
w = sys.argv[1]
for lay in ("side", "bore"):
    for v in ("analytic", "bare", "steel", "bh"):
        rows = list(csv.DictReader(open(f"{w}/{lay}_field_{v}.csv")))
        with open(f"{w}/{lay}_plot_{v}.dat", "w") as f:
            for k, r in enumerate(rows):
                x, y = float(r["x_mm"]), float(r["y_mm"])
                bx, by, bz = (1e3 * float(r[c]) for c in ("Bx_T", "By_T", "Bz_T"))
                a = math.atan2(y, x)
                br, bt = bx * math.cos(a) + by * math.sin(a), -bx * math.sin(a) + by * math.cos(a)
                f.write(f"{k} {br:.9g} {bt:.9g} {bz:.9g}\n")
EOF
gnuplot <<EOF
set terminal pngcairo size 1200,900 font ",11"
set output "docs/studies/off_axis_steel_shaft.png"
set multiplot layout 2,2 title "Ring R 16 / Ri 11 / L 4 mm, magnetization along x: exact field, FEM bare, FEM with a steel hollow shaft through the bore (r 8-10.5 mm), linear and B-H"
set grid
set key bottom left font ",9"
set xrange [0:360]
set xtics 45
set xlabel "angle of the point on the read circle from the magnetization [deg]"
set title "beside the ring: r 18 mm, mid-plane, radial component"
set ylabel "B_r [mT]"
plot "$work/side_plot_analytic.dat" u 1:2 w l lw 3 lc rgb "#999999" t "exact (no steel)", \
     "$work/side_plot_bare.dat" u 1:2 w l lw 1.5 lc rgb "#1f77b4" t "FEM bare", \
     "$work/side_plot_steel.dat" u 1:2 w l lw 1.5 lc rgb "#d62728" t "FEM steel shaft, mu_r 1000", \
     "$work/side_plot_bh.dat" u 1:2 w l lw 1.5 dt 2 lc rgb "#2ca02c" t "FEM steel shaft, B-H (low-carbon steel)"
set title "beside the ring: r 18 mm, mid-plane, tangential component"
set ylabel "B_t [mT]"
plot "$work/side_plot_analytic.dat" u 1:3 w l lw 3 lc rgb "#999999" t "exact (no steel)", \
     "$work/side_plot_bare.dat" u 1:3 w l lw 1.5 lc rgb "#1f77b4" t "FEM bare", \
     "$work/side_plot_steel.dat" u 1:3 w l lw 1.5 lc rgb "#d62728" t "FEM steel shaft, mu_r 1000", \
     "$work/side_plot_bh.dat" u 1:3 w l lw 1.5 dt 2 lc rgb "#2ca02c" t "FEM steel shaft, B-H (low-carbon steel)"
set title "around the bore: r0 13.5 mm, 1 mm above the top face"
set ylabel "B_z [mT]"
plot "$work/bore_plot_analytic.dat" u 1:4 w l lw 3 lc rgb "#999999" t "exact (no steel)", \
     "$work/bore_plot_bare.dat" u 1:4 w l lw 1.5 lc rgb "#1f77b4" t "FEM bare", \
     "$work/bore_plot_steel.dat" u 1:4 w l lw 1.5 lc rgb "#d62728" t "FEM steel shaft, mu_r 1000", \
     "$work/bore_plot_bh.dat" u 1:4 w l lw 1.5 dt 2 lc rgb "#2ca02c" t "FEM steel shaft, B-H (low-carbon steel)"
set title "FEM with the shaft minus FEM bare"
set ylabel "change [mT]"
set key top right
plot "< paste $work/side_plot_steel.dat $work/side_plot_bare.dat" u 1:(\$2-\$6) w l lw 1.5 lc rgb "#d62728" t "side B_r, mu_r 1000", \
     "< paste $work/side_plot_steel.dat $work/side_plot_bare.dat" u 1:(\$3-\$7) w l lw 1.5 lc rgb "#ff7f0e" t "side B_t, mu_r 1000", \
     "< paste $work/bore_plot_steel.dat $work/bore_plot_bare.dat" u 1:(\$4-\$8) w l lw 1.5 lc rgb "#9467bd" t "bore B_z, mu_r 1000", \
     "< paste $work/side_plot_bh.dat $work/side_plot_bare.dat" u 1:(\$2-\$6) w l lw 1.5 dt 2 lc rgb "#2ca02c" t "side B_r, B-H", \
     "< paste $work/side_plot_bh.dat $work/side_plot_bare.dat" u 1:(\$3-\$7) w l lw 1.5 dt 2 lc rgb "#8c564b" t "side B_t, B-H", \
     "< paste $work/bore_plot_bh.dat $work/bore_plot_bare.dat" u 1:(\$4-\$8) w l lw 1.5 dt 2 lc rgb "#17becf" t "bore B_z, B-H"
unset multiplot
EOF
echo "wrote docs/studies/off_axis_steel_shaft.png; tables in $work"
