#include "off_axis_report.hpp"

#include <cmath>
#include <sstream>

#include "core/format.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {

std::string csv_num(double v) { return fmt_sig(v, 10); }

void write_tables(const OffAxisResult& r, const OffAxisOptions& o, StudyOutput& out) {
  std::ostringstream rd, bd, ss, sg, fm;
  rd << "reader,layout,principle,treatment,direction,zero_deg,gain_mismatch,nominal_pp_deg,p50_pp_deg,p99_pp_deg";
  for (int n = 1; n <= 8; ++n) rd << ",mean_c" << n << "_deg";
  rd << ",field_min_mT,field_max_mT\n";
  bd << "reader";
  for (const auto& g : r.groups) bd << ",p99_" << g << "_deg";
  bd << "\n";
  for (const auto& x : r.readers) {
    rd << x.label << "," << x.layout << "," << x.principle << "," << x.treatment << "," << x.setup.orientation.direction
       << "," << csv_num(x.setup.orientation.zero_deg) << "," << csv_num(x.setup.chain.gain_mismatch) << ","
       << csv_num(x.nominal_pp_deg) << "," << csv_num(x.p50_deg) << "," << csv_num(x.p99_deg);
    for (int n = 0; n < 8; ++n) rd << "," << csv_num(x.mean_c_deg[n]);
    rd << "," << csv_num(x.field_min_mT) << "," << csv_num(x.field_max_mT) << "\n";
    bd << x.label;
    for (double v : x.budget_p99_deg) bd << "," << csv_num(v);
    bd << "\n";
  }
  ss << "side_x_mm,k,p99_raw_deg,p99_trimmed_deg\n";
  for (std::size_t i = 0; i < o.scan_side_x_mm.size(); ++i)
    ss << csv_num(o.scan_side_x_mm[i]) << "," << csv_num(r.scan_side_k[i]) << "," << csv_num(r.scan_side_p99_raw[i])
       << "," << csv_num(r.scan_side_p99_trim[i]) << "\n";
  sg << "gap_mm";
  for (const auto& a : o.bore_arrays) sg << ",p99_" << a << "_deg";
  sg << "\n";
  for (std::size_t j = 0; j < o.scan_gap_mm.size(); ++j) {
    sg << csv_num(o.scan_gap_mm[j]);
    for (const auto& row : r.scan_gap_p99) sg << "," << csv_num(row[j]);
    sg << "\n";
  }
  fm << "x_mm,y_mm,b_inplane_mT\n";
  const std::size_t n = r.map_x_mm.size();
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < n; ++i)
      fm << csv_num(r.map_x_mm[i]) << "," << csv_num(r.map_y_mm[n - 1 - j]) << "," << csv_num(r.map_mT[j][i]) << "\n";
  out.write_text("readers.csv", rd.str());
  out.write_text("budget.csv", bd.str());
  out.write_text("scan_side.csv", ss.str());
  out.write_text("scan_gap.csv", sg.str());
  out.write_text("field_map.csv", fm.str());
}

PlotSeries series(const std::string& title, const std::vector<double>& x, const std::vector<double>& y,
                  const std::string& style = "linespoints") {
  PlotSeries s;
  s.title = title;
  s.x = x;
  s.y = y;
  s.style = style;
  return s;
}

PlotSeries curve(const std::string& title, const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  PlotSeries s;
  s.title = plot_literal(title);
  s.x.assign(x.data(), x.data() + x.size());
  s.y.assign(y.data(), y.data() + y.size());
  return s;
}

void write_plots(const OffAxisResult& r, const OffAxisOptions& o, StudyOutput& out) {
  PlotSpec curves;
  curves.title = "Nominal mount: angle error of each reader";
  curves.columns = 2;
  PlotPanel raw = plot_panel("pp above 5 deg: raw, and what a correction leaves of it", "{/Symbol q} [deg]", "error [deg]");
  PlotPanel fixed = plot_panel("pp below 5 deg: trimmed or calibrated, bore arrays", "{/Symbol q} [deg]", "error [deg]");
  raw.commands = {"set xrange [0:360]", "set xtics 90", "set key outside bottom"};
  fixed.commands = raw.commands;
  for (const auto& x : r.readers)
    (x.nominal_pp_deg > 5.0 ? raw : fixed).series.push_back(curve(x.label, r.theta_deg, x.nominal_eps_deg));
  curves.panels = {raw, fixed};
  curves.width_px = 1400;
  curves.height_px = 750;
  write_plot(out.dir(), "error_curves", curves);

  PlotSpec scans;
  scans.title = "p99 of pp over the tolerance box";
  scans.columns = 2;
  PlotPanel side = plot_panel("side-shaft: read radius", "die centre x [mm]", "p99 pp [deg]");
  side.logy = true;
  side.series.push_back(series("raw", o.scan_side_x_mm, r.scan_side_p99_raw));
  side.series.push_back(series("trimmed (BCT)", o.scan_side_x_mm, r.scan_side_p99_trim));
  PlotPanel gap = plot_panel("bore arrays: gap above the ring", "plane height above the top face [mm]", "p99 pp [deg]");
  gap.logy = true;
  for (std::size_t a = 0; a < o.bore_arrays.size(); ++a)
    gap.series.push_back(series(plot_literal(o.bore_arrays[a]), o.scan_gap_mm, r.scan_gap_p99[a]));
  scans.panels = {side, gap};
  scans.width_px = 1300;
  scans.height_px = 550;
  write_plot(out.dir(), "p99_scans", scans);

  PlotSpec spectra;
  spectra.title = "Mean harmonic amplitude over the box";
  PlotPanel sp = plot_panel("", "harmonic n", "mean c_n [deg]");
  sp.logy = true;
  sp.commands = {"set xtics 1", "set key outside right"};
  for (const auto& x : r.readers) {
    PlotSeries s = series(plot_literal(x.label), {}, {});
    for (int n = 1; n <= 8; ++n) {
      s.x.push_back(n);
      s.y.push_back(std::max(x.mean_c_deg[n - 1], 1e-9));
    }
    sp.series.push_back(s);
  }
  spectra.panels = {sp};
  spectra.width_px = 1300;
  write_plot(out.dir(), "spectra", spectra);

  HeatmapSpec map;
  map.title = "In-plane |B| on the ring's mid-plane (material blank); S = side-shaft chip, A = bore-array probes (above)";
  map.xlabel = "x [mm]";
  map.ylabel = "y [mm]";
  const std::size_t n = r.map_x_mm.size();
  for (std::size_t i = 0; i < n; ++i) {
    map.column_labels.push_back(i % 8 == 0 ? fmt(r.map_x_mm[i], 0) : "");
    map.row_labels.push_back(i % 8 == 0 ? fmt(r.map_y_mm[n - 1 - i], 0) : "");
  }
  map.values = r.map_mT;  // the material blank: the colours show the field the sensors can reach
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < n; ++i)
      if (r.magnet.contains_mm(r.map_x_mm[i], r.map_y_mm[n - 1 - j], 0.0)) map.values[j][i] = std::nan("");
  map.cell_text.assign(n, std::vector<std::string>(n, ""));
  const double step = r.map_x_mm[1] - r.map_x_mm[0], x0 = r.map_x_mm[0];
  auto mark = [&](double x, double y, const char* text) {
    const long i = std::lround((x - x0) / step), j = static_cast<long>(n) - 1 - std::lround((y - x0) / step);
    if (i >= 0 && j >= 0 && i < static_cast<long>(n) && j < static_cast<long>(n))
      map.cell_text[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)] = text;
  };
  mark(o.side_center_mm.x(), o.side_center_mm.y(), "S");
  for (int k = 0; k < 8; ++k) mark(o.bore_r0_mm * std::cos(k * 0.7853981633974483), o.bore_r0_mm * std::sin(k * 0.7853981633974483), "A");
  map.cblabel = "|B_{xy}| [mT]";
  map.log_colour = true;
  map.log_floor = 1.0;
  map.cell_font_size = 7;
  write_heatmap(out.dir(), "field_map", map);
}

void write_summary(const OffAxisResult& r, const OffAxisOptions& o, StudyOutput& out) {
  std::ostringstream md;
  const Magnet& m = r.magnet;
  md << "# off_axis: a ring magnet read beside the ring and around the bore\n\n"
     << "- Ring R = " << fmt(m.radius_mm, 2) << " mm, Ri = " << fmt(m.inner_radius_mm, 2) << " mm, L = "
     << fmt(m.height_mm, 2) << " mm, Br = " << fmt(m.br_T, 3) << " T (exact field).\n"
     << "- Side-shaft chip at [" << fmt(o.side_center_mm.x(), 2) << ", " << fmt(o.side_center_mm.y(), 2)
     << "] mm, plane " << fmt(o.side_height_mm, 2) << " mm above the top face; bore arrays at r0 = "
     << fmt(o.bore_r0_mm, 2) << " mm, " << fmt(o.bore_height_mm, 2) << " mm above it.\n"
     << "- Ellipse of the side-shaft field: k = " << fmt(r.k, 5) << " (c2 = q rad with q = (k-1)/(k+1) = "
     << fmt((r.k - 1) / (r.k + 1), 5) << "); the gain trim sets gain_mismatch = " << fmt(r.trim_gain_mismatch, 6)
     << "; ogp's ellipse at the nominal mount gives 1/r - 1 = " << fmt(r.ogp_trim, 6) << ".\n"
     << "- Tolerance box (half-widths): sx " << fmt(o.box.sx_mm, 3) << ", sy " << fmt(o.box.sy_mm, 3) << ", dx "
     << fmt(o.box.dx_mm, 3) << ", dy " << fmt(o.box.dy_mm, 3) << ", dz " << fmt(o.box.dz_mm, 3) << " mm; sensor tilt "
     << fmt(o.box.tilt_x_deg, 2) << "/" << fmt(o.box.tilt_y_deg, 2) << " deg, magnet lean " << fmt(o.box.magnet_tilt_deg, 2)
     << " deg; " << o.samples << " samples, " << o.steps << " steps per turn. Calibrations are taken at the nominal mount.\n\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& x : r.readers)
    rows.push_back({x.label, fmt_deg(x.nominal_pp_deg), fmt_deg(x.p50_deg), fmt_deg(x.p99_deg),
                    fmt(x.field_min_mT, 1) + " - " + fmt(x.field_max_mT, 1)});
  md << "## Readers over the box\n\n"
     << md_table({"reader", "nominal pp [deg]", "p50 pp [deg]", "p99 pp [deg]", "field [mT]"}, rows) << "\n";
  std::vector<std::string> head{"reader"};
  for (const auto& g : r.groups) head.push_back(g + " p99 [deg]");
  rows.clear();
  for (const auto& x : r.readers) {
    std::vector<std::string> row{x.label};
    for (double v : x.budget_p99_deg) row.push_back(fmt_deg(v));
    rows.push_back(row);
  }
  md << "## Budget: each group of the box alone\n\n" << md_table(head, rows) << "\n";
  md << md_image("nominal curves", "error_curves.png") << "\n\n" << md_image("p99 scans", "p99_scans.png") << "\n\n"
     << md_image("mean spectra", "spectra.png") << "\n\n" << md_image("field map", "field_map.png") << "\n\n"
     << "Wall time " << fmt(r.wall_s, 1) << " s.\n";
  out.write_text("summary.md", md.str());
}

}  // namespace

void write_off_axis_report(const OffAxisResult& r, const OffAxisOptions& o, StudyOutput& out) {
  write_tables(r, o, out);
  write_plots(r, o, out);
  write_summary(r, o, out);
}

}  // namespace magenc
