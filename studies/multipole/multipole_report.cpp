#include "multipole_report.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analysis/tolerance.hpp"
#include "core/format.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {

std::string g(double v) { return fmt_sig(v, 10); }

PlotSeries series(const std::string& title, const std::string& style = "linespoints") {
  PlotSeries s;
  s.title = title;
  s.style = style;
  return s;
}

std::string interpolation_csv(const MultipoleStudyResult& r) {
  std::ostringstream os;
  os << "gap_mm,array,ce1_deg,ce2_deg,ce3_deg,ce4_deg,pp_deg\n";
  for (const auto& p : r.interpolation) {
    os << g(p.gap_mm) << ',' << p.array;
    for (double c : p.ce_deg) os << ',' << g(c);
    os << ',' << g(p.pp_deg) << '\n';
  }
  return os.str();
}

std::string eccentricity_csv(const MultipoleStudyResult& r) {
  std::ostringstream os;
  os << "e_mm,c1_deg,e_over_r0_deg,c1_over_law,pp_deg\n";
  for (const auto& e : r.eccentricity)
    os << g(e.e_mm) << ',' << g(e.c1_deg) << ',' << g(e.law_deg) << ',' << g(e.c1_deg / e.law_deg) << ','
       << g(e.pp_deg) << '\n';
  return os.str();
}

std::string poles_csv(const MultipoleStudyResult& r) {
  std::ostringstream os;
  os << "pole_seed,pp_deg,c1_deg,ce1_deg,ce2_deg,ce3_deg,ce4_deg\n";
  for (const auto& p : r.poles) {
    os << p.seed << ',' << g(p.pp_deg) << ',' << g(p.c1_deg);
    for (double c : p.ce_deg) os << ',' << g(c);
    os << '\n';
  }
  return os.str();
}

std::string box_csv(const MultipoleStudyResult& r) {
  std::ostringstream os;
  os << "sample,sx_mm,sy_mm,dx_mm,dy_mm,dz_mm,nonius_margin_deg,slipped_samples,pp_deg,max_abs_error_deg\n";
  for (const auto& b : r.box)
    os << b.index << ',' << g(b.mount.sx_mm) << ',' << g(b.mount.sy_mm) << ',' << g(b.mount.dx_mm) << ','
       << g(b.mount.dy_mm) << ',' << g(b.mount.dz_mm) << ',' << g(b.margin_deg) << ',' << b.slipped_samples << ','
       << g(b.pp_deg) << ',' << g(b.max_abs_deg) << '\n';
  return os.str();
}

void interpolation_plot(const MultipoleStudyResult& r, const std::filesystem::path& dir) {
  PlotPanel pp = plot_panel("peak-to-peak error (ideal mount)", "read gap above the top face [mm]", "pp [deg]");
  PlotPanel ce = plot_panel("c_{e4} (order 4p; ring:N has none: its error lies at orders (N +- 1) p)",
                       "read gap above the top face [mm]", "amplitude [deg]");
  pp.logy = true;
  ce.logy = true;
  for (const auto& a : r.options.arrays) {
    PlotSeries s = series(plot_literal(a)), c4 = series(plot_literal(a));
    for (const auto& p : r.interpolation)
      if (p.array == a) {
        s.x.push_back(p.gap_mm);
        s.y.push_back(p.pp_deg > 1e-12 ? p.pp_deg : std::nan(""));
        c4.x.push_back(p.gap_mm);
        c4.y.push_back(p.ce_deg[3] > 1e-12 ? p.ce_deg[3] : std::nan(""));
      }
    pp.series.push_back(s);
    if (std::any_of(c4.y.begin(), c4.y.end(), [](double v) { return !std::isnan(v); })) ce.series.push_back(c4);
  }
  ce.commands = {"set key top right"};
  write_plot(dir, "interpolation", PlotSpec{"Interpolation error of the pole period against read gap (p = " +
                                                std::to_string(r.pole_pairs) + ", r0 = " + fmt(r.r0_mm, 2) + " mm)",
                                            {pp, ce}, 2, 1400, 600});
}

void eccentricity_plot(const MultipoleStudyResult& r, const std::filesystem::path& dir) {
  PlotPanel p = plot_panel("c1 against the e/r law", "dynamic eccentricity e [mm]", "c1 [deg]");
  p.logx = true;
  p.logy = true;
  PlotSeries c1 = series("c1 (exact field, " + plot_literal(r.array) + ")", "points"), law = series("e / r0", "lines");
  for (const auto& e : r.eccentricity) {
    c1.x.push_back(e.e_mm);
    c1.y.push_back(e.c1_deg);
    law.x.push_back(e.e_mm);
    law.y.push_back(e.law_deg);
  }
  p.series = {law, c1};
  p.commands = {"set key top left"};
  write_plot(dir, "eccentricity", PlotSpec{"Eccentricity of a ring encoder: the e/r law", {p}, 1, 800, 600});
}

void poles_plot(const MultipoleStudyResult& r, const std::filesystem::path& dir) {
  PlotPanel p = plot_panel("sorted over the rings (ideal mount)", "fraction of rings", "[deg]");
  std::vector<double> pp, c1;
  for (const auto& s : r.poles) {
    pp.push_back(s.pp_deg);
    c1.push_back(s.c1_deg);
  }
  std::sort(pp.begin(), pp.end());
  std::sort(c1.begin(), c1.end());
  PlotSeries a = series("pp"), b = series("c1");
  for (std::size_t i = 0; i < pp.size(); ++i) {
    const double f = (static_cast<double>(i) + 0.5) / static_cast<double>(pp.size());
    a.x.push_back(f);
    a.y.push_back(pp[i]);
    b.x.push_back(f);
    b.y.push_back(c1[i]);
  }
  p.series = {a, b};
  p.commands = {"set key top left"};
  write_plot(dir, "pole_errors",
             PlotSpec{"Pole errors: edges sigma " + fmt(r.options.pole_edge_sigma_deg, 3) + " deg, amplitudes sigma " +
                          fmt(r.options.pole_amplitude_sigma, 3) + " (" + std::to_string(r.poles.size()) + " rings)",
                      {p}, 1, 900, 600});
}

void box_plot(const MultipoleStudyResult& r, const std::filesystem::path& dir) {
  PlotPanel p = plot_panel("synchronisation margin over the tolerance box (a smaller gap: more interpolation error)",
                      "air-gap change dz [mm]", "margin [master electrical deg]");
  PlotSeries ok = series("no slip", "points"), bad = series("slips (gross error 360/p)", "points");
  for (const auto& b : r.box) {
    PlotSeries& s = b.slipped_samples > 0 ? bad : ok;
    s.x.push_back(b.mount.dz_mm);
    s.y.push_back(b.margin_deg);
  }
  p.series = {ok};
  if (!bad.x.empty()) p.series.push_back(bad);
  p.commands = {"set key bottom right"};
  write_plot(dir, "nonius_margin", PlotSpec{"Nonius (" + std::to_string(r.pole_pairs) + ", " +
                                                std::to_string(r.nonius_pole_pairs) + "): margin against the air gap",
                                            {p}, 1, 900, 650});
}

void interpolation_md(std::ostringstream& os, const MultipoleStudyResult& r) {
  os << "## Interpolation error against read gap and array (ideal ring and mount)\n\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& p : r.interpolation)
    rows.push_back({fmt(p.gap_mm, 2), p.array, fmt_deg(p.ce_deg[0]), fmt_deg(p.ce_deg[1]), fmt_deg(p.ce_deg[2]),
                    fmt_deg(p.ce_deg[3]), fmt_deg(p.pp_deg)});
  os << md_table({"gap [mm]", "array", "ce1", "ce2", "ce3", "ce4", "pp"}, rows) << "\n(deg)\n\n";
  os << "## Eccentricity against the e/r law (" << r.array << ")\n\n";
  rows.clear();
  for (const auto& e : r.eccentricity)
    rows.push_back({fmt(e.e_mm, 3), fmt_deg(e.c1_deg), fmt_deg(e.law_deg), fmt(e.c1_deg / e.law_deg, 5), fmt_deg(e.pp_deg)});
  os << md_table({"e [mm]", "c1 [deg]", "e/r0 [deg]", "c1 / law", "pp [deg]"}, rows) << "\n";
}

void poles_md(std::ostringstream& os, const MultipoleStudyResult& r) {
  std::vector<double> pp, c1, ce1;
  for (const auto& s : r.poles) {
    pp.push_back(s.pp_deg);
    c1.push_back(s.c1_deg);
    ce1.push_back(s.ce_deg[0]);
  }
  os << "## Pole errors (Monte Carlo, " << r.poles.size() << " rings, edge sigma " << fmt(r.options.pole_edge_sigma_deg, 3)
     << " deg, amplitude sigma " << fmt(r.options.pole_amplitude_sigma, 3) << ", ideal mount)\n\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& [name, v] : {std::pair<std::string, const std::vector<double>*>{"pp", &pp}, {"c1", &c1}, {"ce1", &ce1}})
    rows.push_back({name, fmt_deg(percentile(*v, 50)), fmt_deg(percentile(*v, 99)), fmt_deg(percentile(*v, 100))});
  os << md_table({"quantity", "p50 [deg]", "p99 [deg]", "max [deg]"}, rows) << "\n";
}

void box_md(std::ostringstream& os, const MultipoleStudyResult& r) {
  if (r.box.empty()) return;
  const auto& o = r.options;
  os << "## Nonius (" << r.pole_pairs << ", " << r.nonius_pole_pairs << "), r0 " << fmt(r.r0_mm, 2) << " and "
     << fmt(r.nonius_r0_mm, 2) << " mm\n\n"
     << "Ideal mount: margin " << fmt(r.ideal_margin_deg, 3) << " deg, pp " << fmt_deg(r.ideal_pp_deg) << " deg.\n\n"
     << "Tolerance box (" << r.box.size() << " mounts, uniform): sensor sx, sy +-" << fmt(o.box_offset_mm, 3)
     << " mm, magnet dx, dy +-" << fmt(o.box_eccentricity_mm, 3) << " mm, dz +-" << fmt(o.box_dz_mm, 3) << " mm. "
     << (r.box_engine ? "Read by the Monte Carlo engine (docs/multipole.md \"The Monte Carlo engine\"; largest model misfit " +
                            fmt(r.box_engine_misfit_T * 1e9, 2) + " nT), which agrees with the exact field within ~1e-7 deg "
                            "of error and ~1e-4 deg of margin.\n\n"
                      : std::string("Read on the exact field at every mount.\n\n"));
  std::vector<double> margin, pp;
  std::vector<std::vector<std::string>> slips;
  for (const auto& b : r.box) {
    margin.push_back(b.margin_deg);
    if (b.slipped_samples == 0) pp.push_back(b.pp_deg);
    else
      slips.push_back({std::to_string(b.index), fmt(b.mount.sx_mm, 4), fmt(b.mount.sy_mm, 4), fmt(b.mount.dx_mm, 4),
                       fmt(b.mount.dy_mm, 4), fmt(b.mount.dz_mm, 4), fmt(b.margin_deg, 2),
                       std::to_string(b.slipped_samples)});
  }
  os << md_table({"margin p1 [deg]", "p50 [deg]", "p99 [deg]", "mounts that slip"},
                 {{fmt(percentile(margin, 1), 3), fmt(percentile(margin, 50), 3), fmt(percentile(margin, 99), 3),
                   std::to_string(slips.size()) + " of " + std::to_string(r.box.size())}})
     << "\n";
  if (!pp.empty())
    os << "Error of the mounts that do not slip: pp p50 " << fmt_deg(percentile(pp, 50)) << ", p99 "
       << fmt_deg(percentile(pp, 99)) << " deg (a slip is a gross error of " << fmt(360.0 / r.pole_pairs, 4)
       << " deg, counted apart).\n\n";
  if (!slips.empty())
    os << "Mounts that slip:\n\n"
       << md_table({"sample", "sx", "sy", "dx", "dy", "dz [mm]", "margin [deg]", "slipped samples"}, slips) << "\n";
}

std::string summary_md(const MultipoleStudyResult& r) {
  std::ostringstream os;
  os << "# multipole: a multipole code ring, electrical read heads and a nonius track\n\n"
     << "Exact field of the sectors; p = " << r.pole_pairs << " pole pairs, read radius " << fmt(r.r0_mm, 3)
     << " mm (pole pitch " << fmt(r.pole_pitch_mm, 4) << " mm there), gap " << fmt(r.gap_mm, 3) << " mm, "
     << r.options.steps << " samples per turn, incremental reading (docs/physics.md \"Multipole rings and nonius\").\n\n";
  interpolation_md(os, r);
  poles_md(os, r);
  box_md(os, r);
  return os.str();
}

}  // namespace

void write_multipole_report(StudyOutput& out, const MultipoleStudyResult& r) {
  out.write_text("interpolation.csv", interpolation_csv(r));
  out.write_text("eccentricity.csv", eccentricity_csv(r));
  out.write_text("pole_errors.csv", poles_csv(r));
  interpolation_plot(r, out.dir());
  eccentricity_plot(r, out.dir());
  poles_plot(r, out.dir());
  if (!r.box.empty()) {
    out.write_text("nonius_box.csv", box_csv(r));
    box_plot(r, out.dir());
  }
  out.write_text("summary.md", summary_md(r));
}

}  // namespace magenc
