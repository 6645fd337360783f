#include "report/diagnosis_report.hpp"

#include <ceres/version.h>
#include <omp.h>

#include <cmath>
#include <ctime>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <fstream>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "io/plot.hpp"
#include "magenc_version.hpp"
#include "report/study_output.hpp"
#include "report/study_plots.hpp"

namespace magenc {

namespace {

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json harmonics_json(const Eigen::VectorXd& h) {
  nlohmann::json j;
  j["a0_deg"] = h[0];
  for (int n = 1; 2 * n < h.size(); ++n) {
    j["a" + std::to_string(n) + "_deg"] = h[2 * n - 1];
    j["b" + std::to_string(n) + "_deg"] = h[2 * n];
    j["c" + std::to_string(n) + "_deg"] = harmonic_amplitude(h, n);
  }
  return j;
}

std::string sig(double v, int digits = 4) {
  if (!std::isfinite(v)) return v > 0 ? "inf" : "nan";
  return fmt_sig(v, digits);
}

}  // namespace

std::string diagnosis_json(const std::vector<CurveInput>& curves, const DiagnosisResult& res,
                           const DiagnosisRunInfo& info) {
  nlohmann::json j;
  nlohmann::json params = nlohmann::json::object();
  std::set<std::string> unid(res.not_identifiable.begin(), res.not_identifiable.end());
  for (const auto& p : res.params) {
    nlohmann::json e;
    e["value"] = p.value;
    e["sigma"] = p.free ? finite_or_null(p.sigma) : nlohmann::json(0.0);
    e["free"] = p.free;
    e["unit"] = p.unit;
    e["identifiable"] = !p.free || (!unid.count(p.json_name) && std::isfinite(p.sigma));
    params[p.json_name] = e;
  }
  j["parameters"] = params;
  {  // the magnet tilt in the configuration's polar form (from the fitted components; no sigma)
    double mx = 0, my = 0;
    for (const auto& p : res.params) {
      if (p.json_name == "magnet_tilt_x_deg") mx = p.value;
      if (p.json_name == "magnet_tilt_y_deg") my = p.value;
    }
    const double g = std::hypot(mx, my);
    j["derived"] = {{"magnet_tilt_deg", g},
                    {"magnet_tilt_azimuth_deg", g > 0 ? std::atan2(my, mx) * 180.0 / 3.14159265358979323846 : 0.0}};
  }
  j["residual_rms_deg"] = res.residual_rms_deg;
  j["converged"] = res.converged;
  j["termination"] = res.termination;
  j["explained_fraction"] = res.explained_fraction;
  j["residual_harmonic_share"] = res.residual_harmonic_share;
  j["not_identifiable"] = res.not_identifiable;
  nlohmann::json conf = nlohmann::json::array();
  for (const auto& c : res.confounded)
    conf.push_back({{"parameters", c.names}, {"weights", c.weights}, {"relative_singular_value", c.rel_singular},
                    {"harmonics", c.harmonics}, {"text", c.text}});
  j["confounded"] = conf;
  j["free"] = res.free;
  nlohmann::json corr = nlohmann::json::array();
  for (Eigen::Index a = 0; a < res.correlation.rows(); ++a) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index b = 0; b < res.correlation.cols(); ++b) row.push_back(finite_or_null(res.correlation(a, b)));
    corr.push_back(row);
  }
  j["correlation"] = {{"names", res.free}, {"matrix", corr}};
  nlohmann::json alts = nlohmann::json::array();
  for (const auto& a : res.alternatives) {
    nlohmann::json v;
    for (std::size_t k = 0; k < res.free.size() && k < a.values.size(); ++k) v[res.free[k]] = a.values[k];
    alts.push_back({{"cost", a.cost}, {"values", v}});
  }
  j["alternative_minima"] = alts;
  j["singular_values_normalised"] = std::vector<double>(res.singular_values.data(), res.singular_values.data() + res.singular_values.size());
  j["condition_number"] = finite_or_null(res.condition);
  j["rss_deg2"] = res.rss_deg2;
  j["n_points"] = res.n_points;
  j["n_free"] = res.n_free;
  j["default_free_note"] = res.default_free_note;
  nlohmann::json cj = nlohmann::json::array();
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const MeasuredCurve& m = curves[c].curve;
    nlohmann::json gaps = nlohmann::json::array();
    for (const auto& g : m.gaps) gaps.push_back({{"from_deg", g.from_deg}, {"to_deg", g.to_deg}, {"width_deg", g.width_deg}});
    nlohmann::json ov = nlohmann::json::array();
    for (const auto& o : curves[c].overrides)
      ov.push_back(fit_parameters()[o.param].key + (o.add ? "+=" : "=") + std::to_string(o.value));
    cj.push_back({{"file", m.path}, {"format", m.format}, {"samples", m.size()}, {"turns", m.turns},
                  {"median_step_deg", m.median_step_deg}, {"largest_gap_deg", m.largest_gap_deg}, {"gaps", gaps},
                  {"duplicate_rows", m.duplicates}, {"array", curves[c].base.setup.array.name},
                  {"r0_mm", curves[c].base.setup.r0_mm}, {"overrides", ov},
                  {"residual_rms_deg", res.curves[c].residual_rms_deg},
                  {"measured_harmonics", harmonics_json(res.curves[c].measured_h)},
                  {"fitted_harmonics", harmonics_json(res.curves[c].fitted_h)},
                  {"residual_harmonics", harmonics_json(res.curves[c].residual_h)}});
  }
  j["curves"] = cj;
  nlohmann::json st = nlohmann::json::array();
  for (double c : res.start_costs) st.push_back(finite_or_null(c));
  j["starts"] = {{"count", info.options.starts}, {"seed", info.options.seed}, {"final_cost", st},
                 {"best", res.best_start}, {"costs_on_thinned_curves", res.starts_thinned}, {"iterations_best", res.iterations}};
  j["run"] = {{"program", info.program},
              {"version", kVersion},
              {"git_revision", kGitRevision},
              {"ceres_version", CERES_VERSION_STRING},
              {"date_utc", utc_timestamp_iso()},
              {"command_line", info.command_line},
              {"field", info.field_spec},
              {"curve_sets", info.curve_sets},
              {"seed", info.options.seed},
              {"starts", info.options.starts},
              {"free_zero_offset", info.options.free_zero},
              {"cond_limit", info.options.cond_limit},
              {"fd_step_typical_sizes", info.options.fd_step},
              {"threads", omp_get_max_threads()},
              {"fit_seconds", res.fit_seconds},
              {"wall_seconds", info.wall_s},
              {"config", info.config_json.empty() ? nlohmann::json(nullptr) : nlohmann::json::parse(info.config_json)}};
  return j.dump(2) + "\n";
}

std::string diagnosis_csv(const std::vector<CurveInput>& curves, const DiagnosisResult& res) {
  std::ostringstream os;
  os << "curve,theta_deg,measured_deg,fitted_deg,residual_deg,row\n" << std::setprecision(10);
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const MeasuredCurve& m = curves[c].curve;
    for (std::size_t i = 0; i < m.size(); ++i)
      os << c + 1 << "," << m.theta_deg[i] << "," << m.error_deg[i] << "," << res.curves[c].fitted_deg[i] << ","
         << res.curves[c].residual_deg[i] << "," << m.row[i] << "\n";
  }
  return os.str();
}

void write_diagnosis_plots(const std::filesystem::path& dir, const std::vector<CurveInput>& curves,
                           const DiagnosisResult& res) {
  const int C = static_cast<int>(curves.size());
  PlotSpec fit{"diagnose: measured and fitted angle error (residual RMS " + sig(res.residual_rms_deg, 3) + " deg)", {}, 1,
               1100, 80 + 520 * C};
  PlotSpec har{"diagnose: harmonics (least squares on the samples)", {}, 1, 1100, 80 + 360 * C};
  for (int c = 0; c < C; ++c) {
    const MeasuredCurve& m = curves[c].curve;
    const std::string name = plot_literal(std::filesystem::path(m.path).filename().string());
    PlotPanel top;
    top.title = "curve " + std::to_string(c + 1) + ": " + name + " (array " + plot_literal(curves[c].base.setup.array.name) + ")";
    top.xlabel = "rotor angle {/Symbol q} [deg]";
    top.ylabel = "angle error [deg]";
    top.commands = {"set xrange [0:360]", "set xtics 45", "set key outside right top", "set grid"};
    PlotSeries meas{"measured", {}, {}, "points", "pt 7 ps 0.4 lc rgb '#1f77b4'"};
    PlotSeries fitted{"fitted", {}, {}, "lines", "lw 2 lc rgb '#d62728'"};
    PlotSeries resid{"residual", {}, {}, "points", "pt 7 ps 0.3 lc rgb '#2ca02c'"};
    for (std::size_t i = 0; i < m.size(); ++i) {
      meas.x.push_back(m.theta_deg[i]);
      meas.y.push_back(m.error_deg[i]);
      fitted.x.push_back(m.theta_deg[i]);
      fitted.y.push_back(res.curves[c].fitted_deg[i]);
      resid.x.push_back(m.theta_deg[i]);
      resid.y.push_back(res.curves[c].residual_deg[i]);
    }
    top.series = {meas, fitted};
    PlotPanel bottom;
    bottom.title = "residual fitted - measured, RMS " + sig(res.curves[c].residual_rms_deg, 3) + " deg";
    bottom.xlabel = top.xlabel;
    bottom.ylabel = "residual [deg]";
    bottom.commands = top.commands;
    bottom.series = {resid};
    fit.panels.push_back(top);
    fit.panels.push_back(bottom);
    har.panels.push_back(harmonics_panel("curve " + std::to_string(c + 1) + ": " + name,
                                         {{"measured", spectrum_from_ls(res.curves[c].measured_h)},
                                          {"fitted", spectrum_from_ls(res.curves[c].fitted_h)},
                                          {"residual", spectrum_from_ls(res.curves[c].residual_h)}},
                                         true, true, 1e-5));
  }
  write_plot(dir, "fit", fit);
  write_plot(dir, "harmonics", har);
}

namespace {

// summary.md: every curve's file, sampling, array and residual.
void summary_curves_section(std::ostringstream& md, const std::vector<CurveInput>& curves, const DiagnosisResult& res) {
  md << "## Curves\n\n";
  std::vector<std::vector<std::string>> t;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const MeasuredCurve& m = curves[c].curve;
    std::string ov;
    for (const auto& o : curves[c].overrides)
      ov += (ov.empty() ? "" : ", ") + fit_parameters()[o.param].key + (o.add ? " += " : " = ") + sig(o.value);
    std::string gaps;
    for (std::size_t g = 0; g < m.gaps.size() && g < 3; ++g)
      gaps += (g ? "; " : "") + fmt(m.gaps[g].width_deg, 1) + " deg after " + fmt(m.gaps[g].from_deg, 1);
    t.push_back({std::to_string(c + 1), "`" + m.path + "`", m.format, std::to_string(m.size()), fmt(m.turns, 2),
                 fmt(m.largest_gap_deg, 2), gaps.empty() ? "none" : gaps, "`" + curves[c].base.setup.array.name + "`",
                 fmt(curves[c].base.setup.r0_mm, 3), ov.empty() ? "-" : ov, sig(res.curves[c].residual_rms_deg, 3)});
  }
  md << md_table({"#", "file", "format", "samples", "turns", "largest gap [deg]", "gaps reported", "array", "r0 [mm]",
                  "known per-curve values", "residual RMS [deg]"},
                 t)
     << "\n";
}

// summary.md: the directions the data do not fix and the equally good minima elsewhere.
void summary_confounding_section(std::ostringstream& md, const DiagnosisResult& res, const DiagnosisRunInfo& info) {
  md << "## What one fit cannot tell apart\n\n";
  if (!res.default_free_note.empty()) md << res.default_free_note << "\n\n";
  if (res.confounded.empty())
    md << "At the optimum the column-normalised Jacobian has condition number " << sig(res.condition, 3)
       << " (limit " << sig(info.options.cond_limit, 3) << "): every free parameter is separated by these data.\n\n";
  else {
    md << "At the optimum the column-normalised Jacobian has condition number " << sig(res.condition, 3)
       << " (limit " << sig(info.options.cond_limit, 3) << "). Directions the data do not fix:\n\n";
    for (const auto& c : res.confounded) md << "- " << c.text << "\n";
    md << "\nTheir sigma is reported as infinite (null in fit.json); their values are one point of a valley.\n\n";
  }
  if (!res.alternatives.empty()) {
    md << "**Equally good minima elsewhere** (cost within 1 % of the best, more than 3 sigma away): the data "
          "cannot choose between these and the values above; the sigmas describe each minimum locally.\n\n";
    for (const auto& a : res.alternatives) {
      md << "- cost " << sig(a.cost, 4) << ":";
      for (std::size_t k = 0; k < res.free.size() && k < a.values.size(); ++k)
        md << " `" << res.free[k] << "` " << sig(a.values[k], 4);
      md << "\n";
    }
    md << "\n";
  }
}

}  // namespace

std::string diagnosis_summary(const std::vector<CurveInput>& curves, const DiagnosisResult& res,
                              const DiagnosisRunInfo& info) {
  std::ostringstream md;
  md << "# diagnose: which mounting state and signal-chain errors explain the measured curve\n\n"
     << "Field `" << info.field_spec << "`; " << curves.size() << " curve(s), " << res.n_points << " samples, "
     << res.n_free << " free variables; nonlinear least squares (Ceres " << CERES_VERSION_STRING
     << ", Levenberg-Marquardt, central-difference Jacobian) on wrapped angle differences, " << info.options.starts
     << " starts (seed " << info.options.seed << "), best start " << res.best_start << " after " << res.iterations
     << " iterations; fit time " << fmt(res.fit_seconds, 2) << " s.\n\n";
  summary_curves_section(md, curves, res);
  md << "## Parameters (1 sigma from the Jacobian at the optimum, scaled by the residual)\n\n";
  {
    std::vector<std::vector<std::string>> t;
    std::set<std::string> unid(res.not_identifiable.begin(), res.not_identifiable.end());
    for (const auto& p : res.params) {
      if (!p.free && p.value == 0) continue;
      const std::string status = !p.free ? "fixed" : unid.count(p.json_name) ? "free, NOT identifiable" : "free";
      t.push_back({"`" + p.json_name + "`", sig(p.value, 5), p.free ? sig(p.sigma, 3) : "-", p.unit, status});
    }
    md << md_table({"parameter", "value", "sigma", "unit", "status"}, t)
       << "\n(fixed parameters at 0 are not listed; every table parameter is in fit.json)\n\n";
  }
  md << "Residual RMS " << sig(res.residual_rms_deg, 4) << " deg over all curves (RSS " << sig(res.rss_deg2, 4)
     << " deg^2, N - p = " << res.n_points - res.n_free << ").\n\n";
  summary_confounding_section(md, res, info);
  md << "## Correlation matrix of the free variables\n\n";
  {
    std::vector<std::string> h{""};
    for (const auto& n : res.free) h.push_back("`" + n + "`");
    std::vector<std::vector<std::string>> t;
    for (Eigen::Index a = 0; a < res.correlation.rows(); ++a) {
      std::vector<std::string> row{"`" + res.free[a] + "`"};
      for (Eigen::Index b = 0; b < res.correlation.cols(); ++b)
        row.push_back(std::isfinite(res.correlation(a, b)) ? fmt(res.correlation(a, b), 3) : "-");
      t.push_back(row);
    }
    md << md_table(h, t) << "\n";
  }
  md << "## Harmonics measured / fitted / residual (deg, least squares on the samples)\n\n";
  for (std::size_t c = 0; c < curves.size(); ++c) {
    std::vector<std::vector<std::string>> t;
    const auto row = [&](const std::string& name, const Eigen::VectorXd& h) {
      std::vector<std::string> r{name, fmt_auto(h[0], 4)};
      for (int n = 1; n <= kHarmonics; ++n) r.push_back(fmt_auto(harmonic_amplitude(h, n), 4));
      t.push_back(r);
    };
    row("measured", res.curves[c].measured_h);
    row("fitted", res.curves[c].fitted_h);
    row("residual", res.curves[c].residual_h);
    std::vector<std::string> h{"curve " + std::to_string(c + 1), "a0"};
    for (int n = 1; n <= kHarmonics; ++n) h.push_back("c" + std::to_string(n));
    md << md_table(h, t) << "\n";
  }
  md << "## Starts\n\nFinal cost (0.5 RSS, deg^2) per start"
     << (res.starts_thinned ? " (on the curves thinned to <= 360 samples; the best basins were then polished on all "
                              "samples)" : "")
     << ": ";
  for (std::size_t s = 0; s < res.start_costs.size(); ++s)
    md << (s ? ", " : "") << sig(res.start_costs[s], 4);
  md << ". Starts that end at different costs are different local minima (e.g. mirror images); the lowest is "
        "reported.\n\n";
  md << "## Plots\n\n" << md_image("measured vs fitted, residual", "fit.png") << "\n"
     << md_image("harmonics measured vs fitted", "harmonics.png") << "\n\n"
     << "A fit says which model parameters reproduce the curve, not that they are the cause: parameters left "
        "fixed (at the values listed in fit.json) and effects outside the model also shape it.\n";
  return md.str();
}

void write_diagnosis_outputs(const std::filesystem::path& dir, const std::vector<CurveInput>& curves,
                             const DiagnosisResult& res, const DiagnosisRunInfo& info) {
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream f(dir / name, std::ios::binary);
    f << text;
    f.flush();
    if (!f) throw ComputeError("writing " + (dir / name).string() + " failed");
  };
  write("fit.json", diagnosis_json(curves, res, info));
  write("fit.csv", diagnosis_csv(curves, res));
  write("summary.md", diagnosis_summary(curves, res, info));
  if (!info.config_toml.empty()) write("config.toml", "# Configuration used by diagnose\n" + info.config_toml);
  write_diagnosis_plots(dir, curves, res);
}

}  // namespace magenc
