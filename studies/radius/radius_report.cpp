#include "studies/radius/radius_report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "report/setup_text.hpp"
#include "core/format.hpp"
#include "io/plot.hpp"
#include "report/study_output.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {

// A neighbour's total in summary.md: "edge" where the best r0 ends the scanned range.
std::string neighbour(double v) { return std::isfinite(v) ? fmt(v, 3) : std::string("edge"); }

// A number in the CSV tables and plot commands: 10 significant digits (core/format fmt_sig), "nan" for
// any non-finite value (the scan's edges).
std::string num10(double v) { return std::isfinite(v) ? fmt_sig(v, 10) : std::string("nan"); }

std::vector<const RadiusRow*> rows_of(const RadiusScanResult& r, const std::string& field, const std::string& array) {
  std::vector<const RadiusRow*> out;
  for (const auto& row : r.rows)
    if (row.field == field && row.array == array) out.push_back(&row);
  return out;
}

const Recommendation* rec_of(const RadiusScanResult& r, const std::string& field, const std::string& array) {
  for (const auto& x : r.recommendations)
    if (x.field == field && x.array == array) return &x;
  return nullptr;
}

std::vector<std::string> array_names(const RadiusScanOptions& opt) {
  std::vector<std::string> a;
  for (const auto& x : opt.arrays) a.push_back(x.name);
  return a;
}

// The row of (field, array) nearest to r0.
const RadiusRow* row_at(const RadiusScanResult& r, const std::string& field, const std::string& array, double r0) {
  const RadiusRow* best = nullptr;
  for (const auto* row : rows_of(r, field, array))
    if (!best || std::abs(row->r0_mm - r0) < std::abs(best->r0_mm - r0)) best = row;
  return best;
}

}  // namespace

std::string file_tag(const std::string& name) {
  std::string t;
  for (char c : name)
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') t += c;
  return t;
}

std::string radius_csv(const RadiusScanResult& r, bool windowed) {
  std::ostringstream os;
  os << "field,array,r0_mm,bz_amplitude_T,ideal_pp_deg,worst_pp_deg,worst_corner,mc_mean_pp_deg,mc_p95_pp_deg,mc_p99_pp_deg,"
        "mc_max_pp_deg,mc_samples,noise_sigma_deg,noise_pp_deg,adc_clipped,total_p99_pp_deg,total_worst_pp_deg";
  // With a field window: its counts and the field extremes, after the standard columns.
  if (windowed) os << ",mc_out_of_window,corners_out_of_window,field_min_mT,field_max_mT";
  os << "\n";
  for (const auto& x : r.rows) {
    os << x.field << "," << x.array << "," << num10(x.r0_mm) << "," << num10(x.bz_amplitude_T) << "," << num10(x.ideal_pp_deg)
       << "," << num10(x.worst_pp_deg)
       << "," << x.worst_corner << "," << num10(x.mc.mean) << "," << num10(x.mc.p95) << "," << num10(x.mc.p99) << ","
       << num10(x.mc.max) << "," << x.mc.n << "," << num10(x.noise.sigma_deg) << "," << num10(x.noise.pp_deg) << ","
       << (x.noise.adc_clipped ? 1 : 0) << "," << num10(x.total_p99_pp_deg) << "," << num10(x.total_worst_pp_deg);
    if (windowed)
      os << "," << x.mc_out_of_window << "," << x.corners_out_of_window << "," << num10(x.field_min_mT) << ","
         << num10(x.field_max_mT);
    os << "\n";
  }
  return os.str();
}

std::string recommendation_csv(const RadiusScanResult& r) {
  std::ostringstream os;
  os << "field,array,r0_best_mm,total_p99_pp_deg,mc_p99_pp_deg,noise_pp_deg,total_p99_left_deg,"
        "total_p99_right_deg,band_lo_mm,band_hi_mm,r0_best_mount_only_mm,r_bz_peak_mm,at_scan_edge\n";
  for (const auto& x : r.recommendations) {
    double peak = std::numeric_limits<double>::quiet_NaN();
    for (const auto& f : r.fields)
      if (f.field == x.field) peak = f.r_bz_peak_mm;
    os << x.field << "," << x.array << "," << num10(x.r0_best_mm) << "," << num10(x.total_p99_best_deg) << ","
       << num10(x.mc_p99_best_deg) << "," << num10(x.noise_pp_best_deg) << "," << num10(x.total_p99_left_deg) << ","
       << num10(x.total_p99_right_deg) << "," << num10(x.band_lo_mm) << "," << num10(x.band_hi_mm) << ","
       << num10(x.r0_best_mount_only_mm) << "," << num10(peak) << "," << (x.at_scan_edge ? 1 : 0) << "\n";
  }
  return os.str();
}

std::string validation_csv(const RadiusScanResult& r) {
  std::ostringstream os;
  os << "field,array,r0_mm,case,sx_mm,sy_mm,dx_mm,dy_mm,dz_mm,pp_direct_deg,pp_direct_coarse_deg,pp_surrogate_deg,"
        "pp_diff_deg,max_coef_diff_deg\n";
  for (const auto& v : r.validation)
    os << v.field << "," << v.array << "," << num10(v.r0_mm) << "," << v.label << "," << num10(v.mount.sx_mm) << ","
       << num10(v.mount.sy_mm) << "," << num10(v.mount.dx_mm) << "," << num10(v.mount.dy_mm) << "," << num10(v.mount.dz_mm) << ","
       << num10(v.pp_direct_deg) << "," << num10(v.pp_direct_coarse_deg) << "," << num10(v.pp_surrogate_deg) << ","
       << num10(v.pp_surrogate_deg - v.pp_direct_deg) << "," << num10(v.max_coef_diff_deg) << "\n";
  return os.str();
}

ValidationSummary summarize_validation(const RadiusScanResult& r, const std::string& field) {
  ValidationSummary s;
  for (const auto& v : r.validation) {
    if (v.field != field) continue;
    ++s.cases;
    const double d = std::abs(v.pp_surrogate_deg - v.pp_direct_deg);
    s.max_pp_diff_deg = std::max(s.max_pp_diff_deg, d);
    if (v.pp_direct_deg >= 0.01) s.max_rel_pp_diff = std::max(s.max_rel_pp_diff, d / v.pp_direct_deg);
    s.max_coef_diff_deg = std::max(s.max_coef_diff_deg, v.max_coef_diff_deg);
    s.max_grid_pp_diff_deg = std::max(s.max_grid_pp_diff_deg, std::abs(v.pp_direct_coarse_deg - v.pp_direct_deg));
    s.max_model_pp_diff_deg = std::max(s.max_model_pp_diff_deg, std::abs(v.pp_surrogate_deg - v.pp_direct_coarse_deg));
  }
  return s;
}

namespace {

// 1. Harmonics and pp against r0, one panel per mounting case, per (field, array).
void plot_harmonics(const RadiusScanResult& r, const std::vector<std::string>& arrays, const std::vector<std::pair<std::string, Mount>>& cases, const std::string& xr, const std::filesystem::path& dir) {
  for (const auto& f : r.fields) {
    for (const auto& a : arrays) {
      PlotSpec spec;
      spec.title = "Angle-error harmonics vs probe radius: " + plot_literal(f.field) + " field, array " +
                   plot_literal(a) + " (log scale; values below 1e-5 deg drawn at 1e-5)";
      spec.columns = 3;
      spec.width_px = 1500;
      spec.height_px = 900;
      for (const auto& [label, mount] : cases) {
        PlotPanel p;
        p.title = "case " + plot_literal(label) + " (sx " + fmt(mount.sx_mm, 2) + ", sy " + fmt(mount.sy_mm, 2) +
                  ", dx " + fmt(mount.dx_mm, 2) + ", dy " + fmt(mount.dy_mm, 2) + ", dz " + fmt(mount.dz_mm, 2) +
                  " mm)";
        p.xlabel = xr;
        p.ylabel = "error [deg]";
        p.logy = true;
        p.commands = {"set key top right font ',9'", "set yrange [1e-5:*]"};
        std::vector<double> x;
        std::vector<std::vector<double>> c(5), pp(1);
        for (const auto& s : r.spectra) {
          if (s.field != f.field || s.array != a || s.extra.empty() || s.extra[0].second != label) continue;
          x.push_back(s.r0_mm);
          const double floor_deg = 1e-5;  // log axis: exact zeros would be undefined
          for (int n = 1; n <= 4; ++n)
            c[static_cast<std::size_t>(n)].push_back(std::max(s.spectrum.c_deg[n], floor_deg));
          c[0].push_back(std::max(std::abs(s.spectrum.a0_deg), floor_deg));
          pp[0].push_back(std::max(s.spectrum.pp_deg, floor_deg));
        }
        p.series.push_back({"|a_0|", x, c[0], "lines", "lw 1.5 dt 2"});
        for (int n = 1; n <= 4; ++n)
          p.series.push_back({"c_" + std::to_string(n), x, c[static_cast<std::size_t>(n)], "lines", "lw 1.5"});
        p.series.push_back({"pp", x, pp[0], "lines", "lw 2.5 lc rgb 'black'"});
        spec.panels.push_back(p);
      }
      write_plot(dir, "harmonics_" + file_tag(f.field) + "_" + file_tag(a), spec);
    }
  }
}

// 2. Percentile bands against r0, one panel per array, per field.
void plot_percentiles(const RadiusScanResult& r, const RadiusScanOptions& opt, const std::vector<std::string>& arrays, const std::string& xr, const std::filesystem::path& dir) {
  for (const auto& f : r.fields) {
    PlotSpec spec;
    spec.title = "Peak-to-peak angle error over the tolerance box vs r_0: " + plot_literal(f.field) + " field (" +
                 std::to_string(opt.samples) + " MC samples per radius)";
    spec.columns = static_cast<int>(std::min<std::size_t>(arrays.size(), 3));
    spec.width_px = 600 * spec.columns;
    spec.height_px = 650;
    for (const auto& a : arrays) {
      PlotPanel p;
      p.title = "array " + plot_literal(a);
      p.xlabel = xr;
      p.ylabel = "peak-to-peak error [deg]";
      p.logy = true;
      p.commands = {"set key top right font ',9'"};
      std::vector<double> x, mean, p95, p99, worst, noise, total;
      for (const auto* row : rows_of(r, f.field, a)) {
        x.push_back(row->r0_mm);
        mean.push_back(row->mc.mean);
        p95.push_back(row->mc.p95);
        p99.push_back(row->mc.p99);
        worst.push_back(row->worst_pp_deg);
        noise.push_back(row->noise.pp_deg);
        total.push_back(row->total_p99_pp_deg);
      }
      p.series.push_back({"MC mean", x, mean, "lines", "lw 1.5"});
      p.series.push_back({"MC 95th pct", x, p95, "lines", "lw 1.5"});
      p.series.push_back({"MC 99th pct", x, p99, "lines", "lw 1.5"});
      p.series.push_back({"worst corner", x, worst, "lines", "lw 1.5 dt 2"});
      p.series.push_back({"noise pp", x, noise, "lines", "lw 1.5 dt 3"});
      p.series.push_back({"total (99th + noise)", x, total, "lines", "lw 2.5 lc rgb 'black'"});
      if (const auto* rc = rec_of(r, f.field, a))
        p.series.push_back({"best r_0 = " + fmt(rc->r0_best_mm, 2) + " mm", {rc->r0_best_mm}, {rc->total_p99_best_deg},
                            "points", "pt 7 ps 1.8 lc rgb 'red'"});
      spec.panels.push_back(p);
    }
    write_plot(dir, "percentiles_" + file_tag(f.field), spec);
  }
}

// 3. Total p99 of every (field, array) in one panel.
void plot_total_p99(const RadiusScanResult& r, const std::vector<std::string>& arrays, const std::string& xr, const std::filesystem::path& dir) {
  PlotSpec spec;
  spec.title = "Total error (MC 99th percentile + noise pp) vs probe radius";
  PlotPanel p;
  p.xlabel = xr;
  p.ylabel = "total peak-to-peak error [deg]";
  p.logy = true;
  for (const auto& f : r.fields)
    for (const auto& a : arrays) {
      std::vector<double> x, y;
      for (const auto* row : rows_of(r, f.field, a)) {
        x.push_back(row->r0_mm);
        y.push_back(row->total_p99_pp_deg);
      }
      p.series.push_back({plot_literal(f.field + " " + a), x, y, "lines",
                          f.field == r.fields.front().field ? "lw 2" : "lw 2 dt 2"});
    }
  spec.panels.push_back(p);
  write_plot(dir, "total_p99", spec);
}

// 4. Bz amplitude on the plane against r.
void plot_bz_profile(const RadiusScanResult& r, const RadiusScanOptions& opt, const std::vector<std::string>& arrays, const std::filesystem::path& dir) {
  PlotSpec spec;
  spec.title = "B_z amplitude on the probe circle (sensing plane z_s = " + fmt(opt.plane_z_mm, 2) + " mm)";
  PlotPanel p;
  p.xlabel = "r [mm]";
  p.ylabel = "B_z amplitude [mT]";
  p.commands = {"set key bottom center"};
  double ymax = 0;
  for (const auto& f : r.fields) {
    std::vector<double> x, y;
    const std::string a = arrays.front();
    for (const auto* row : rows_of(r, f.field, a)) {
      x.push_back(row->r0_mm);
      y.push_back(row->bz_amplitude_T * 1e3);
      ymax = std::max(ymax, y.back());
    }
    p.series.push_back({plot_literal(f.field), x, y, "lines", "lw 2"});
  }
  for (const auto& f : r.fields)
    p.series.push_back({"peak " + plot_literal(f.field) + ": r = " + fmt(f.r_bz_peak_mm, 3) + " mm",
                        {f.r_bz_peak_mm, f.r_bz_peak_mm}, {0.0, ymax * 1.05}, "lines", "dt 2 lw 1.5"});
  p.commands.push_back("set yrange [0:" + num10(ymax * 1.1) + "]");
  spec.panels.push_back(p);
  write_plot(dir, "bz_profile", spec);
}

}  // namespace

void write_radius_plots(const RadiusScanResult& r, const RadiusScanOptions& opt, const std::filesystem::path& dir) {
  const auto arrays = array_names(opt);
  const auto cases = spectra_cases(opt);
  const std::string xr = "r_0 [mm]";
  plot_harmonics(r, arrays, cases, xr, dir);
  plot_percentiles(r, opt, arrays, xr, dir);
  plot_total_p99(r, arrays, xr, dir);
  plot_bz_profile(r, opt, arrays, dir);
}

std::string budget_csv(const RadiusScanResult& r) {
  std::ostringstream os;
  os << "field,array,r0_mm,group,p99_only_deg,p99_all_deg,share\n";
  for (const auto& b : r.budget)
    os << b.field << "," << b.array << "," << num10(b.r0_mm) << "," << b.group << "," << num10(b.p99_only_deg) << ","
       << num10(b.p99_all_deg) << "," << num10(b.share) << "\n";
  return os.str();
}

void write_budget_plot(const RadiusScanResult& r, const std::filesystem::path& dir) {
  if (r.budget.empty()) return;
  PlotSpec spec;
  spec.title = "Error budget at the recommended r_0: p99 of pp with one group of the tolerance box alone / p99 with the whole box";
  std::vector<std::string> keys;  // field/array in order
  for (const auto& b : r.budget)
    if (std::find(keys.begin(), keys.end(), b.field + "|" + b.array) == keys.end()) keys.push_back(b.field + "|" + b.array);
  spec.columns = std::min<int>(3, int(keys.size()));
  const int rows = (int(keys.size()) + spec.columns - 1) / spec.columns;
  spec.width_px = 520 * spec.columns;
  spec.height_px = 80 + 380 * rows;
  for (const auto& key : keys) {
    PlotPanel p;
    std::vector<const BudgetRow*> bs;
    for (const auto& b : r.budget)
      if (b.field + "|" + b.array == key) bs.push_back(&b);
    p.title = plot_literal(bs.front()->field) + ", " + plot_literal(bs.front()->array) + ", r_0 = " +
              fmt(bs.front()->r0_mm, 2) + " mm (p99 all = " + fmt(bs.front()->p99_all_deg, 3) + " deg)";
    p.xlabel = "";
    p.ylabel = "share of the p99 [%]";
    PlotSeries bars;
    bars.style = "boxes";
    bars.extra = "lc rgb '#3b75af'";
    std::string tics = "set xtics (";
    for (std::size_t i = 0; i < bs.size(); ++i) {
      bars.x.push_back(double(i));
      bars.y.push_back(100.0 * bs[i]->share);
      tics += (i ? ", " : "") + std::string("'") + bs[i]->group + "' " + std::to_string(i);
      p.commands.push_back("set label '" + fmt(100.0 * bs[i]->share, 0) + "' at " + std::to_string(i) + ", " +
                           num10(100.0 * bs[i]->share) + " center offset 0,0.7 font ',9'");
    }
    p.series.push_back(bars);
    p.commands.push_back(tics + ") rotate by -30 font ',9'");
    p.commands.push_back("set boxwidth 0.6");
    p.commands.push_back("set xrange [-0.6:" + num10(double(bs.size()) - 0.4) + "]");
    double top = 0;
    for (const auto* b : bs) top = std::max(top, 100.0 * b->share);
    p.commands.push_back("set yrange [0:" + num10(std::max(1.0, 1.15 * top)) + "]");
    p.commands.push_back("unset key");
    spec.panels.push_back(p);
  }
  write_plot(dir, "budget", spec);
}

namespace {

// What ran: magnet, sensor, arrays, tolerance box and window.
void summary_what_ran(std::ostringstream& md, const RadiusScanResult& r, const RadiusScanOptions& opt, const StudySetup& setup, const std::vector<std::string>& notes, const std::vector<std::string>& arrays) {
  md << "## What ran\n\n";
  md << "- Magnet: " << magnet_text(setup) << ", mu_r = " << fmt(setup.magnet_mu_r, 2)
     << " (FEM only); sensing plane h = " << fmt(setup.plane_height_mm, 2)
     << " mm above the top face (z_s = " << fmt(opt.plane_z_mm, 3) << " mm).\n";
  md << "- Fields run:";
  for (const auto& f : r.fields) md << " `" << f.spec << "`";
  md << ".\n";
  for (const auto& n : notes) md << "- " << n << "\n";
  md << "- Radii: " << fmt(opt.r0_mm.front(), 3) << " .. " << fmt(opt.r0_mm.back(), 3) << " mm, " << opt.r0_mm.size()
     << " radii; arrays:";
  for (const auto& a : arrays) md << " `" << a << "`";
  md << ".\n";
  md << "- Tolerance box: |sx| <= " << fmt(opt.box.sx_mm, 3) << ", |sy| <= " << fmt(opt.box.sy_mm, 3)
     << ", |dx| <= " << fmt(opt.box.dx_mm, 3) << ", |dy| <= " << fmt(opt.box.dy_mm, 3) << ", |dz| <= "
     << fmt(opt.box.dz_mm, 3) << " mm";
  if (opt.box.has_tilts())
    md << "; sensor tilt |tilt_x| <= " << fmt(opt.box.tilt_x_deg, 2) << ", |tilt_y| <= " << fmt(opt.box.tilt_y_deg, 2)
       << " deg; magnet lean components (toward x, toward y) each within +-" << fmt(opt.box.magnet_tilt_deg, 2)
       << " deg (magnet tilt up to " << fmt(std::sqrt(2.0) * opt.box.magnet_tilt_deg, 2)
       << " deg in any azimuth; pivot at the bottom-face centre, L = " << fmt(opt.magnet_height_mm, 2) << " mm)";
  if (opt.box.has_chain())
    md << "; signal chain |offset_cos| <= " << fmt(opt.box.offset_cos_mT, 3) << " mT, |offset_sin| <= "
       << fmt(opt.box.offset_sin_mT, 3) << " mT, |gain mismatch| <= " << fmt(opt.box.gain_mismatch, 4)
       << ", |phase error| <= " << fmt(opt.box.phase_error_deg, 3) << " deg (applied to the channels before atan2)";
  if (opt.box.has_elevation())
    md << "; magnetization elevation " << fmt(opt.elevation_deg, 2) << " +- "
       << fmt(opt.box.magnetization_elevation_deg, 2) << " deg";
  md << "; worst case over its " << opt.box.case_corners().size() << " corners; Monte Carlo "
     << opt.samples << " samples per radius, uniform in the box, seed " << opt.seed
     << " (the same samples at every radius and array).\n";
  md << "- Sensor noise (assumptions): " << fmt(opt.noise.probe_noise_uT_rms, 1) << " uT rms field noise per probe, "
     << opt.noise.adc_bits << "-bit ADC over +-" << fmt(opt.noise.adc_full_scale_mT, 0) << " mT per probe (LSB "
     << fmt(opt.noise.lsb_T() * 1e6, 1) << " uT, LSB/sqrt(12) = " << fmt(opt.noise.lsb_T() * 1e6 / std::sqrt(12.0), 1)
     << " uT), together " << fmt(opt.noise.probe_sigma_T() * 1e6, 1)
     << " uT rms per probe. The angle noise is sigma_phi = sigma_probe*|w|/(g*A(r0)) (two: sigma/A, diff4: "
        "sigma/(sqrt2 A), ring:N: sigma/(sqrt(N/2) A)); its peak-to-peak equivalent is "
     << fmt(opt.noise.pp_sigmas, 1) << " sigma_phi.\n";
  md << "- Total error = MC 99th percentile of the mounting pp + noise pp (a linear sum: conservative, the noise "
        "extremes can coincide with the mounting-error peaks).\n";
  md << "- Spectra cases (radius_spectra.csv): " << fmt(opt.case_offset_mm, 2) << " mm of each of sx, sy, dx, dy; dz = +-"
     << fmt(opt.case_dz_mm, 2) << " mm with dx = " << fmt(opt.case_residual_dx_mm, 2) << " mm.\n\n";

  if (opt.window.active()) {
    md << "Field window (sensor.field_min_mT .. field_max_mT): " << fmt(opt.window.min_mT, 1) << " .. "
       << (std::isinf(opt.window.max_mT) ? std::string("inf") : fmt(opt.window.max_mT, 1))
       << " mT on each probe's peak |Bz| over a turn. Corners and Monte Carlo samples whose field leaves it are "
          "counted apart (columns mc_out_of_window, corners_out_of_window of radius.csv) and left out of the pp "
          "statistics: such a mount fails whatever its angle error.\n";
    md << "\n";
    for (const auto& x : r.recommendations) {
      const RadiusRow* best = row_at(r, x.field, x.array, x.r0_best_mm);
      long out_mc = 0, rows_all_out = 0;
      for (const RadiusRow* row : rows_of(r, x.field, x.array)) {
        out_mc += row->mc_out_of_window;
        rows_all_out += row->mc.n == 0 ? 1 : 0;
      }
      md << "- `" << x.array << "` (" << x.field << "): at the best r0 = " << fmt(x.r0_best_mm, 2) << " mm, "
         << best->mc_out_of_window << " of " << opt.samples << " samples and " << best->corners_out_of_window
         << " corners out of the window (field " << fmt(best->field_min_mT, 1) << " .. " << fmt(best->field_max_mT, 1)
         << " mT); over the scan " << out_mc << " samples out, " << rows_all_out
         << " radii with no sample inside.\n";
    }
    md << "\n";
  }
}

// Recommendation: best r0 per (field, array).
void summary_recommendation(std::ostringstream& md, const RadiusScanResult& r, const RadiusScanOptions& opt) {
  md << "## Recommendation\n\n";
  std::vector<std::vector<std::string>> tab;
  for (const auto& x : r.recommendations) {
    double peak = 0;
    for (const auto& f : r.fields)
      if (f.field == x.field) peak = f.r_bz_peak_mm;
    tab.push_back({x.field, x.array, fmt(x.r0_best_mm, 2), fmt(x.total_p99_best_deg, 3), fmt(x.mc_p99_best_deg, 3),
                   fmt(x.noise_pp_best_deg, 3), neighbour(x.total_p99_left_deg) + " / " + neighbour(x.total_p99_right_deg),
                   fmt(x.band_lo_mm, 2) + " .. " + fmt(x.band_hi_mm, 2), fmt(x.r0_best_mount_only_mm, 2),
                   fmt(peak, 3)});
  }
  md << md_table({"field", "array", "best r0 [mm]", "total p99 [deg]", "MC p99 [deg]", "noise pp [deg]",
                  "total at r0 -/+ step [deg]", "band within " + fmt(100 * opt.band_rel, 0) + "% [mm]",
                  "best r0, mounting only [mm]", "Bz peak r [mm]"},
                 tab)
     << "\n";
  for (const auto& x : r.recommendations) {
    const FieldScanInfo* fi = nullptr;
    for (const auto& f : r.fields)
      if (f.field == x.field) fi = &f;
    const RadiusRow* at_peak = row_at(r, x.field, x.array, fi->r_bz_peak_mm);
    const RadiusRow* best = row_at(r, x.field, x.array, x.r0_best_mm);
    const RadiusRow* at_max = rows_of(r, x.field, x.array).back();
    md << "- **" << x.array << "** (" << x.field << " field): r0 = " << fmt(x.r0_best_mm, 2)
       << " mm minimises the 99th-percentile total error, " << fmt(x.total_p99_best_deg, 3) << " deg ("
       << fmt(x.mc_p99_best_deg, 3) << " mounting + " << fmt(x.noise_pp_best_deg, 3) << " noise); one step ("
       << fmt(opt.r0_mm.size() > 1 ? opt.r0_mm[1] - opt.r0_mm[0] : 0.0, 2) << " mm) inward/outward gives "
       << neighbour(x.total_p99_left_deg) << " / " << neighbour(x.total_p99_right_deg) << " deg, and the total stays within "
       << fmt(100 * opt.band_rel, 0) << "% of the best for r0 in " << fmt(x.band_lo_mm, 2) << " .. "
       << fmt(x.band_hi_mm, 2) << " mm. ";
    md << "Bz on the circle peaks at r = " << fmt(fi->r_bz_peak_mm, 3) << " mm (" << fmt(fi->bz_peak_T * 1e3, 1)
       << " mT); there the total is " << fmt(at_peak->total_p99_pp_deg, 3) << " deg. ";
    if (std::abs(x.r0_best_mount_only_mm - x.r0_best_mm) > 1e-9)
      md << "Mounting error alone would be lowest at r0 = " << fmt(x.r0_best_mount_only_mm, 2)
         << " mm; the noise moves the choice. ";
    else
      md << "Mounting error alone has its minimum at the same radius; the noise (" << fmt(best->noise.pp_deg, 3)
         << " deg there, " << fmt(at_max->noise.pp_deg, 3) << " deg at r0 = " << fmt(at_max->r0_mm, 2)
         << " mm where Bz is " << fmt(at_max->bz_amplitude_T * 1e3, 1) << " mT) does not move it. ";
    md << "Worst box corner at the best r0: " << fmt(best->worst_pp_deg, 3) << " deg (" << best->worst_corner << ")";
    if (best->mc.max > best->worst_pp_deg + 1e-9)
      md << "; note the largest MC sample (" << fmt(best->mc.max, 3)
         << " deg) exceeds it: pp is not maximal at a corner here";
    md << ".";
    if (x.at_scan_edge) md << " **The best r0 is at the edge of the scanned range: widen it.**";
    if (best->noise.adc_clipped) md << " **The signal exceeds the ADC full scale at this radius.**";
    md << "\n";
  }
  md << "\n";
}

// Exact vs FEM field (only with more than one field).
void summary_exact_vs_fem(std::ostringstream& md, const RadiusScanResult& r, const StudySetup& setup, const std::vector<std::string>& arrays) {
  if (r.fields.size() > 1) {
    md << "## Exact vs FEM field\n\n";
    const std::string f0 = r.fields.front().field;
    std::vector<std::vector<std::string>> t;
    for (std::size_t i = 1; i < r.fields.size(); ++i) {
      const std::string f1 = r.fields[i].field;
      for (const auto& a : arrays) {
        const auto r0s = rows_of(r, f0, a), r1s = rows_of(r, f1, a);
        double dtot = 0, dtot_rel = 0, damp = 0;
        for (std::size_t k = 0; k < std::min(r0s.size(), r1s.size()); ++k) {
          const double d = std::abs(r1s[k]->total_p99_pp_deg - r0s[k]->total_p99_pp_deg);
          dtot = std::max(dtot, d);
          dtot_rel = std::max(dtot_rel, d / r0s[k]->total_p99_pp_deg);
          damp = std::max(damp, std::abs(r1s[k]->bz_amplitude_T / r0s[k]->bz_amplitude_T - 1));
        }
        const auto* a0 = rec_of(r, f0, a);
        const auto* a1 = rec_of(r, f1, a);
        t.push_back({f1 + " vs " + f0, a, fmt(a0->r0_best_mm, 2) + " / " + fmt(a1->r0_best_mm, 2),
                     fmt(a0->total_p99_best_deg, 3) + " / " + fmt(a1->total_p99_best_deg, 3), fmt(dtot, 3),
                     fmt(100 * dtot_rel, 2), fmt(100 * damp, 2)});
      }
      md << "Bz peak radius: " << f0 << " " << fmt(r.fields.front().r_bz_peak_mm, 3) << " mm, " << f1 << " "
         << fmt(r.fields[i].r_bz_peak_mm, 3) << " mm.\n\n";
    }
    md << md_table({"fields", "array", "best r0 [mm]", "best total p99 [deg]", "max |diff| total p99 [deg]",
                    "max rel diff [%]", "max rel diff Bz amplitude [%]"},
                   t)
       << "\n";
    md << "The exact field has mu_r = 1; the FEM uses magnet.mu_r = " << fmt(setup.magnet_mu_r, 2)
       << ", so part of the difference is physics, not discretization.\n\n";
  }
}

// Field artefacts: error with an ideal mount.
void summary_field_artefacts(std::ostringstream& md, const RadiusScanResult& r, const std::vector<std::string>& arrays) {
  md << "## Field artefacts: error with an ideal mount\n\n";
  md << "An exact field gives zero error with an ideal mount; anything else is a numerical artefact of the field "
        "source (mesh, faceting, grid).\n\n";
  {
    std::vector<std::vector<std::string>> it;
    for (const auto& f : r.fields)
      for (const auto& a : arrays) {
        double mx = 0;
        for (const auto* row : rows_of(r, f.field, a)) mx = std::max(mx, row->ideal_pp_deg);
        const auto* rc = rec_of(r, f.field, a);
        const RadiusRow* b = row_at(r, f.field, a, rc->r0_best_mm);
        it.push_back({f.field, a, fmt(mx, 5), fmt(b->ideal_pp_deg, 5), fmt(b->total_p99_pp_deg, 3)});
      }
    md << md_table({"field", "array", "max ideal-mount pp over r0 [deg]", "ideal-mount pp at best r0 [deg]",
                    "total p99 at best r0 [deg]"},
                   it)
       << "\n";
  }
}

// How each field's node models were built (radius.surrogate_build, CircleFieldModel::Construction).
void summary_builds(std::ostringstream& md, const RadiusScanResult& r) {
  md << "Node models (`radius.surrogate_build`):";
  for (const auto& f : r.fields) {
    md << " " << f.field << ":";
    for (std::size_t i = 0; i < f.builds.size(); ++i)
      md << (i ? "," : "") << " " << f.builds[i].first << " (" << f.builds[i].second << " radii)";
    md << ";";
  }
  md << " symmetry: from the exact field's rotational symmetry; symmetrized: the field's symmetric part from "
        "12 azimuths plus its own asymmetry at the nodes (each reading takes it at its nominal node, so an ideal "
        "mount reads the field itself); axis_aligned: a direct fit per node.";
  for (const auto& f : r.fields)
    if (f.max_node_residual_rel > 0)
      md << " The " << f.field << " field's asymmetry at the nodes is at most " << fmt_sig(f.max_node_residual_rel, 2)
         << " of its Bz amplitude.";
  md << "\n\n";
}

// How fast and how accurate: the surrogate.
void summary_surrogate(std::ostringstream& md, const RadiusScanResult& r, const RadiusScanOptions& opt) {
  md << "## How fast and how accurate: the surrogate\n\n";
  md << "Per radius the field is sampled on a 5x5x5 stencil around each of " << opt.fast_steps
     << " nodes on the probe circle and fitted by a local polynomial of degree " << opt.surrogate_order
     << " in the displacement; the MC samples, box corners and spectra cases then run through an exact atan2/"
        "spectrum pipeline on " << opt.fast_steps << " theta samples (see radius_scan.hpp). "
        "Checked against the direct pipeline (" << opt.direct_steps << " theta samples, direct field "
        "evaluation) at " << opt.validate_radii << " radii on the spectra cases, the worst corners and "
     << opt.validate_samples << " MC samples (radius_validation.csv):\n\n";
  std::vector<std::vector<std::string>> vt;
  for (const auto& f : r.fields) {
    const auto s = summarize_validation(r, f.field);
    vt.push_back({f.field, std::to_string(s.cases), fmt(s.max_pp_diff_deg, 5), fmt(100 * s.max_rel_pp_diff, 3),
                  fmt(s.max_coef_diff_deg, 5), fmt(s.max_grid_pp_diff_deg, 5), fmt(s.max_model_pp_diff_deg, 5),
                  fmt(f.max_fit_residual_T * 1e6, 3)});
  }
  md << md_table({"field", "cases", "max |pp diff| [deg]", "max rel pp diff (pp >= 0.01 deg) [%]", "max |a_n, b_n diff| [deg]",
                  "theta-grid part: max |pp(" + std::to_string(opt.fast_steps) + ") - pp(" +
                      std::to_string(opt.direct_steps) + ")| [deg]",
                  "field-model part [deg]", "max fit residual [uT]"},
                 vt)
     << "\n";
  summary_builds(md, r);
  md << "The 'theta-grid part' compares the direct pipeline at " << opt.fast_steps << " and " << opt.direct_steps
     << " theta samples (peak-to-peak resolution alone); the 'field-model part' compares the surrogate with the direct "
        "pipeline on the same " << opt.fast_steps << " samples (the local polynomials alone). A large fit residual "
        "means the field source itself is not smooth on the stencil scale (the FE field's grad psi jumps between "
        "elements): the surrogate then acts as a local least-squares smoothing of the field, and its difference to the "
        "direct pipeline measures that roughness (note the direct pipeline's own theta-grid dependence for such a "
        "field) rather than a surrogate error.\n\n";
}

// Error budget at the recommended r0.
void summary_budget(std::ostringstream& md, const RadiusScanResult& r, const RadiusScanOptions& opt) {
  if (!r.budget.empty()) {
    md << "## Error budget at the recommended r0\n\n"
       << "Share of a group = p99 of the peak-to-peak error with only that group of the tolerance box active (the same "
       << opt.samples << " Monte Carlo samples, seed " << opt.seed << ", every other half-width 0) divided by the p99 "
          "with the whole box, at the recommended r0 of each field and array (mounting error only, no noise). The shares "
          "do not add up to 100 %: the sources combine neither linearly nor in quadrature.\n\n";
    std::vector<std::string> groups;
    for (const auto& b : r.budget)
      if (std::find(groups.begin(), groups.end(), b.group) == groups.end()) groups.push_back(b.group);
    std::vector<std::string> header = {"field", "array", "r0 [mm]", "p99 all [deg]"};
    for (const auto& gname : groups) header.push_back(gname + " p99 [deg] (share)");
    std::vector<std::vector<std::string>> bt;
    for (const auto& x : r.recommendations) {
      std::vector<std::string> row = {x.field, "`" + x.array + "`", "", ""};
      for (const auto& gname : groups) {
        std::string cell = "-";
        for (const auto& b : r.budget)
          if (b.field == x.field && b.array == x.array && b.group == gname) {
            row[2] = fmt(b.r0_mm, 2);
            row[3] = fmt(b.p99_all_deg, 4);
            cell = fmt(b.p99_only_deg, 4) + " (" + fmt(100.0 * b.share, 0) + " %)";
          }
        row.push_back(cell);
      }
      bt.push_back(row);
    }
    md << md_table(header, bt) << "\n" << md_image("error budget at the recommended r0", "budget.png") << "\n";
  }
}

// Timing.
void summary_timing(std::ostringstream& md, const RadiusScanResult& r, double wall_s) {
  md << "## Timing\n\n";
  std::vector<std::vector<std::string>> tt;
  for (const auto& f : r.fields)
    tt.push_back({f.field, fmt(f.t_models_s, 2), fmt(f.t_cases_s, 2), fmt(f.t_validate_s, 2)});
  md << md_table({"field", "field models [s]", "spectra + corners + MC [s]", "validation [s]"}, tt) << "\n";
  md << "Scan wall time " << fmt(wall_s, 1) << " s.\n\n";
}

// Plots.
void summary_plots(std::ostringstream& md, const RadiusScanResult& r, const std::vector<std::string>& arrays) {
  md << "## Plots\n\n";
  md << md_image("Bz amplitude vs r", "bz_profile.png");
  md << md_image("total p99 vs r0", "total_p99.png");
  for (const auto& f : r.fields) md << md_image("percentiles " + f.field, "percentiles_" + file_tag(f.field) + ".png");
  for (const auto& f : r.fields)
    for (const auto& a : arrays)
      md << md_image("harmonics " + f.field + " " + a, "harmonics_" + file_tag(f.field) + "_" + file_tag(a) + ".png");
  md << "\nFiles: radius.csv, radius_spectra.csv, radius_recommendation.csv, radius_validation.csv, radius_budget.csv, "
        "config.toml, run.json.\n";
}

}  // namespace

std::string radius_summary_md(const RadiusScanResult& r, const RadiusScanOptions& opt, const StudySetup& setup,
                              const std::vector<std::string>& notes, double wall_s) {
  std::ostringstream md;
  const auto arrays = array_names(opt);
  md << "# Probe radius study (`radius`)\n\n";
  md << "Which probe radius r0 to choose for this magnet, and what a mounting tolerance costs.\n\n";
  summary_what_ran(md, r, opt, setup, notes, arrays);
  summary_recommendation(md, r, opt);
  summary_exact_vs_fem(md, r, setup, arrays);
  summary_field_artefacts(md, r, arrays);
  summary_surrogate(md, r, opt);
  summary_budget(md, r, opt);
  summary_timing(md, r, wall_s);
  summary_plots(md, r, arrays);
  return md.str();
}

}  // namespace magenc
