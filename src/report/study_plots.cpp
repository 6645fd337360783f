#include "report/study_plots.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace magenc {

std::string coef_axis_label(const std::string& coef) {
  if (coef == "pp_deg") return "peak-to-peak [deg]";
  const auto us = coef.find('_');
  const std::string base = coef.substr(0, us);
  const std::string unit = us == std::string::npos ? "" : " [" + coef.substr(us + 1) + "]";
  if (base.size() >= 2) return base.substr(0, 1) + "_{" + base.substr(1) + "}" + unit;
  return plot_literal(coef);
}

PlotPanel eps_panel(const std::string& title, const std::vector<EpsCase>& cases) {
  PlotPanel p;
  p.title = title;
  p.xlabel = "rotor angle {/Symbol q} [deg]";
  p.ylabel = "angle error {/Symbol e} [deg]";
  p.commands = {"set xrange [0:360]", "set xtics 45", "set key outside right top"};
  for (const auto& c : cases) {
    PlotSeries s;
    s.title = c.label;
    s.x.assign(c.result->theta_deg.data(), c.result->theta_deg.data() + c.result->theta_deg.size());
    s.y.assign(c.result->eps_deg.data(), c.result->eps_deg.data() + c.result->eps_deg.size());
    p.series.push_back(std::move(s));
  }
  return p;
}

PlotPanel harmonics_panel(const std::string& title, const std::vector<SpectrumCase>& cases,
                          bool include_dc, bool logy, double min_deg) {
  PlotPanel p;
  p.title = title;
  p.xlabel = "harmonic n";
  p.ylabel = logy ? "amplitude c_n [deg] (log)" : "amplitude c_n [deg]";
  p.logy = logy;
  const int first = include_dc ? 0 : 1;
  const double group = 0.8;
  const double w = group / std::max<std::size_t>(1, cases.size());
  std::ostringstream xt;
  xt << "set xtics (";
  for (int n = first; n <= kHarmonics; ++n)
    xt << (n > first ? ", " : "") << (n == 0 ? "'|a_0|'" : "'" + std::to_string(n) + "'") << " " << n;
  xt << ")";
  p.commands = {xt.str(), "set grid noxtics ytics",
                "set xrange [" + std::to_string(first - 0.6) + ":" + std::to_string(kHarmonics + 0.6) + "]",
                "set boxwidth " + std::to_string(0.95 * w), "set key outside right top"};
  if (logy) {
    std::ostringstream yr;
    yr << "set yrange [" << min_deg << ":*]";
    p.commands.push_back(yr.str());
  } else {
    p.commands.push_back("set yrange [0:*]");
  }
  for (std::size_t j = 0; j < cases.size(); ++j) {
    PlotSeries s;
    s.title = cases[j].label;
    s.style = "boxes";
    const double off = (static_cast<double>(j) - 0.5 * (static_cast<double>(cases.size()) - 1.0)) * w;
    for (int n = first; n <= kHarmonics; ++n) {
      double v = n == 0 ? std::abs(cases[j].spectrum.a0_deg) : cases[j].spectrum.c_deg[n];
      if (logy && v < min_deg) v = min_deg;  // clipped to the axis floor
      s.x.push_back(n + off);
      s.y.push_back(v);
    }
    p.series.push_back(std::move(s));
  }
  return p;
}

PlotSpec coefficient_figure(const std::string& title, const std::string& xlabel,
                            const std::vector<SweepCase>& sweeps, const std::vector<FitRow>& fits,
                            const std::vector<std::string>& coefs, int columns) {
  PlotSpec spec;
  spec.title = title + "  (points: computed, lines: cubic fit)";
  spec.columns = columns;
  const int rows = (static_cast<int>(coefs.size()) + columns - 1) / columns;
  spec.width_px = 480 * columns;
  spec.height_px = 60 + 340 * rows;
  for (const auto& coef : coefs) {
    PlotPanel p;
    p.title = coef_axis_label(coef).substr(0, coef_axis_label(coef).find(' '));
    p.xlabel = xlabel;
    p.ylabel = coef_axis_label(coef);
    p.commands = {"set key outside right top vertical font ',9' samplen 1"};
    for (std::size_t k = 0; k < sweeps.size(); ++k) {
      const SweepResult& sw = *sweeps[k].sweep;
      const std::string lc = "lc " + std::to_string(k + 1);
      PlotSeries pts;
      pts.title = sweeps[k].label;
      pts.style = "points";
      // Distinct marker shapes so coinciding sweeps stay visible.
      static const char* kMarkers[] = {"pt 7 ps 0.6", "pt 6 ps 1.1", "pt 4 ps 1.1", "pt 8 ps 1.2",
                                       "pt 12 ps 1.3", "pt 2 ps 1.0", "pt 1 ps 1.0"};
      pts.extra = std::string(kMarkers[k % 7]) + " " + lc;
      pts.x = sw.x_mm();
      pts.y = sw.column(coef);
      p.series.push_back(pts);
      if (const FitRow* f = find_fit(fits, sw, coef)) {
        PlotSeries line;
        line.title = "";
        line.style = "lines";
        line.extra = "lw 1.5 " + lc;  // empty title: no legend entry
        const auto [lo, hi] = std::minmax_element(pts.x.begin(), pts.x.end());
        const int n = 100;
        for (int i = 0; i <= n; ++i) {
          const double x = *lo + (*hi - *lo) * i / n;
          line.x.push_back(x);
          line.y.push_back(eval_cubic(f->p, x));
        }
        p.series.push_back(std::move(line));
      }
    }
    // A coefficient that is zero up to rounding would otherwise autoscale its
    // noise to full height and look like data.
    double ymax = 0;
    for (const auto& s : p.series)
      if (s.style == "points")
        for (double y : s.y)
          if (std::isfinite(y)) ymax = std::max(ymax, std::abs(y));
    if (ymax < kRoundingZeroDeg) {
      p.commands.push_back("set yrange [-1:1]");
      p.commands.push_back("set label 'zero up to rounding (< " + fmt_auto(kRoundingZeroDeg, 1) +
                           " deg)' at graph 0.5, 0.8 center font ',9'");
    }
    spec.panels.push_back(std::move(p));
  }
  return spec;
}

PlotSpec difference_figure(const std::string& title, const std::string& xlabel,
                           const std::vector<DifferenceCase>& cases, const std::vector<std::string>& coefs,
                           int columns) {
  static const char* kMarkers[] = {"pt 7", "pt 5", "pt 9", "pt 11", "pt 13", "pt 4", "pt 6"};
  PlotSpec spec;
  spec.title = title;
  spec.columns = columns;
  spec.width_px = 560 * columns;
  spec.height_px = 80 + 380 * static_cast<int>((coefs.size() + columns - 1) / columns);
  for (const auto& coef : coefs) {
    PlotPanel p;
    const std::string axis = coef_axis_label(coef);
    p.title = axis.substr(0, axis.find(' ')) + " (FEM - exact)";
    p.xlabel = xlabel;
    p.ylabel = "{/Symbol D}" + axis;
    p.commands = {"set key outside right top", "set xzeroaxis"};
    for (std::size_t k = 0; k < cases.size(); ++k) {
      PlotSeries s;
      s.title = cases[k].label;
      s.style = "linespoints";
      s.extra = std::string(kMarkers[k % 7]) + " lc " + std::to_string(k + 1);
      s.x = cases[k].value->x_mm();
      const auto v = cases[k].value->column(coef), e = cases[k].exact->column(coef);
      for (std::size_t i = 0; i < v.size(); ++i) s.y.push_back(v[i] - e[i]);
      p.series.push_back(s);
    }
    spec.panels.push_back(p);
  }
  return spec;
}

}  // namespace magenc
