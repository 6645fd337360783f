#include "studies/design/design_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/format.hpp"
#include "io/plot.hpp"
#include "report/study_output.hpp"

namespace magenc {

namespace {

std::string num10(double v) { return std::isfinite(v) ? fmt_sig(v, 10) : std::string(v > 0 ? "inf" : "nan"); }
std::string g3(double v) { return std::isfinite(v) ? fmt_sig(v, 3) : std::string(v > 0 ? "inf" : "nan"); }

std::string design_text(const DesignOptions& o, const Design& d) {
  const std::string magnet = d.material + " R " + g3(d.magnet_radius_mm) + " mm" +
                             (d.magnet_inner_radius_mm > 0 ? " (ring, Ri " + g3(d.magnet_inner_radius_mm) + " mm)" : "") +
                             " x L " + g3(d.magnet_height_mm) + " mm, ";
  if (d.side)
    return magnet + o.space.sensor_name(d.sensor) + " at r " + g3(d.side_radius_mm) + " mm, " +
           g3(d.side_height_mm) + " mm above the mid-plane";
  return magnet + "gap " + g3(d.gap_mm) + " mm, " + o.space.sensor_name(d.sensor) + " at r0 " + g3(d.r0_mm) + " mm";
}

// The sensor whose best design (field in the window) has the smallest p99: the recommended design's when
// there is one.
std::size_t best_sensor(const DesignOptions& o, const DesignStudyResult& r) {
  if (r.recommended >= 0) return r.designs[static_cast<std::size_t>(r.recommended)].sensor;
  std::size_t best = 0;
  double p = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < r.designs.size(); ++i)
    if (r.results[i].p99_req_deg(o.req) < p) {
      p = r.results[i].p99_req_deg(o.req);
      best = r.designs[i].sensor;
    }
  return best;
}

}  // namespace

namespace {
// Ring magnets in the space (design.magnet_inner_radius_mm other than [0]): designs.csv adds the column
// magnet_inner_radius_mm after magnet_radius_mm; a space of solid magnets writes the columns of before.
bool has_rings(const DesignOptions& o) {
  return std::any_of(o.space.magnet_inner_radius_mm.begin(), o.space.magnet_inner_radius_mm.end(),
                     [](double ri) { return ri != 0.0; });
}
// Side-shaft readers in the space (design.side_principles): designs.csv adds side_radius_mm, side_height_mm
// after r0_mm (NaN for a Bz array; gap_mm and r0_mm NaN for a side-shaft reader).
bool has_side(const DesignOptions& o) { return !o.space.side_principles.empty(); }
}  // namespace

std::string design_csv(const DesignOptions& o, const DesignStudyResult& r) {
  std::ostringstream os;
  const bool rings = has_rings(o), side = has_side(o);
  os << "index,material,br_T,magnet_radius_mm," << (rings ? "magnet_inner_radius_mm," : "")
     << "magnet_height_mm,gap_mm,sensor,r0_mm," << (side ? "side_radius_mm,side_height_mm," : "") << "volume_mm3,seed,"
        "bz_amplitude_mT,p50_uncal_deg,p99_uncal_deg,p50_cal_deg,p99_cal_deg,field_min_mT,field_max_mT,"
        "field_lo_mT,field_hi_mT,margin_mT,pass,reason\n";
  for (std::size_t i = 0; i < r.designs.size(); ++i) {
    const Design& d = r.designs[i];
    const DesignResult& x = r.results[i];
    os << d.index << "," << d.material << "," << num10(d.br_T) << "," << num10(d.magnet_radius_mm) << ",";
    if (rings) os << num10(d.magnet_inner_radius_mm) << ",";
    os << num10(d.magnet_height_mm) << "," << num10(d.gap_mm) << "," << o.space.sensor_name(d.sensor) << ","
       << num10(d.r0_mm) << ",";
    if (side) os << num10(d.side_radius_mm) << "," << num10(d.side_height_mm) << ",";
    os << num10(d.volume_mm3()) << "," << design_seed(o, d.index) << ","
       << num10(x.bz_amplitude_mT) << "," << num10(x.p50_uncal_deg) << "," << num10(x.p99_uncal_deg) << ","
       << num10(x.p50_cal_deg) << "," << num10(x.p99_cal_deg) << "," << num10(x.field_min_mT) << ","
       << num10(x.field_max_mT) << "," << num10(x.field_lo_mT) << "," << num10(x.field_hi_mT) << ","
       << num10(x.margin_mT) << "," << (x.pass(o.req) ? 1 : 0) << "," << x.reason(o.req) << "\n";
  }
  return os.str();
}

std::string design_pareto_csv(const DesignOptions& o, const DesignStudyResult& r) {
  std::ostringstream os;
  os << "sensor,index,volume_mm3,p99_deg,pass\n";
  for (std::size_t s = 0; s < r.pareto.size(); ++s)
    for (std::size_t i : r.pareto[s])
      os << o.space.sensor_name(s) << "," << i << "," << num10(r.designs[i].volume_mm3()) << ","
         << num10(r.results[i].p99_req_deg(o.req)) << "," << (r.results[i].pass(o.req) ? 1 : 0) << "\n";
  return os.str();
}

std::string design_budget_csv(const DesignOptions&, const DesignStudyResult& r) {
  std::ostringstream os;
  os << "index,group,p99_uncal_deg,p99_cal_deg\n";
  for (const auto& b : r.budget)
    os << r.recommended << "," << b.group << "," << num10(b.p99_uncal_deg) << "," << num10(b.p99_cal_deg) << "\n";
  return os.str();
}

std::string design_verdict(const DesignOptions& o, const DesignStudyResult& r) {
  if (r.recommended >= 0) {
    const auto i = static_cast<std::size_t>(r.recommended);
    return "recommended design " + std::to_string(i) + ": " + design_text(o, r.designs[i]) + " (volume " +
           g3(r.designs[i].volume_mm3()) + " mm^3, p99 " + g3(r.results[i].p99_req_deg(o.req)) + " deg)";
  }
  return "no design meets the requirements (p99 <= " + g3(o.req.target_p99_deg) + " deg" +
         (o.req.window.active() ? ", field in [" + g3(o.req.window.min_mT) + ", " + g3(o.req.window.max_mT) + "] mT" : "") +
         ") among " + std::to_string(r.designs.size()) + " designs";
}

std::string design_summary_md(const DesignOptions& o, const DesignStudyResult& r, int ranks, double wall_s) {
  std::ostringstream os;
  os << "# design: magnet, air gap, sensor and r0 from the requirements\n\n";
  os << "Which design meets p99 <= " << g3(o.req.target_p99_deg) << " deg ("
     << (o.req.calibration.none() ? "uncalibrated" : "after calibration " + o.req.calibration.name()) << ")";
  if (o.req.window.active())
    os << " with the field in the chip's window [" << g3(o.req.window.min_mT) << ", " << g3(o.req.window.max_mT) << "] mT";
  os << " from " << g3(o.req.temperature_min_C) << " to " << g3(o.req.temperature_max_C) << " C";
  if (o.req.stray_mT > 0) os << " under stray fields up to " << g3(o.req.stray_mT) << " mT";
  os << ", with the smallest magnet?\n\n";
  os << r.designs.size() << " designs (" << o.space.materials.size() << " materials x " << o.space.magnet_radius_mm.size()
     << " radii x " << (has_rings(o) ? std::to_string(o.space.magnet_inner_radius_mm.size()) + " inner radii x " : "")
     << o.space.magnet_height_mm.size() << " heights x " << o.space.gap_mm.size() << " gaps x "
     << o.space.r0_mm.size() << " r0 x " << o.space.sensors.size() << " sensors"
     << (has_side(o) ? " + " + std::to_string(o.space.side_radius_mm.size()) + " side-shaft radii x " +
                           std::to_string(o.space.side_height_mm.size()) + " heights x " +
                           std::to_string(o.space.side_principles.size()) + " principles per magnet"
                     : std::string())
     << "), " << o.samples
     << " Monte Carlo samples each (exact field, fast pipeline" << (has_side(o) ? "; side-shaft: direct" : "") << ", "
     << o.fast_steps << " theta steps), "
     << (o.seed_per_design ? "seeded per design from design.seed = " : "common samples of design.seed = ") << o.seed
     << "; evaluated on " << ranks << " MPI rank" << (ranks == 1 ? "" : "s") << " in " << fmt(wall_s, 1) << " s. "
     << r.passing << " designs meet every requirement.\n\n";
  os << "**" << design_verdict(o, r) << "**\n\n";
  if (r.recommended < 0) {
    // The closest designs: smallest p99 among those whose field is in the window, and why they fail.
    std::vector<std::size_t> idx(r.designs.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) {
      const double pa = r.results[a].p99_req_deg(o.req), pb = r.results[b].p99_req_deg(o.req);
      return pa != pb ? pa < pb : a < b;
    });
    std::vector<std::vector<std::string>> rows;
    for (std::size_t k = 0; k < idx.size() && k < 5; ++k)
      rows.push_back({std::to_string(idx[k]), design_text(o, r.designs[idx[k]]), r.results[idx[k]].reason(o.req)});
    os << "Closest designs (smallest p99):\n\n" << md_table({"design", "what", "fails because"}, rows) << "\n";
  } else {
    const auto i = static_cast<std::size_t>(r.recommended);
    const DesignResult& x = r.results[i];
    os << md_table({"quantity", "value"},
                   {{"magnet volume", g3(r.designs[i].volume_mm3()) + " mm^3"},
                    {"p99 uncalibrated", g3(x.p99_uncal_deg) + " deg"},
                    {"p99 calibrated", o.req.calibration.none() ? "(none)" : g3(x.p99_cal_deg) + " deg"},
                    {r.designs[i].side ? "in-plane field at the nominal mount" : "Bz amplitude on the circle",
                     r.designs[i].side ? "(field window row)" : g3(x.bz_amplitude_mT) + " mT"},
                    {"field over the box at the temperature extremes", g3(x.field_lo_mT) + " .. " + g3(x.field_hi_mT) + " mT"},
                    {"window margin", g3(x.margin_mT) + " mT"}})
       << "\n";
    os << "Error budget of the recommended design (p99 with one group alone; the shares need not add up):\n\n";
    std::vector<std::vector<std::string>> rows;
    for (const auto& b : r.budget)
      rows.push_back({b.group, g3(b.p99_uncal_deg), o.req.calibration.none() ? "-" : g3(b.p99_cal_deg)});
    os << md_table({"group", "p99 uncal [deg]", "p99 cal [deg]"}, rows) << "\n";
  }
  os << md_image("Pareto fronts", "design_pareto.png") << "\n\n" << md_image("p99 map", "design_map.png") << "\n\n";
  os << "## Pareto fronts (p99 against magnet volume, field in the window)\n\n";
  for (std::size_t s = 0; s < r.pareto.size(); ++s) {
    std::vector<std::vector<std::string>> rows;
    for (std::size_t i : r.pareto[s])
      rows.push_back({std::to_string(i), design_text(o, r.designs[i]), g3(r.designs[i].volume_mm3()),
                      g3(r.results[i].p99_req_deg(o.req)), r.results[i].pass(o.req) ? "yes" : "no"});
    os << "### " << o.space.sensor_name(s) << "\n\n"
       << (rows.empty() ? std::string("No design of this sensor keeps the field in the window.\n")
                        : md_table({"design", "what", "volume [mm^3]", "p99 [deg]", "meets all"}, rows))
       << "\n";
  }
  os << "Files: design.csv (every design), design_pareto.csv, design_budget.csv.\n";
  return os.str();
}

void write_design_plots(const DesignOptions& o, const DesignStudyResult& r, const std::filesystem::path& dir) {
  // 1. p99 against volume: every design in the window as points, the fronts as lines, the target.
  PlotPanel p;
  p.title = "p99 of the peak-to-peak error against magnet volume";
  p.xlabel = "magnet volume [mm^3]";
  p.ylabel = o.req.calibration.none() ? "p99 [deg]" : "p99 after " + plot_literal(o.req.calibration.name()) + " [deg]";
  p.logx = true;
  p.logy = true;
  double vmin = std::numeric_limits<double>::infinity(), vmax = 0;
  for (std::size_t s = 0; s < o.space.sensor_count(); ++s) {
    PlotSeries all, front;
    all.title = plot_literal(o.space.sensor_name(s)) + " designs";
    all.style = "points";
    all.extra = "pt 7 ps 0.6 lc " + std::to_string(s + 1);
    front.title = plot_literal(o.space.sensor_name(s)) + " Pareto front";
    front.style = "linespoints";
    front.extra = "lw 2 pt 5 lc " + std::to_string(s + 1);
    for (std::size_t i = 0; i < r.designs.size(); ++i) {
      if (r.designs[i].sensor != s || !r.results[i].field_ok()) continue;
      all.x.push_back(r.designs[i].volume_mm3());
      all.y.push_back(r.results[i].p99_req_deg(o.req));
      vmin = std::min(vmin, r.designs[i].volume_mm3());
      vmax = std::max(vmax, r.designs[i].volume_mm3());
    }
    for (std::size_t i : r.pareto[s]) {
      front.x.push_back(r.designs[i].volume_mm3());
      front.y.push_back(r.results[i].p99_req_deg(o.req));
    }
    p.series.push_back(all);
    p.series.push_back(front);
  }
  if (vmax > 0) {
    PlotSeries target;
    target.title = "target";
    target.x = {vmin, vmax};
    target.y = {o.req.target_p99_deg, o.req.target_p99_deg};
    target.extra = "lw 2 dt 2 lc rgb 'black'";
    p.series.push_back(target);
  }
  if (r.recommended >= 0) {
    const auto i = static_cast<std::size_t>(r.recommended);
    PlotSeries rec;
    rec.title = "recommended";
    rec.style = "points";
    rec.x = {r.designs[i].volume_mm3()};
    rec.y = {r.results[i].p99_req_deg(o.req)};
    rec.extra = "pt 6 ps 3 lw 2 lc rgb 'black'";
    p.series.push_back(rec);
  }
  p.commands = {"set key outside right"};
  PlotSpec spec;
  spec.title = "design: Pareto fronts per sensor";
  spec.panels = {p};
  spec.width_px = 1200;
  write_plot(dir, "design_pareto", spec);

  // 2. Map over magnet radius x gap (a side-shaft reader: x its read radius) for the best sensor: the smallest
  // p99 over the other variables.
  const std::size_t s = best_sensor(o, r);
  const bool side = o.space.is_side(s);
  const auto& R = o.space.magnet_radius_mm;
  const auto& G = side ? o.space.side_radius_mm : o.space.gap_mm;
  HeatmapSpec h;
  h.title = plot_literal(o.space.sensor_name(s)) + ": smallest p99 [deg] over material, height, " +
            (side ? "plane" : "r0") + " (out: field leaves the window)";
  h.xlabel = "magnet radius [mm]";
  h.ylabel = side ? "side-shaft read radius [mm]" : "gap [mm]";
  h.cblabel = "p99 [deg]";
  for (double x : R) h.column_labels.push_back(g3(x));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t gi = G.size(); gi-- > 0;) {  // largest gap on top
    h.row_labels.push_back(g3(G[gi]));
    std::vector<double> row(R.size(), nan), out_row(R.size(), nan);  // in the window; outside it
    std::vector<std::string> text(R.size());
    for (std::size_t i = 0; i < r.designs.size(); ++i) {
      const Design& d = r.designs[i];
      if (d.sensor != s || (side ? d.side_radius_mm : d.gap_mm) != G[gi]) continue;
      const auto ri = static_cast<std::size_t>(std::find(R.begin(), R.end(), d.magnet_radius_mm) - R.begin());
      const double v = r.results[i].p99_req_deg(o.req);
      std::vector<double>& target = r.results[i].field_ok() ? row : out_row;
      if (std::isnan(target[ri]) || v < target[ri]) target[ri] = v;
    }
    // Blank cells: every design there leaves the window; the text gives their smallest p99.
    for (std::size_t k = 0; k < R.size(); ++k) text[k] = std::isnan(row[k]) ? "out (" + g3(out_row[k]) + ")" : g3(row[k]);
    h.values.push_back(row);
    h.cell_text.push_back(text);
  }
  h.log_colour = true;
  h.log_floor = 1e-3;
  h.width_px = 900;
  h.height_px = 700;
  write_heatmap(dir, "design_map", h);
}

}  // namespace magenc
