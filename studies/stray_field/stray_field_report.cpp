#include "studies/stray_field/stray_field_report.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "report/setup_text.hpp"
#include "core/format.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {

std::string g10(double v) { return fmt_sig(v, 10); }
std::string dir_text(const Eigen::Vector3d& u) {
  return "(" + fmt(u.x(), 2) + ", " + fmt(u.y(), 2) + ", " + fmt(u.z(), 2) + ")";
}
std::string tolerated_text(const ToleratedField& t, const StrayFieldOptions& opt) {
  if (t.beyond) return "> " + fmt_sig(opt.search_max_mT, 4) + " mT (no error found)";
  if (t.field_mT == 0) return "0 (the mount alone exceeds it)";
  return fmt_auto(t.field_mT, 3) + " mT (" + fmt_auto(t.field_mT / kmT_per_kA_per_m, 3) + " kA/m)";
}
double floor_log(double v) { return std::max(v, 1e-6); }  // log axes: an exact zero at the floor

void write_curve_plot(const StrayFieldResult& r, const std::filesystem::path& dir) {
  PlotSpec ps;
  ps.title = "Worst angle error over all directions of a uniform stray field (" + r.field + " field)";
  ps.width_px = 1100;
  ps.height_px = 700;
  PlotPanel p;
  p.xlabel = "|B| of the stray field [mT]   (1 kA/m = 1.257 mT)";
  p.ylabel = "worst pp over the directions [deg] (zero drawn at 10^{-6})";
  p.logx = p.logy = true;
  for (const auto& s : r.sensors) {
    PlotSeries ser{plot_literal(s.label), {}, {}, "linespoints", "lw 2"};
    for (std::size_t i = 0; i < s.curve.size(); ++i) {
      ser.x.push_back(s.curve_mT[i]);
      ser.y.push_back(floor_log(s.curve[i].pp_deg));
    }
    p.series.push_back(ser);
  }
  p.commands = {"set grid", "set key top left", "set yrange [1e-6:*]", "set format y '10^{%L}'",
                "set format x '10^{%L}'"};
  for (double th : {0.1, 1.0})
    p.commands.push_back("set arrow from graph 0, first " + fmt_sig(th, 6) + " to graph 1, first " + fmt_sig(th, 6) +
                         " nohead dt 2 lc rgb 'gray40'");
  ps.panels.push_back(p);
  write_plot(dir, "error_vs_field", ps);
}

void write_wire_plot(const StrayFieldResult& r, const StrayFieldOptions& opt, const std::filesystem::path& dir) {
  PlotSpec ps;
  const double plotted_A = opt.wire_currents_A[opt.wire_currents_A.size() / 2];  // the middle current
  ps.title = "A straight conductor beside the sensor (distances along x from the die centre)";
  ps.columns = 2;
  ps.width_px = 1400;
  ps.height_px = 650;
  for (const char* orientation : {"along y", "along z"}) {
    PlotPanel p;
    p.title = std::string("conductor ") + orientation +
              (orientation[6] == 'y' ? " at the die's height: field normal to the die" : " (vertical): field in the die plane");
    p.xlabel = "distance [mm]";
    p.ylabel = "pp [deg] at " + fmt_sig(plotted_A, 4) + " A (zero drawn at 10^{-6})";
    p.logx = p.logy = true;
    for (const auto& s : r.sensors) {
      PlotSeries ser{plot_literal(s.label), {}, {}, "linespoints", "lw 2"};
      for (const auto& w : s.wires)
        if (w.orientation == orientation && w.current_A == plotted_A) {
          ser.x.push_back(w.distance_mm);
          ser.y.push_back(floor_log(w.pp_deg));
        }
      p.series.push_back(ser);
    }
    p.commands = {"set grid", "set key bottom left", "set yrange [1e-6:*]", "set format y '10^{%L}'"};
    ps.panels.push_back(p);
  }
  write_plot(dir, "wires", ps);
}

void write_direction_maps(const StrayFieldResult& r, const StrayFieldOptions& opt, const std::filesystem::path& dir) {
  for (const auto& s : r.sensors) {
    HeatmapSpec hm;
    hm.title = plot_literal(s.label) + ": pp over the directions of a uniform " +
               fmt_auto(opt.map_kA_per_m * kmT_per_kA_per_m, 3) + " mT field (" + fmt_auto(opt.map_kA_per_m, 3) +
               " kA/m)";
    hm.xlabel = "azimuth of the field [deg] (fixed frame, from x)";
    hm.ylabel = "polar angle from +z [deg]";
    for (std::size_t j = 0; j < r.azimuth_deg.size(); ++j)
      hm.column_labels.push_back(j % 3 == 0 ? fmt(r.azimuth_deg[j], 0) : std::string());
    for (double t : r.polar_deg) hm.row_labels.push_back(fmt(t, 0));
    for (Eigen::Index i = 0; i < s.map_pp_deg.rows(); ++i) {
      std::vector<double> row;
      for (Eigen::Index j = 0; j < s.map_pp_deg.cols(); ++j) row.push_back(s.map_pp_deg(i, j));
      hm.values.push_back(row);
    }
    hm.cblabel = "pp [deg] (log; below 10^{-4}: lowest colour)";
    hm.width_px = 1200;
    hm.height_px = 650;
    std::string name = s.label;
    std::replace(name.begin(), name.end(), ':', '_');
    write_heatmap(dir, "direction_map_" + name, hm);
  }
}

// wires.csv: pp beside a straight conductor, every sensor and wire case.
std::string wires_csv(const StrayFieldResult& r) {
  std::ostringstream os;
  os << "sensor,principle,orientation,distance_mm,current_A,B_at_centre_mT,pp_deg,c1_deg\n";
  for (const auto& s : r.sensors)
    for (const auto& w : s.wires)
      os << s.label << "," << principle_name(s.principle) << "," << w.orientation << "," << g10(w.distance_mm)
         << "," << g10(w.current_A) << "," << g10(w.field_mT) << "," << g10(w.pp_deg) << "," << g10(w.c1_deg) << "\n";
  return os.str();
}

// summary.md, "What ran".
void summary_what_ran(const StrayFieldResult& r, const StrayFieldOptions& opt, std::ostringstream& md, const StudySetup& setup) {
  md << "# stray_field: angle error in homogeneous stray fields and beside a conductor\n\n";
  md << "## What ran\n\n";
  md << "- Field `" << r.field << "`: magnet " << magnet_text(setup) << "; sensing plane " << fmt(setup.plane_height_mm, 2) << " mm above the top face; bz arrays on r0 = "
     << fmt(setup.r0_mm, 2) << " mm; " << opt.steps << " samples per turn.\n";
  md << "- Mount: sx " << fmt(r.mount.sx_mm, 3) << ", sy " << fmt(r.mount.sy_mm, 3) << ", dx " << fmt(r.mount.dx_mm, 3)
     << ", dy " << fmt(r.mount.dy_mm, 3) << ", dz " << fmt(r.mount.dz_mm, 3) << " mm; tilts " << fmt(r.mount.tilt_x_deg, 2)
     << ", " << fmt(r.mount.tilt_y_deg, 2) << " deg (the `mount.*` keys).\n";
  md << "- Uniform stray field over " << (opt.polar_points - 2) * opt.azimuth_points + 2 << " directions ("
     << opt.polar_points << " polar angles, poles once, x " << opt.azimuth_points
     << " azimuths), fixed frame; \"worst\" is the largest pp over them, with c1 of that direction. "
        "1 kA/m = 1.257 mT (B = mu0 H in air).\n";
  md << "- Tables: `levels.csv` (test levels and the magnitude curve, worst direction), `tolerated.csv`, `wires.csv`.\n\n";

}

// summary.md, the test levels: worst pp and c1 over the directions.
void summary_levels(const StrayFieldResult& r, const StrayFieldOptions& opt, std::ostringstream& md) {
  md << "## ISO 11452-8-style levels: worst pp over the directions [deg]\n\n";
  {
    std::vector<std::string> header = {"sensor", "mount alone"};
    for (double h : opt.levels_kA_per_m)
      header.push_back(fmt_auto(h, 3) + " kA/m (" + fmt_auto(h * kmT_per_kA_per_m, 3) + " mT)");
    std::vector<std::vector<std::string>> t;
    for (const auto& s : r.sensors) {
      std::vector<std::string> row = {"`" + s.label + "`", fmt_deg(s.base_pp_deg)};
      for (const auto& e : s.levels) row.push_back(fmt_deg(e.pp_deg));
      t.push_back(row);
    }
    md << md_table(header, t) << "\n";
  }
  md << "c1 at the worst direction and that direction (x, y, z) at the highest level:\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& s : r.sensors) {
      const StrayError& e = s.levels.back();
      t.push_back({"`" + s.label + "`", fmt_deg(e.c1_deg), fmt_deg(e.max_c1_deg),
                   e.pp_deg > kRoundingZeroDeg ? dir_text(e.worst_dir) : std::string("none (no error)")});
    }
    md << md_table({"sensor", "c1 at worst [deg]", "largest c1 [deg]", "worst direction"}, t) << "\n";
  }
  md << md_image("worst pp vs stray-field magnitude", "error_vs_field.png") << "\n\n";

}

// summary.md, the uniform field each sensor tolerates.
void summary_tolerated(const StrayFieldResult& r, const StrayFieldOptions& opt, std::ostringstream& md) {
  md << "## Uniform field tolerated\n\n";
  {
    std::vector<std::string> header = {"sensor"};
    for (double th : opt.thresholds_deg) header.push_back("pp <= " + fmt_auto(th, 3) + " deg");
    std::vector<std::vector<std::string>> t;
    for (const auto& s : r.sensors) {
      std::vector<std::string> row = {"`" + s.label + "`"};
      for (const auto& tf : s.tolerated) row.push_back(tolerated_text(tf, opt));
      t.push_back(row);
    }
    md << md_table(header, t) << "\n";
  }
  for (const auto& s : r.sensors) {
    md << "- `" << s.label << "` tolerates";
    for (std::size_t i = 0; i < s.tolerated.size(); ++i)
      md << (i ? "; " : " ") << tolerated_text(s.tolerated[i], opt) << " for " << fmt_auto(opt.thresholds_deg[i], 3)
         << " deg pp";
    md << ".\n";
  }
  md << "\nThe largest magnitude (0.1 % bisection) whose worst direction keeps pp at or below the threshold. "
        "Differential Bz arrays subtract probes with opposite weights: a homogeneous field cancels exactly, on a "
        "tilted die too (every probe of the die reads the same n.B). `two` takes a homogeneous Bz as channel "
        "offsets; the one-spot principles add the in-plane stray field to the magnet's at the spot, which turns its "
        "direction (xmr, amr: only the direction is read).\n\n";

}

// summary.md, the direction maps and the conductor.
void summary_maps_and_wires(const StrayFieldResult& r, const StrayFieldOptions& opt, std::ostringstream& md) {
  md << "## Direction maps at " << fmt_auto(opt.map_kA_per_m, 3) << " kA/m\n\n";
  for (const auto& s : r.sensors) {
    std::string name = s.label;
    std::replace(name.begin(), name.end(), ':', '_');
    md << md_image("pp over the directions: " + s.label, "direction_map_" + name + ".png") << "\n\n";
  }

  md << "## A straight conductor\n\n";
  md << "An infinite conductor through the point (distance, 0, 0) from the die centre (fixed frame), along y at the "
        "die's height (its field there is along z, normal to the die) or along z (vertical: its field lies in the die "
        "plane). pp [deg]:\n\n";
  {
    std::vector<std::string> header = {"orientation", "distance [mm]", "current [A]", "|B| at centre [mT]"};
    for (const auto& s : r.sensors) header.push_back("`" + s.label + "`");
    std::vector<std::vector<std::string>> t;
    const std::size_t W = r.sensors.empty() ? 0 : r.sensors.front().wires.size();
    for (std::size_t i = 0; i < W; ++i) {
      const WireCase& w = r.sensors.front().wires[i];
      std::vector<std::string> row = {w.orientation, fmt_sig(w.distance_mm, 4), fmt_sig(w.current_A, 4),
                                      fmt_auto(w.field_mT, 3)};
      for (const auto& s : r.sensors) row.push_back(fmt_deg(s.wires[i].pp_deg));
      t.push_back(row);
    }
    md << md_table(header, t) << "\n";
  }
  md << "A differential array cancels the conductor's field only to its gradient across the array; the field of a "
        "conductor falls as 1/d, its gradient as 1/d^2.\n\n";
  md << md_image("pp beside a conductor", "wires.png") << "\n";
}

}  // namespace

std::string stray_levels_csv(const StrayFieldResult& r, const StrayFieldOptions& opt) {
  std::ostringstream os;
  os << "sensor,principle,kind,H_kA_per_m,B_mT,worst_pp_deg,c1_at_worst_deg,max_c1_deg,worst_dir_x,worst_dir_y,"
        "worst_dir_z\n";
  for (const auto& s : r.sensors) {
    auto row = [&](const char* kind, double b_mT, const StrayError& e) {
      os << s.label << "," << principle_name(s.principle) << "," << kind << "," << g10(b_mT / kmT_per_kA_per_m) << ","
         << g10(b_mT) << "," << g10(e.pp_deg) << "," << g10(e.c1_deg) << "," << g10(e.max_c1_deg) << ","
         << g10(e.worst_dir.x()) << "," << g10(e.worst_dir.y()) << "," << g10(e.worst_dir.z()) << "\n";
    };
    for (std::size_t i = 0; i < s.levels.size(); ++i)
      row("level", opt.levels_kA_per_m[i] * kmT_per_kA_per_m, s.levels[i]);
    for (std::size_t i = 0; i < s.curve.size(); ++i) row("curve", s.curve_mT[i], s.curve[i]);
  }
  return os.str();
}

std::string stray_tolerated_csv(const StrayFieldResult& r) {
  std::ostringstream os;
  os << "sensor,principle,threshold_pp_deg,tolerated_B_mT,tolerated_H_kA_per_m,beyond_search\n";
  for (const auto& s : r.sensors)
    for (const auto& t : s.tolerated)
      os << s.label << "," << principle_name(s.principle) << "," << g10(t.threshold_deg) << "," << g10(t.field_mT)
         << "," << g10(t.field_mT / kmT_per_kA_per_m) << "," << (t.beyond ? "true" : "false") << "\n";
  return os.str();
}

void write_stray_field_report(const StrayFieldResult& r, const StrayFieldOptions& opt, const StudySetup& setup,
                              StudyOutput& out) {
  // 1. Tables.
  out.write_text("levels.csv", stray_levels_csv(r, opt));
  out.write_text("tolerated.csv", stray_tolerated_csv(r));
  out.write_text("wires.csv", wires_csv(r));
  // 2. Plots.
  write_curve_plot(r, out.dir());
  write_wire_plot(r, opt, out.dir());
  write_direction_maps(r, opt, out.dir());
  // 3. summary.md, one function per section.
  std::ostringstream md;
  summary_what_ran(r, opt, md, setup);
  summary_levels(r, opt, md);
  summary_tolerated(r, opt, md);
  summary_maps_and_wires(r, opt, md);
  out.write_text("summary.md", md.str());
}

}  // namespace magenc
