#include "studies/calibration/calibration_report.hpp"

#include <sstream>

#include "report/setup_text.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {

std::string g6(double v) { return fmt_sig(v, 6); }

// residual.csv: every sensor x scenario x method; residual_spectra.csv: mean c_n at the drift box.
void write_tables(const CalibrationStudyResult& r, StudyOutput& out) {
  const auto nm = static_cast<Eigen::Index>(r.methods.size());
  std::ostringstream csv;
  csv << "sensor,scenario,method,p50_pp_deg,p99_pp_deg,uncalibrated_p50_pp_deg,uncalibrated_p99_pp_deg\n";
  for (const auto& s : r.sensors)
    for (std::size_t k = 0; k < s.scenarios.size(); ++k)
      for (Eigen::Index m = 0; m < nm; ++m)
        csv << s.label << "," << s.scenarios[k] << "," << r.methods[static_cast<std::size_t>(m)].name() << ","
            << g6(s.p50(static_cast<Eigen::Index>(k), m)) << "," << g6(s.p99(static_cast<Eigen::Index>(k), m)) << ","
            << g6(s.uncal_p50[static_cast<Eigen::Index>(k)]) << "," << g6(s.uncal_p99[static_cast<Eigen::Index>(k)]) << "\n";
  out.write_text("residual.csv", csv.str());
  std::ostringstream sp;
  sp << "sensor,method,c1_deg,c2_deg,c3_deg,c4_deg,c5_deg,c6_deg,c7_deg,c8_deg\n";
  for (const auto& s : r.sensors) {
    sp << s.label << ",none";
    for (int n = 0; n < 8; ++n) sp << "," << g6(s.uncal_mean_c[n]);
    sp << "\n";
    for (Eigen::Index m = 0; m < nm; ++m) {
      sp << s.label << "," << r.methods[static_cast<std::size_t>(m)].name();
      for (int n = 0; n < 8; ++n) sp << "," << g6(s.mean_c(m, n));
      sp << "\n";
    }
  }
  out.write_text("residual_spectra.csv", sp.str());

}

// p99_vs_drift.png: p99 vs drift scale, a panel per method, a line per sensor.
void write_drift_plot(const CalibrationStudyResult& r, const CalibrationStudyOptions& opt, StudyOutput& out) {
  const auto nm = static_cast<Eigen::Index>(r.methods.size());
  PlotSpec scan;
  scan.title = "p99 of the residual pp after the factory correction vs drift box scale (1 = the configured box)";
  scan.columns = static_cast<int>(std::min<Eigen::Index>(nm, 3));
  for (Eigen::Index m = 0; m < nm; ++m) {
    PlotPanel p;
    p.title = plot_literal(r.methods[static_cast<std::size_t>(m)].name());
    p.xlabel = "drift box scale";
    p.ylabel = "p99 residual pp [deg]";
    p.logy = true;
    p.logx = true;
    // The key under the panel: inside it covered curves (ogp's are flat, across the whole width).
    p.commands = {"set key below horizontal nobox noopaque", "set xtics (0.25, 0.5, 1, 2)", "set xrange [0.2:2.5]"};
    for (const auto& s : r.sensors) {
      PlotSeries ser;
      ser.title = plot_literal(s.label);
      ser.style = "linespoints";
      for (std::size_t k = 0; k < opt.scales.size(); ++k) {
        ser.x.push_back(opt.scales[k]);
        ser.y.push_back(std::max(s.p99(static_cast<Eigen::Index>(k + 1), m), 1e-9));
      }
      p.series.push_back(ser);
    }
    scan.panels.push_back(p);
  }
  scan.height_px = 500;
  write_plot(out.dir(), "p99_vs_drift", scan);

}

// residual_spectra.png: mean residual spectra, a panel per sensor.
void write_spectra_plot(const CalibrationStudyResult& r, StudyOutput& out) {
  const auto nm = static_cast<Eigen::Index>(r.methods.size());
  PlotSpec spec;
  spec.title = "mean harmonic amplitudes at the drift box: uncalibrated and after each correction";
  spec.columns = 2;
  for (const auto& s : r.sensors) {
    PlotPanel p;
    p.title = plot_literal(s.label);
    p.xlabel = "harmonic n";
    p.ylabel = "mean c_n [deg]";
    p.logy = true;
    p.commands = {"set xtics 1", "set xrange [0.5:8.5]", "set format y '%g'", "set key bottom left"};
    PlotSeries u;
    u.title = "uncalibrated";
    u.style = "linespoints";
    for (int n = 0; n < 8; ++n) {
      u.x.push_back(n + 1);
      u.y.push_back(std::max(s.uncal_mean_c[n], 1e-9));
    }
    p.series.push_back(u);
    for (Eigen::Index m = 0; m < nm; ++m) {
      PlotSeries ser;
      ser.title = plot_literal(r.methods[static_cast<std::size_t>(m)].name());
      ser.style = "linespoints";
      for (int n = 0; n < 8; ++n) {
        ser.x.push_back(n + 1);
        ser.y.push_back(std::max(s.mean_c(m, n), 1e-9));
      }
      p.series.push_back(ser);
    }
    spec.panels.push_back(p);
  }
  spec.height_px = 350 * static_cast<int>((r.sensors.size() + 1) / 2);
  write_plot(out.dir(), "residual_spectra", spec);

}

// summary.md: the residual at the drift box beside the uncalibrated p99, and the budget per drift key.
void write_summary(const CalibrationStudyResult& r, const CalibrationStudyOptions& opt, const StudySetup& setup, StudyOutput& out) {
  const auto nm = static_cast<Eigen::Index>(r.methods.size());
  std::ostringstream md;
  md << "# calibration: what is left of the factory correction after a drift\n\n"
     << "Field " << r.field << "; " << opt.samples << " factory states (seed " << opt.seed << ") in the tolerance box "
     << "sx, sy +-" << g6(opt.box.sx_mm) << " mm, dx, dy +-" << g6(opt.box.dx_mm) << "/" << g6(opt.box.dy_mm)
     << " mm, dz +-" << g6(opt.box.dz_mm) << " mm; each calibrated there and run after one drift draw from the drift box:";
  for (const auto& d : opt.drift) md << " " << d.key << " +-" << g6(d.half_width) << ";";
  md << " " << opt.mc_steps << " samples per turn; r0 " << g6(setup.r0_mm) << " mm for the bz arrays. "
     << "Wall time " << fmt_sig(r.wall_s, 3) << " s.\n\n";
  md << "## Residual pp at the drift box (p50 / p99, deg) beside the uncalibrated p99\n\n";
  std::vector<std::string> head{"sensor", "uncalibrated p99"};
  for (const auto& m : r.methods) head.push_back(m.name() + " p50 / p99");
  head.push_back("factory state itself, p99 per method");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : r.sensors) {
    const auto k = static_cast<Eigen::Index>(s.scale1);
    std::vector<std::string> row{s.label, fmt_deg(s.uncal_p99[k])};
    std::string self;
    for (Eigen::Index m = 0; m < nm; ++m) {
      row.push_back(fmt_deg(s.p50(k, m)) + " / " + fmt_deg(s.p99(k, m)));
      self += (m ? ", " : "") + fmt_deg(s.p99(0, m));
    }
    row.push_back(self);
    rows.push_back(row);
  }
  md << md_table(head, rows) << "\n";
  md << "## Budget: p99 of the residual pp with each drift key alone (deg)\n\n";
  std::vector<std::string> bh{"sensor", "method"};
  for (const auto& d : opt.drift) bh.push_back(d.key);
  bh.push_back("dominant");
  std::vector<std::vector<std::string>> brows;
  const std::size_t first_alone = 1 + opt.scales.size();
  for (const auto& s : r.sensors)
    for (Eigen::Index m = 0; m < nm; ++m) {
      std::vector<std::string> row{s.label, r.methods[static_cast<std::size_t>(m)].name()};
      double best = -1;
      std::string dom;
      for (std::size_t j = 0; j < opt.drift.size(); ++j) {
        const double v = s.p99(static_cast<Eigen::Index>(first_alone + j), m);
        row.push_back(fmt_deg(v));
        if (v > best) best = v, dom = opt.drift[j].key;
      }
      row.push_back(dom);
      brows.push_back(row);
    }
  md << md_table(bh, brows) << "\n";
  md << md_image("p99 of the residual vs drift size", "p99_vs_drift.png") << "\n\n"
     << md_image("mean residual spectra", "residual_spectra.png") << "\n\n"
     << "Tables: residual.csv (every scenario), residual_spectra.csv. Method: docs/physics.md \"Calibration\".\n";
  out.write_text("summary.md", md.str());
}

}  // namespace

void write_calibration_report(const CalibrationStudyResult& r, const CalibrationStudyOptions& opt, const StudySetup& setup,
                              StudyOutput& out) {
  write_tables(r, out);
  write_drift_plot(r, opt, out);
  write_spectra_plot(r, out);
  write_summary(r, opt, setup, out);
}

}  // namespace magenc
