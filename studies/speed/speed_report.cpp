#include "speed_report.hpp"

#include <cmath>
#include <sstream>

#include "core/format.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {

std::string g(double v) { return fmt_sig(v, 10); }

PlotSeries series(const std::string& title) {
  PlotSeries s;
  s.title = title;
  s.style = "linespoints";
  return s;
}

std::string label(const std::string& timing, Prediction p) {
  return timing + (p == Prediction::Ideal ? ", ideal prediction" : "");
}

std::string sweep_csv(const SpeedStudyResult& r) {
  std::ostringstream os;
  os << "timing,prediction,rpm,a0_deg,pp_deg,c1_deg,c2_deg,c3_deg,c4_deg\n";
  for (const auto& p : r.sweep) {
    os << p.timing << ',' << prediction_name(p.prediction) << ',' << g(p.rpm) << ',' << g(p.spectrum.a0_deg) << ','
       << g(p.spectrum.pp_deg);
    for (int n = 1; n <= 4; ++n) os << ',' << g(p.spectrum.c_deg[n]);
    os << '\n';
  }
  return os.str();
}

std::string commutation_csv(const SpeedStudyResult& r) {
  std::ostringstream os;
  os << "timing,prediction,rpm,pole_pairs,electrical_mean_deg,electrical_max_deg,torque_factor_mean,"
        "torque_factor_min\n";
  for (const auto& c : r.commutation)
    os << c.timing << ',' << prediction_name(c.prediction) << ',' << g(c.rpm) << ',' << c.pole_pairs << ','
       << g(c.electrical_mean_deg) << ',' << g(c.electrical_max_deg) << ',' << g(c.torque_mean) << ','
       << g(c.torque_min) << '\n';
  return os.str();
}

std::string attenuation_csv(const SpeedStudyResult& r) {
  std::ostringstream os;
  os << "rpm,filter_hz,a0_deg,c1_deg,c2_deg,c3_deg,c4_deg,c1_ratio,c2_ratio,c3_ratio,c4_ratio\n";
  const Spectrum& still = r.attenuation.front().spectrum;
  for (const auto& a : r.attenuation) {
    os << g(a.rpm) << ',' << g(r.options.filter_hz) << ',' << g(a.spectrum.a0_deg);
    for (int n = 1; n <= 4; ++n) os << ',' << g(a.spectrum.c_deg[n]);
    for (int n = 1; n <= 4; ++n) os << ',' << (still.c_deg[n] > 1e-12 ? g(a.spectrum.c_deg[n] / still.c_deg[n]) : "");
    os << '\n';
  }
  return os.str();
}

std::string calibration_csv(const SpeedStudyResult& r) {
  std::ostringstream os;
  const std::string at = g(r.options.calibration_rpm);
  os << "rpm,pp_raw_deg,pp_calibrated_at_rest_deg,pp_calibrated_at_" << at << "_rpm_deg,max_abs_raw_deg,"
     << "max_abs_calibrated_at_rest_deg,max_abs_calibrated_at_" << at << "_rpm_deg\n";
  for (const auto& c : r.calibration)
    os << g(c.rpm) << ',' << g(c.pp_raw_deg) << ',' << g(c.pp_cal_rest_deg) << ',' << g(c.pp_cal_moving_deg) << ','
       << g(c.max_raw_deg) << ',' << g(c.max_cal_rest_deg) << ',' << g(c.max_cal_moving_deg) << '\n';
  return os.str();
}

void sweep_plot(const SpeedStudyResult& r, const std::filesystem::path& dir) {
  PlotPanel lag = plot_panel("mean error a0 (negative: the output lags)", "speed [rpm]", "a0 [deg]");
  PlotPanel pp = plot_panel("peak-to-peak error", "speed [rpm]", "pp [deg]");
  for (const auto& t : r.options.timings)
    for (const Prediction p : {Prediction::None, Prediction::Ideal}) {
      PlotSeries a = series(plot_literal(label(t.name, p))), b = a;
      for (const auto& s : r.sweep)
        if (s.timing == t.name && s.prediction == p) {
          a.x.push_back(s.rpm);
          a.y.push_back(s.spectrum.a0_deg);
          b.x.push_back(s.rpm);
          b.y.push_back(s.spectrum.pp_deg);
        }
      lag.series.push_back(a);
      pp.series.push_back(b);
    }
  lag.commands = {"set key bottom left"};
  pp.commands = {"set key top left"};
  write_plot(dir, "speed_error", PlotSpec{"Angle error against speed (" + plot_literal(r.array) + ")", {lag, pp}, 2, 1400, 600});
}

void commutation_plot(const SpeedStudyResult& r, const std::filesystem::path& dir) {
  PlotPanel el = plot_panel("electrical error (mean p a0)", "speed [rpm]", "electrical error [deg]");
  PlotPanel tq = plot_panel("torque factor cos(p eps), least over the turn", "speed [rpm]", "torque factor");
  for (const auto& t : r.options.timings)
    for (const Prediction p : {Prediction::None, Prediction::Ideal})
      for (const long pairs : r.options.pole_pairs) {
        PlotSeries a = series(plot_literal(label(t.name, p) + ", p = " + std::to_string(pairs))), b = a;
        for (const auto& c : r.commutation)
          if (c.timing == t.name && c.prediction == p && c.pole_pairs == pairs) {
            a.x.push_back(c.rpm);
            a.y.push_back(c.electrical_mean_deg);
            b.x.push_back(c.rpm);
            b.y.push_back(c.torque_min);
          }
        el.series.push_back(a);
        tq.series.push_back(b);
      }
  el.commands = {"set key below"};
  tq.commands = {"set key below", "set yrange [-1.05:1.05]"};
  write_plot(dir, "commutation", PlotSpec{"Motor commutation at speed", {el, tq}, 2, 1400, 900});
}

void attenuation_plot(const SpeedStudyResult& r, const std::filesystem::path& dir) {
  const std::string filter = fmt(r.options.filter_hz, 0) + " Hz";
  PlotPanel value = plot_panel("c_n behind a first-order filter at " + filter, "speed [rpm]", "c_n [deg]");
  PlotPanel ratio = plot_panel("c_n at speed / c_n at rest (harmonics of at least 1 % of c_1 at rest)", "speed [rpm]", "ratio");
  value.logy = true;
  const Spectrum& still = r.attenuation.front().spectrum;
  for (int n = 1; n <= 4; ++n) {
    std::string name = "c";
    name += std::to_string(n);
    PlotSeries v = series(name), q = v;
    for (const auto& a : r.attenuation) {
      v.x.push_back(a.rpm);
      v.y.push_back(a.spectrum.c_deg[n] > 1e-12 ? a.spectrum.c_deg[n] : std::nan(""));
      q.x.push_back(a.rpm);
      q.y.push_back(a.spectrum.c_deg[n] / still.c_deg[n]);
    }
    value.series.push_back(v);
    if (still.c_deg[n] >= 0.01 * still.c_deg[1] && still.c_deg[n] > 1e-9) ratio.series.push_back(q);
  }
  write_plot(dir, "attenuation", PlotSpec{"Static harmonics behind the channel filter (mount of the configuration)",
                                          {value, ratio}, 2, 1400, 600});
}

void calibration_plot(const SpeedStudyResult& r, const std::filesystem::path& dir) {
  const std::string timing = r.options.calibration_timing.name;
  PlotPanel max_abs = plot_panel(plot_literal("largest |error|, " + r.options.calibration_method + ", timing " + timing + " (no hold)"),
                    "speed of the run [rpm]", "max |eps| [deg]");
  PlotPanel pp = plot_panel("peak-to-peak", "speed of the run [rpm]", "pp [deg]");
  const std::string moving = "calibrated at " + fmt(r.options.calibration_rpm, 0) + " rpm";
  for (PlotPanel* pn : {&max_abs, &pp}) {
    const bool m = pn == &max_abs;
    PlotSeries raw = series("uncorrected"), rest = series("calibrated at rest"), mov = series(moving);
    for (const auto& c : r.calibration) {
      raw.x.push_back(c.rpm);
      raw.y.push_back(m ? c.max_raw_deg : c.pp_raw_deg);
      rest.x.push_back(c.rpm);
      rest.y.push_back(m ? c.max_cal_rest_deg : c.pp_cal_rest_deg);
      mov.x.push_back(c.rpm);
      mov.y.push_back(m ? c.max_cal_moving_deg : c.pp_cal_moving_deg);
    }
    pn->series = {raw, rest, mov};
    pn->logy = true;
  }
  write_plot(dir, "calibration", PlotSpec{"A calibration taken at one speed, run at another", {max_abs, pp}, 2, 1400, 600});
}

// The sweep point of a timing and prediction nearest to rpm.
const SpeedPoint* nearest(const SpeedStudyResult& r, const std::string& timing, Prediction p, double rpm) {
  const SpeedPoint* best = nullptr;
  for (const auto& s : r.sweep)
    if (s.timing == timing && s.prediction == p && (!best || std::abs(s.rpm - rpm) < std::abs(best->rpm - rpm)))
      best = &s;
  return best;
}

std::string summary_md(const SpeedStudyResult& r) {
  std::ostringstream os;
  const auto& o = r.options;
  os << "# speed: the angle error of a turning encoder\n\n"
     << "Field " << r.field << ", array " << r.array << ", mount sx " << fmt(r.mount.sx_mm, 3) << " sy "
     << fmt(r.mount.sy_mm, 3) << " dx " << fmt(r.mount.dx_mm, 3) << " dy " << fmt(r.mount.dy_mm, 3) << " mm, "
     << o.steps << " samples per turn, 0 to " << fmt(o.rpm_max, 0) << " rpm (docs/physics.md \"Speed\").\n\n"
     << "## Error against speed\n\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& t : o.timings)
    for (const Prediction p : {Prediction::None, Prediction::Ideal})
      for (const double rpm : {0.0, 6000.0, 10000.0, o.rpm_max}) {
        const SpeedPoint* s = nearest(r, t.name, p, rpm);
        if (!s) continue;
        rows.push_back({label(t.name, p), fmt(s->rpm, 0), fmt_deg(s->spectrum.a0_deg), fmt_deg(s->spectrum.pp_deg),
                        fmt_deg(s->spectrum.c_deg[1]), fmt_deg(s->spectrum.c_deg[2])});
      }
  os << md_table({"timing", "rpm", "a0 [deg]", "pp [deg]", "c1 [deg]", "c2 [deg]"}, rows) << "\n";
  os << "## Commutation (least torque factor over the turn)\n\n";
  rows.clear();
  for (const auto& c : r.commutation)
    if (c.rpm == o.rpm_max || std::abs(c.rpm - 10000) < o.rpm_max / (2.0 * (o.rpm_points - 1)))
      rows.push_back({label(c.timing, c.prediction), fmt(c.rpm, 0), std::to_string(c.pole_pairs),
                      fmt_deg(c.electrical_mean_deg), fmt(c.torque_min, 4)});
  os << md_table({"timing", "rpm", "pole pairs", "electrical error [deg]", "torque factor"}, rows) << "\n";
  os << "## Filter attenuation of the static harmonics (" << fmt(o.filter_hz, 0) << " Hz)\n\n";
  rows.clear();
  const Spectrum& still = r.attenuation.front().spectrum;
  for (const auto& a : r.attenuation)
    if (a.rpm == 0 || a.rpm == o.rpm_max || std::abs(a.rpm - 6000) < o.rpm_max / (2.0 * (o.rpm_points - 1)))
      rows.push_back({fmt(a.rpm, 0), fmt_deg(a.spectrum.a0_deg), fmt_deg(a.spectrum.c_deg[1]),
                      fmt_deg(a.spectrum.c_deg[2]), fmt_deg(a.spectrum.c_deg[3])});
  os << md_table({"rpm", "a0 [deg]", "c1 [deg]", "c2 [deg]", "c3 [deg]"}, rows) << "\n"
     << "Static: c1 " << fmt_deg(still.c_deg[1]) << ", c3 " << fmt_deg(still.c_deg[3]) << " deg.\n\n";
  os << "## Calibration at one speed, run at another (" << o.calibration_method << ", "
     << o.calibration_timing.name << " without its hold)\n\n";
  rows.clear();
  const double step = o.rpm_max / (o.rpm_points - 1);
  for (const auto& c : r.calibration)
    if (std::abs(std::remainder(c.rpm, std::max(step, o.rpm_max / 6.0))) < step / 2 || c.rpm == o.calibration_rpm)
      rows.push_back({fmt(c.rpm, 0), fmt_deg(c.max_raw_deg), fmt_deg(c.max_cal_rest_deg), fmt_deg(c.max_cal_moving_deg),
                      fmt_deg(c.pp_cal_rest_deg), fmt_deg(c.pp_cal_moving_deg)});
  os << md_table({"rpm", "max abs(eps) raw", "max abs(eps'), calibrated at rest",
                  "max abs(eps'), calibrated at " + fmt(o.calibration_rpm, 0) + " rpm", "pp', at rest",
                  "pp', at " + fmt(o.calibration_rpm, 0) + " rpm"},
                 rows);
  return os.str();
}

}  // namespace

void write_speed_report(StudyOutput& out, const SpeedStudyResult& r) {
  out.write_text("speed_vs_rpm.csv", sweep_csv(r));
  out.write_text("commutation.csv", commutation_csv(r));
  out.write_text("attenuation.csv", attenuation_csv(r));
  out.write_text("calibration_vs_rpm.csv", calibration_csv(r));
  sweep_plot(r, out.dir());
  commutation_plot(r, out.dir());
  attenuation_plot(r, out.dir());
  calibration_plot(r, out.dir());
  out.write_text("summary.md", summary_md(r));
}

}  // namespace magenc
