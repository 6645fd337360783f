#include "studies/sensor_principles/sensor_principles_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "report/setup_text.hpp"
#include "core/format.hpp"
#include "io/plot.hpp"
#include "io/tables.hpp"

namespace magenc {

namespace {

std::string g10(double v) { return fmt_sig(v, 10); }
std::string mT_text(double v) { return std::isinf(v) ? std::string(v > 0 ? "inf" : "-inf") : fmt(v, 2); }
std::string window_text(const FieldWindow& w) {
  if (!w.active()) return "off";
  return mT_text(w.min_mT) + " .. " + mT_text(w.max_mT) + " mT";
}

// The mechanism behind each single-error case (derivations: tests/probe/test_sensor_principles.cpp and
// docs/physics.md); the numbers that support it come from the run.
std::string mechanism(const std::string& c) {
  if (c == "sx" || c == "sy")
    return "A Hall probe on r0 moves across the gradient of Bz: its amplitude and phase change to first order in "
           "s (DC and a 2nd harmonic). The in-plane spot sits on the axis, where every first derivative of (Bx, By) "
           "vanishes by the magnet's two mirror symmetries: its error is second order, c2 = |C| s^2/b0 "
           "(C = (1/2) d2Bx/dy2 on the axis).";
  if (c == "dx" || c == "dy")
    return "The magnet's centre orbits the axis. Bz probes on r0 see the magnet come and go once per turn (c1; "
           "differential arrays cancel most of it and keep the field's higher angular harmonics). The in-plane spot "
           "is a point of the rotor frame (on the axis), where any field fixed to the rotor turns rigidly with it: "
           "a constant, no pp.";
  if (c == "dz")
    return "A common change of the field's scale cancels in atan2 for every principle; what is left is the residual "
           "dx's error at the new gap (none for the in-plane spot, as for dx alone).";
  if (c == "tilt_x" || c == "tilt_y")
    return "A tilted Hall plate reads n.B and picks up the in-plane field (b sin a), which differential arrays "
           "largely cancel. A tilted in-plane die sees the turning field through cos a on one axis: a gain error "
           "cos a - 1, c2 = tan^2(a/2) rad.";
  if (c == "magnet_tilt")
    return "The tilted magnet wobbles under Bz probes on r0: once per turn (c1, c3 for `two`; the differential "
           "arrays cancel most of it). For the in-plane spot on the axis the tilted magnet is, like an eccentric one, "
           "fixed to the rotor: its field there turns rigidly with it, a constant only.";
  return "";
}

const char* case_words(const std::string& c) {
  if (c == "sx") return "static eccentricity sx";
  if (c == "sy") return "static eccentricity sy";
  if (c == "dx") return "dynamic eccentricity dx";
  if (c == "dy") return "dynamic eccentricity dy";
  if (c == "dz") return "air gap dz (with a residual dx)";
  if (c == "tilt_x") return "sensor tilt about x";
  if (c == "tilt_y") return "sensor tilt about y";
  if (c == "magnet_tilt") return "magnet tilt";
  return "";
}

std::string case_value(const std::string& c, const Mount& m) {
  if (c == "sx") return fmt(m.sx_mm, 3) + " mm";
  if (c == "sy") return fmt(m.sy_mm, 3) + " mm";
  if (c == "dx") return fmt(m.dx_mm, 3) + " mm";
  if (c == "dy") return fmt(m.dy_mm, 3) + " mm";
  if (c == "dz") return fmt(m.dz_mm, 3) + " mm (dx " + fmt(m.dx_mm, 3) + " mm)";
  if (c == "tilt_x") return fmt(m.tilt_x_deg, 2) + " deg";
  if (c == "tilt_y") return fmt(m.tilt_y_deg, 2) + " deg";
  if (c == "magnet_tilt") return fmt(m.magnet_tilt_deg, 2) + " deg";
  return "";
}

}  // namespace

std::string principles_csv(const SensorPrinciplesResult& r) {
  std::ostringstream os;
  os << "sensor,principle,array,window_min_mT,window_max_mT,ideal_field_min_mT,ideal_field_max_mT,mc_samples_in_window,"
        "mc_out_of_window,mc_mean_pp_deg,mc_p95_pp_deg,mc_p99_pp_deg,mc_max_pp_deg,mc_field_min_mT,mc_field_max_mT,"
        "margin_low_mT,margin_high_mT\n";
  for (const auto& s : r.sensors)
    os << s.label << "," << principle_name(s.principle) << "," << (reads_in_plane(s.principle) ? "point" : s.label)
       << "," << g10(s.window.min_mT) << "," << g10(s.window.max_mT) << "," << g10(s.ideal_field_min_mT) << ","
       << g10(s.ideal_field_max_mT) << "," << s.mc.n << "," << s.mc_out_of_window << "," << g10(s.mc.mean) << ","
       << g10(s.mc.p95) << "," << g10(s.mc.p99) << "," << g10(s.mc.max) << "," << g10(s.mc_field_min_mT) << ","
       << g10(s.mc_field_max_mT) << "," << g10(s.margin_low_mT) << "," << g10(s.margin_high_mT) << "\n";
  return os.str();
}

namespace {

// Heat map: pp of each error alone (rows: cases, columns: sensors).
void write_pp_heatmap(const SensorPrinciplesResult& r, const std::filesystem::path& dir) {
  const std::size_t C = r.cases.size();
  HeatmapSpec hm;
  hm.title = "Peak-to-peak angle error of each mounting error alone (" + r.field + " field)";
  hm.xlabel = "sensor";
  for (const auto& s : r.sensors) hm.column_labels.push_back(plot_literal(s.label));
  for (std::size_t c = 0; c < C; ++c) {
    hm.row_labels.push_back(plot_literal(r.cases[c].first + " = " + case_value(r.cases[c].first, r.cases[c].second)));
    std::vector<double> v;
    std::vector<std::string> t;
    for (const auto& s : r.sensors) {
      const double pp = s.cases[c].spectrum.pp_deg;
      v.push_back(pp);
      t.push_back(pp < kRoundingZeroDeg ? "0" : fmt_auto(pp, 2));
    }
    hm.values.push_back(v);
    hm.cell_text.push_back(t);
  }
  hm.cblabel = "pp [deg] (log scale; below 10^{-4} deg: lowest colour)";
  hm.log_floor = 1e-4;
  hm.cell_font_size = 10;
  hm.width_px = 1100;
  hm.height_px = 200 + 50 * static_cast<int>(C);
  write_heatmap(dir, "pp_heatmap", hm);
}

// Box: p99 of pp per sensor; field extremes over the box against each window.
void write_box_plot(const SensorPrinciplesResult& r, const SensorPrinciplesOptions& opt, const std::filesystem::path& dir) {
  const std::size_t S = r.sensors.size();
  PlotSpec ps;
  ps.title = "Tolerance box: " + std::to_string(opt.samples) + " Monte Carlo samples, the same for every sensor";
  ps.columns = 2;
  ps.width_px = 1300;
  ps.height_px = 560;
  {
    PlotPanel p;
    p.title = "pp over the box (in-window samples)";
    p.xlabel = "sensor";
    p.ylabel = "pp [deg]";
    p.logy = true;
    PlotSeries p99{"p99", {}, {}, "boxes", "fs solid 0.5"}, mx{"max", {}, {}, "points", "pt 7 ps 1.5"},
        mean{"mean", {}, {}, "points", "pt 5 ps 1.3"};
    std::string xt = "set xtics (";
    for (std::size_t i = 0; i < S; ++i) {
      const double x = static_cast<double>(i);
      const auto& s = r.sensors[i];
      const double floor = 1e-6;  // log axis: an exact zero is drawn at the floor
      p99.x.push_back(x);
      p99.y.push_back(std::max(s.mc.p99, floor));
      mx.x.push_back(x);
      mx.y.push_back(std::max(s.mc.max, floor));
      mean.x.push_back(x);
      mean.y.push_back(std::max(s.mc.mean, floor));
      xt += (i ? ", \"" : "\"") + plot_literal(s.label) + "\" " + std::to_string(i);
    }
    p.commands = {xt + ")", "set boxwidth 0.6", "set xrange [-0.6:" + std::to_string(S - 0.4) + "]", "set grid ytics"};
    p.series = {p99, mean, mx};
    ps.panels.push_back(p);
  }
  {
    PlotPanel p;
    p.title = "field magnitude over the box and each sensor's window";
    p.xlabel = "sensor";
    p.ylabel = "field [mT] (bz: peak |Bz| per probe; others: |(b1, b2)|)";
    PlotSeries lo{"field min over the box", {}, {}, "points", "pt 9 ps 1.6"},
        hi{"field max over the box", {}, {}, "points", "pt 11 ps 1.6"},
        wlo{"window min", {}, {}, "points", "pt 1 ps 2.5 lw 2"}, whi{"window max", {}, {}, "points", "pt 2 ps 2.5 lw 2"};
    std::string xt = "set xtics (";
    for (std::size_t i = 0; i < S; ++i) {
      const double x = static_cast<double>(i);
      const auto& s = r.sensors[i];
      lo.x.push_back(x);
      lo.y.push_back(s.mc_field_min_mT);
      hi.x.push_back(x);
      hi.y.push_back(s.mc_field_max_mT);
      if (s.window.min_mT > 0) {
        wlo.x.push_back(x);
        wlo.y.push_back(s.window.min_mT);
      }
      if (!std::isinf(s.window.max_mT)) {
        whi.x.push_back(x);
        whi.y.push_back(s.window.max_mT);
      }
      xt += (i ? ", \"" : "\"") + plot_literal(s.label) + "\" " + std::to_string(i);
    }
    p.commands = {xt + ")", "set xrange [-0.6:" + std::to_string(S - 0.4) + "]", "set yrange [0:*]",
                  "set offsets 0, 0, 10, 0", "set grid ytics",
                  "set key bottom right"};
    p.series = {lo, hi, wlo, whi};
    ps.panels.push_back(p);
  }
  write_plot(dir, "box_p99", ps);
}

// summary.md: What ran.
void summary_what_ran(std::ostringstream& md, const SensorPrinciplesResult& r, const SensorPrinciplesOptions& opt, const StudySetup& setup) {
  const std::size_t S = r.sensors.size();
  md << "## What ran\n\n";
  md << "- Field `" << r.field << "`: magnet " << magnet_text(setup) << "; sensing plane " << fmt(setup.plane_height_mm, 2) << " mm above the top face.\n";
  md << "- Sensors: ";
  for (std::size_t i = 0; i < S; ++i) {
    const auto& s = r.sensors[i];
    md << (i ? ", " : "") << "`" << s.label << "` ("
       << (reads_in_plane(s.principle) ? principle_name(s.principle) + ", one spot at the die centre"
                                        : "bz, probes on r0 = " + fmt(setup.r0_mm, 2) + " mm")
       << ")";
  }
  md << "; " << setup.steps << " samples per turn for the single errors, " << opt.mc_steps
     << " for the Monte Carlo.\n";
  md << "- Tolerance box: |sx| <= " << fmt(opt.box.sx_mm, 3) << ", |sy| <= " << fmt(opt.box.sy_mm, 3) << ", |dx| <= "
     << fmt(opt.box.dx_mm, 3) << ", |dy| <= " << fmt(opt.box.dy_mm, 3) << ", |dz| <= " << fmt(opt.box.dz_mm, 3)
     << " mm; sensor tilts |tilt_x| <= " << fmt(opt.box.tilt_x_deg, 2) << ", |tilt_y| <= " << fmt(opt.box.tilt_y_deg, 2)
     << " deg; magnet lean components within +-" << fmt(opt.box.magnet_tilt_deg, 2) << " deg; " << opt.samples
     << " uniform samples, seed " << opt.seed << ", the same samples for every sensor.\n";
  md << "- Field windows: ";
  for (std::size_t i = 0; i < S; ++i)
    md << (i ? ", " : "") << "`" << r.sensors[i].label << "` " << window_text(r.sensors[i].window);
  md << " (study keys window.<principle>_min_mT / _max_mT; a sample whose field leaves the window is counted apart "
        "and left out of the pp statistics).\n";
  md << "- Tables: `spectra.csv` (spectra table; extra columns sensor, principle, case, tilts, field_min_mT, "
        "field_max_mT, in_window), `principles.csv` (one row per sensor: the box).\n\n";
}

// summary.md: Each mounting error alone.
void summary_each_error_alone(std::ostringstream& md, const SensorPrinciplesResult& r) {
  const std::size_t C = r.cases.size();
  md << "## Each mounting error alone: peak-to-peak error [deg]\n\n";
  {
    std::vector<std::string> header = {"error"};
    for (const auto& s : r.sensors) header.push_back("`" + s.label + "`");
    std::vector<std::vector<std::string>> t;
    for (std::size_t c = 0; c < C; ++c) {
      std::vector<std::string> row = {std::string(case_words(r.cases[c].first)) + " " +
                                      case_value(r.cases[c].first, r.cases[c].second)};
      for (const auto& s : r.sensors) row.push_back(fmt_deg(s.cases[c].spectrum.pp_deg));
      t.push_back(row);
    }
    md << md_table(header, t) << "\n";
  }
  md << md_image("pp of each mounting error alone, per sensor", "pp_heatmap.png") << "\n\n";
  md << "Dominant harmonics (amplitude >= max(1e-4 deg, 1 % of the largest)), deg:\n\n";
  {
    std::vector<std::string> header = {"error"};
    for (const auto& s : r.sensors) header.push_back("`" + s.label + "`");
    std::vector<std::vector<std::string>> t;
    for (std::size_t c = 0; c < C; ++c) {
      std::vector<std::string> row = {r.cases[c].first};
      for (const auto& s : r.sensors) {
        const Spectrum& sp = s.cases[c].spectrum;
        std::string txt = harmonics_text(dominant_harmonics(sp, 1e-4, 0.01, 3), sp);
        if (std::abs(sp.a0_deg) >= 1e-4) txt = "a0 " + fmt_auto(sp.a0_deg, 3) + "; " + txt;
        row.push_back(txt);
      }
      t.push_back(row);
    }
    md << md_table(header, t) << "\n";
  }
}

// summary.md: Which principle tolerates which error, and why.
void summary_which_principle(std::ostringstream& md, const SensorPrinciplesResult& r) {
  const std::size_t C = r.cases.size(), S = r.sensors.size();
  md << "## Which principle tolerates which error, and why\n\n";
  for (std::size_t c = 0; c < C; ++c) {
    std::vector<std::size_t> order(S);
    for (std::size_t i = 0; i < S; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return r.sensors[a].cases[c].spectrum.pp_deg < r.sensors[b].cases[c].spectrum.pp_deg;
    });
    const auto& best = r.sensors[order.front()];
    const auto& worst = r.sensors[order.back()];
    const double pb = best.cases[c].spectrum.pp_deg, pw = worst.cases[c].spectrum.pp_deg;
    md << "- **" << case_words(r.cases[c].first) << "** (" << case_value(r.cases[c].first, r.cases[c].second)
       << "): least error `" << best.label << "` (pp " << fmt_deg(pb) << " deg), most `" << worst.label << "` (pp "
       << fmt_deg(pw) << " deg";
    if (pb > kRoundingZeroDeg) md << ", " << (pw / pb < 10 ? fmt(pw / pb, 2) : fmt(pw / pb, 0)) << " times more";
    md << "). " << mechanism(r.cases[c].first) << "\n";
  }
  md << "\nPer sensor, the errors it shrugs off (pp < 0.01 deg at the values above) and those it does not:\n\n";
  for (const auto& sen : r.sensors) {
    std::string ok, bad;
    for (std::size_t c = 0; c < C; ++c) {
      const double pp = sen.cases[c].spectrum.pp_deg;
      std::string& to = pp < 0.01 ? ok : bad;
      to += (to.empty() ? "" : ", ") + r.cases[c].first + (pp < 0.01 ? "" : " (" + fmt_deg(pp) + ")");
    }
    md << "- `" << sen.label << "`: tolerates " << (ok.empty() ? std::string("none") : ok) << "; sensitive to "
       << (bad.empty() ? std::string("none") : bad) << ".\n";
  }
  md << "\n";
  md << "- `inplane`, `xmr` and `amr` read the same field angle at the same spot: for mounting errors alone their "
        "spectra agree (AMR's doubled angle is halved again while |eps| < 90 deg). They differ in the signal chain "
        "(offsets in mT against relative offsets; on `amr` a relative offset o makes c2 = o/2 rad and a gain error g "
        "makes c4 = g/(2(2+g)) rad) and in their field windows.\n\n";
}

// summary.md: The tolerance box.
void summary_tolerance_box(std::ostringstream& md, const SensorPrinciplesResult& r, const SensorPrinciplesOptions& opt) {
  const std::size_t S = r.sensors.size();
  md << "## The tolerance box\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& s : r.sensors)
      t.push_back({"`" + s.label + "`", std::to_string(s.mc.n), std::to_string(s.mc_out_of_window), fmt_deg(s.mc.mean),
                   fmt_deg(s.mc.p95), fmt_deg(s.mc.p99), fmt_deg(s.mc.max),
                   mT_text(s.mc_field_min_mT) + " .. " + mT_text(s.mc_field_max_mT), window_text(s.window),
                   mT_text(s.margin_low_mT) + " / " + mT_text(s.margin_high_mT)});
    md << md_table({"sensor", "samples in window", "out of window", "mean pp [deg]", "p95 [deg]", "p99 [deg]",
                    "max [deg]", "field over the box [mT]", "window", "margin low / high [mT]"},
                   t)
       << "\n";
  }
  {
    std::size_t best = 0;
    for (std::size_t i = 1; i < S; ++i)
      if (r.sensors[i].mc.p99 < r.sensors[best].mc.p99) best = i;
    md << "Over the whole box the lowest 99th percentile of pp is `" << r.sensors[best].label << "`'s, "
       << fmt_deg(r.sensors[best].mc.p99) << " deg";
    for (std::size_t i = 0; i < S; ++i)
      if (i != best && r.sensors[best].mc.p99 > 0 && std::isfinite(r.sensors[i].mc.p99))
        md << "; `" << r.sensors[i].label << "` " << fmt_deg(r.sensors[i].mc.p99) << " deg ("
           << fmt(r.sensors[i].mc.p99 / r.sensors[best].mc.p99, 2) << "x)";
    md << ". ";
    long out_total = 0;
    for (const auto& s : r.sensors) out_total += s.mc_out_of_window;
    if (out_total == 0)
      md << "Every sample's field stays inside every sensor's window.";
    else
      for (const auto& s : r.sensors)
        if (s.mc_out_of_window > 0)
          md << "`" << s.label << "`: " << s.mc_out_of_window << " of " << opt.samples
             << " samples leave its window (field " << mT_text(s.mc_field_min_mT) << " .. "
             << mT_text(s.mc_field_max_mT) << " mT against " << window_text(s.window) << "). ";
    md << " A negative margin means the field over the box leaves the window on that side.\n\n";
  }
  md << md_image("p99 of pp over the box and field against the windows", "box_p99.png") << "\n";
}

}  // namespace

void write_sensor_principles_report(const SensorPrinciplesResult& r, const SensorPrinciplesOptions& opt,
                                    const StudySetup& setup, StudyOutput& out) {
  // 1. Tables.
  out.write_text("spectra.csv", spectra_csv(r.spectra));
  out.write_text("principles.csv", principles_csv(r));


  // 2. Heat map: pp of each error alone (rows: cases, columns: sensors).
  write_pp_heatmap(r, out.dir());

  // 3. Box: p99 of pp per sensor; field extremes over the box against each window.
  write_box_plot(r, opt, out.dir());

  // 4. summary.md.
  std::ostringstream md;
  md << "# sensor_principles: Hall arrays, in-plane Hall, xMR and AMR on the same magnet and mount\n\n";
  summary_what_ran(md, r, opt, setup);
  summary_each_error_alone(md, r);
  summary_which_principle(md, r);
  summary_tolerance_box(md, r, opt);
  out.write_text("summary.md", md.str());
}

}  // namespace magenc
