#include "studies/temperature/temperature_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "report/setup_text.hpp"
#include "core/format.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {
std::string g10(double v) { return fmt_sig(v, 10); }
std::string mT_text(double v) { return std::isinf(v) ? std::string(v > 0 ? "inf" : "-inf") : fmt(v, 2); }

const TemperaturePoint& at(const TemperatureCurve& c, double t) {
  const TemperaturePoint* best = &c.points.front();
  for (const auto& p : c.points)
    if (std::abs(p.temperature_C - t) < std::abs(best->temperature_C - t)) best = &p;
  return *best;
}
// pp_vs_temperature.png: pp against temperature, the configured mount and the box's p99 sample.
void write_pp_plot(const TemperatureResult& r, StudyOutput& out) {
  PlotSpec ps;
  ps.title = "Angle error against temperature (" + r.field + " field; Br coefficient " +
             fmt_sig(r.coefficients.br_tc_per_K, 4) + "/K)";
  ps.columns = 2;
  ps.width_px = 1400;
  ps.height_px = 650;
  for (const char* label : {"mount", "box p99"}) {
    PlotPanel p;
    p.title = std::string(label == std::string("mount") ? "the configured mount" : "the box's p99 sample (per sensor)");
    p.xlabel = "temperature [C]";
    p.ylabel = "pp [deg]";
    for (const auto& c : r.curves) {
      if (c.mount_label != label) continue;
      PlotSeries s{plot_literal(c.sensor), {}, {}, "linespoints", "lw 2"};
      for (const auto& pt : c.points) {
        s.x.push_back(pt.temperature_C);
        s.y.push_back(pt.spectrum.pp_deg);
      }
      p.series.push_back(s);
    }
    p.commands = {"set grid", "set key top left"};
    ps.panels.push_back(p);
  }
  write_plot(out.dir(), "pp_vs_temperature", ps);
}

// field_vs_temperature.png: the field the chip needs against temperature, with the window.
void write_field_plot(const TemperatureResult& r, StudyOutput& out) {
  PlotSpec ps;
  ps.title = "Field the chip needs against temperature (bz: peak |Bz| per probe; inplane: |(b1, b2)|)";
  ps.width_px = 1100;
  ps.height_px = 650;
  PlotPanel p;
  p.xlabel = "temperature [C]";
  p.ylabel = "field [mT]";
  for (const auto& c : r.curves) {
    if (c.mount_label != "box p99") continue;
    PlotSeries lo{plot_literal(c.sensor) + " min", {}, {}, "linespoints", "lw 2"};
    PlotSeries hi{plot_literal(c.sensor) + " max", {}, {}, "lines", "lw 1 dt 2"};
    for (const auto& pt : c.points) {
      lo.x.push_back(pt.temperature_C);
      lo.y.push_back(pt.field_min_mT);
      hi.x.push_back(pt.temperature_C);
      hi.y.push_back(pt.field_max_mT);
    }
    p.series.push_back(lo);
    p.series.push_back(hi);
  }
  double ylo = std::numeric_limits<double>::infinity(), yhi = 0;
  for (const auto& c : r.curves)
    for (const auto& pt : c.points) {
      ylo = std::min(ylo, pt.field_min_mT);
      yhi = std::max(yhi, pt.field_max_mT);
    }
  if (r.window.min_mT > 0) ylo = std::min(ylo, r.window.min_mT);
  if (!std::isinf(r.window.max_mT)) yhi = std::max(yhi, r.window.max_mT);
  p.commands = {"set grid", "set key outside right",
                "set yrange [" + fmt_sig(ylo - 3, 6) + ":" + fmt_sig(yhi + 3, 6) + "]"};
  if (r.window.min_mT > 0)
    p.commands.push_back("set arrow from graph 0, first " + fmt_sig(r.window.min_mT, 6) + " to graph 1, first " +
                         fmt_sig(r.window.min_mT, 6) + " nohead lw 2 lc rgb 'red'");
  if (!std::isinf(r.window.max_mT))
    p.commands.push_back("set arrow from graph 0, first " + fmt_sig(r.window.max_mT, 6) + " to graph 1, first " +
                         fmt_sig(r.window.max_mT, 6) + " nohead lw 2 lc rgb 'red'");
  p.title = "box p99 mounts; red: the window (" + mT_text(r.window.min_mT) + " .. " + mT_text(r.window.max_mT) + " mT)";
  ps.panels.push_back(p);
  write_plot(out.dir(), "field_vs_temperature", ps);
}

// summary.md: what ran, pp and the field margin at the extremes.
void write_summary(const TemperatureResult& r, const TemperatureOptions& opt, const StudySetup& setup, StudyOutput& out) {
  const Environment& e = r.coefficients;
  std::ostringstream md;
  md << "# temperature: error spectra and field margin from " << fmt(opt.temperature_min_C, 0) << " to "
     << fmt(opt.temperature_max_C, 0) << " C\n\n## What ran\n\n";
  md << "- Field `" << r.field << "`: magnet " << magnet_text(setup) << " at 20 C; Br(T) = Br (1 + " << fmt_sig(e.br_tc_per_K, 4) << " (T - 20))"
     << (setup.magnet_material != "none" ? " (magnet.material `" + setup.magnet_material + "`)" : "")
     << "; offset drift " << fmt_sig(e.offset_cos_tc_uT_per_K, 4) << " / " << fmt_sig(e.offset_sin_tc_uT_per_K, 4)
     << " uT/K (cos / sin) on offsets " << fmt_sig(setup.offset_cos_mT, 4) << " / "
     << fmt_sig(setup.offset_sin_mT, 4) << " mT at 20 C; air-gap drift " << fmt_sig(e.dz_tc_um_per_K, 4)
     << " um/K.\n";
  md << "- Temperatures every " << fmt_sig(opt.temperature_step_K, 4) << " K; " << opt.steps
     << " samples per turn; field window " << mT_text(r.window.min_mT) << " .. " << mT_text(r.window.max_mT)
     << " mT (sensor.field_min_mT, field_max_mT) for every sensor.\n";
  md << "- Mounts: the configured one (sx " << fmt(r.curves.front().mount.sx_mm, 3) << ", dx "
     << fmt(r.curves.front().mount.dx_mm, 3) << ", dz " << fmt(r.curves.front().mount.dz_mm, 3)
     << " mm, ...), and per sensor the sample of " << opt.samples
     << " in the tolerance box (seed " << opt.seed << "; |sx|, |sy| <= " << fmt(opt.box.sx_mm, 3) << ", |dx|, |dy| <= "
     << fmt(opt.box.dx_mm, 3) << ", |dz| <= " << fmt(opt.box.dz_mm, 3) << " mm, tilts <= " << fmt(opt.box.tilt_x_deg, 2)
     << " deg) whose pp at 20 C is nearest the box's 99th percentile.\n";
  md << "- Table: `temperature.csv`.\n\n";
  md << "## pp and the field margin at the extremes\n\n";
  std::vector<std::vector<std::string>> t;
  for (const auto& c : r.curves) {
    const auto &lo = c.points.front(), &mid = at(c, 20.0), &hi = c.points.back();
    double mlo = std::numeric_limits<double>::infinity(), mhi = mlo;
    bool all_in = true;
    for (const auto& p : c.points) {
      mlo = std::min(mlo, p.margin_low_mT);
      mhi = std::min(mhi, p.margin_high_mT);
      all_in = all_in && p.in_window;
    }
    t.push_back({"`" + c.sensor + "`", c.mount_label, fmt_deg(lo.spectrum.pp_deg), fmt_deg(mid.spectrum.pp_deg),
                 fmt_deg(hi.spectrum.pp_deg), fmt_deg(lo.spectrum.c_deg[1]) + " / " + fmt_deg(hi.spectrum.c_deg[1]),
                 mT_text(hi.field_min_mT) + " .. " + mT_text(lo.field_max_mT), mT_text(mlo) + " / " + mT_text(mhi),
                 all_in ? "yes" : "no"});
  }
  md << md_table({"sensor", "mount", "pp at " + fmt(opt.temperature_min_C, 0) + " C [deg]", "pp at 20 C [deg]",
                  "pp at " + fmt(opt.temperature_max_C, 0) + " C [deg]", "c1 cold / hot [deg]",
                  "field over the range [mT]", "least margin low / high [mT]", "in window throughout"},
                 t)
     << "\n";
  md << "Br(T)/Br: " << fmt(r.curves.front().points.front().br_scale, 3) << " at " << fmt(opt.temperature_min_C, 0)
     << " C, " << fmt(r.curves.front().points.back().br_scale, 3) << " at " << fmt(opt.temperature_max_C, 0)
     << " C. The angle is a ratio of channels: Br alone cancels; what changes is offset/amplitude (the offsets "
        "drift while the amplitude follows Br), the air gap, and the field against the window.\n\n";
  md << md_image("pp against temperature", "pp_vs_temperature.png") << "\n\n";
  md << md_image("field against temperature", "field_vs_temperature.png") << "\n";
  out.write_text("summary.md", md.str());
}

}  // namespace

std::string temperature_csv(const TemperatureResult& r) {
  std::ostringstream os;
  os << "sensor,mount,temperature_C,br_scale,pp_deg,a0_deg,c1_deg,c2_deg,c3_deg,c4_deg,field_min_mT,field_max_mT,"
        "in_window,margin_low_mT,margin_high_mT,sx_mm,sy_mm,dx_mm,dy_mm,dz_mm,tilt_x_deg,tilt_y_deg\n";
  for (const auto& c : r.curves)
    for (const auto& p : c.points)
      os << c.sensor << "," << c.mount_label << "," << g10(p.temperature_C) << "," << g10(p.br_scale) << ","
         << g10(p.spectrum.pp_deg) << "," << g10(p.spectrum.a0_deg) << "," << g10(p.spectrum.c_deg[1]) << ","
         << g10(p.spectrum.c_deg[2]) << "," << g10(p.spectrum.c_deg[3]) << "," << g10(p.spectrum.c_deg[4]) << ","
         << g10(p.field_min_mT) << "," << g10(p.field_max_mT) << "," << (p.in_window ? "true" : "false") << ","
         << g10(p.margin_low_mT) << "," << g10(p.margin_high_mT) << "," << g10(c.mount.sx_mm) << ","
         << g10(c.mount.sy_mm) << "," << g10(c.mount.dx_mm) << "," << g10(c.mount.dy_mm) << "," << g10(c.mount.dz_mm)
         << "," << g10(c.mount.tilt_x_deg) << "," << g10(c.mount.tilt_y_deg) << "\n";
  return os.str();
}

void write_temperature_report(const TemperatureResult& r, const TemperatureOptions& opt, const StudySetup& setup,
                              StudyOutput& out) {
  out.write_text("temperature.csv", temperature_csv(r));
  write_pp_plot(r, out);
  write_field_plot(r, out);
  write_summary(r, opt, setup, out);
}

}  // namespace magenc
