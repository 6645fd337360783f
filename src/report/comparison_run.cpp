#include "report/comparison_run.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/errors.hpp"
#include "io/plot.hpp"
#include "io/tables.hpp"

namespace magenc {

ComparisonInputs comparison_inputs_from_config(const Config& cfg) {
  ComparisonInputs in;
  in.sources = fem_sources_from_config(cfg);  // first: a missing solve directory is the error to report
  in.exact = std::make_shared<const AnalyticField>(Magnet::from_config(cfg));
  in.base = Mount::from_config(cfg);
  const auto arrays = split_list(cfg.str("study.arrays"), "study.arrays");
  ProbeArray::parse(cfg.str("sensor.array"));  // unused here (study.arrays), but still checked
  for (const auto& a : arrays) in.setups.push_back(probe_setup_from_config(cfg, a, "study.arrays"));
  in.dir = cfg.str("fem_field.dir");
  return in;
}

std::vector<const SourceRun*> ArrayRun::all() const {
  std::vector<const SourceRun*> out;
  for (const auto& f : fem) out.push_back(&f);
  out.push_back(&exact);
  return out;
}

namespace {

SourceRun run_source(const std::string& label, const FieldSource& field, const ProbeSetup& setup,
                     const ComparisonPlan& plan) {
  SourceRun r;
  r.label = label;
  r.field = field.name();
  if (plan.ideal) r.ideal = angle_error(field, setup, *plan.ideal);
  for (const auto& m : plan.points) r.points.push_back(angle_error(field, setup, m));
  for (const auto& s : plan.sweeps) r.sweeps.push_back(run_sweep(field, setup, s));
  return r;
}

}  // namespace

ComparisonRun run_comparison(const std::vector<FemSource>& sources, const FieldSource& exact,
                             const std::vector<ProbeSetup>& setups, const ComparisonPlan& plan) {
  ComparisonRun run;
  run.plan = plan;
  for (const auto& setup : setups) {
    ArrayRun r;
    r.setup = setup;
    r.exact = run_source("exact", exact, setup, plan);
    for (const auto& s : sources) r.fem.push_back(run_source(s.label, *s.field, setup, plan));
    std::vector<const SourceRun*> fitted = {&r.exact};
    for (const auto& f : r.fem) fitted.push_back(&f);
    for (const SourceRun* sr : fitted)
      for (const auto& s : sr->sweeps) {
        auto f = fit_sweep(s, plan.study, plan.fit_coefs);
        run.fits.insert(run.fits.end(), f.begin(), f.end());
      }
    for (const auto& f : r.fem) {
      if (plan.ideal)
        run.compared.push_back(
            {setup.array.name, "ideal", "", 0.0, f.label, f.ideal->spectrum, r.exact.ideal->spectrum});
      for (std::size_t k = 0; k < plan.sweeps.size(); ++k) {
        auto c = compare_sweeps(f.sweeps[k], r.exact.sweeps[k], f.label);
        run.compared.insert(run.compared.end(), c.begin(), c.end());
      }
    }
    run.arrays.push_back(std::move(r));
  }
  return run;
}

std::vector<SpectrumRow> comparison_spectra_rows(const ComparisonRun& run) {
  std::vector<SpectrumRow> rows;
  for (const auto& r : run.arrays)
    for (const SourceRun* sr : r.all()) {
      if (sr->ideal)
        rows.push_back({sr->field, r.setup.array.name, r.setup.r0_mm, *run.plan.ideal, sr->ideal->spectrum,
                        {{"sweep", "ideal"}, {"source", sr->label}}});
      for (const auto& s : sr->sweeps)
        for (auto row : s.rows) {
          row.extra.push_back({"source", sr->label});
          rows.push_back(row);
        }
    }
  return rows;
}

void write_comparison_tables(StudyOutput& out, const ComparisonRun& run) {
  out.write_text("spectra.csv", spectra_csv(comparison_spectra_rows(run)));
  out.write_text("comparison.csv", comparison_csv(run.compared, spectrum_columns()));
  out.write_text("fits.csv", fits_csv(run.fits));
}

std::vector<SweepCase> coefficient_cases(const ComparisonRun& run, std::size_t k) {
  std::vector<SweepCase> sc;
  for (const auto& r : run.arrays) {
    const std::string a = plot_literal(r.setup.array.name);
    if (!r.fem.empty()) sc.push_back({a + " " + r.fem.front().label, &r.fem.front().sweeps.at(k)});
    sc.push_back({a + " exact", &r.exact.sweeps.at(k)});
  }
  return sc;
}

std::vector<DifferenceCase> difference_cases(const ComparisonRun& run, std::size_t k) {
  std::vector<DifferenceCase> dc;
  for (const auto& r : run.arrays) {
    const std::string a = plot_literal(r.setup.array.name);
    for (const auto& f : r.fem) dc.push_back({a + " " + f.label, &f.sweeps.at(k), &r.exact.sweeps.at(k)});
  }
  return dc;
}

std::vector<std::string> write_comparison_plots(const std::filesystem::path& dir, const ComparisonRun& run,
                                                std::size_t k, const SweepPlotText& text,
                                                const std::vector<std::string>& diff_coefs) {
  write_plot(dir, "coefficients_" + text.tag,
             coefficient_figure(text.coefficients_title, text.xlabel, coefficient_cases(run, k), run.fits,
                                run.plan.fit_coefs));
  write_plot(dir, "differences_" + text.tag,
             difference_figure(text.differences_title, text.xlabel, difference_cases(run, k), diff_coefs));
  return {"coefficients_" + text.tag + ".png", "differences_" + text.tag + ".png"};
}

double max_abs_difference(const SweepResult& fem, const SweepResult& exact, const std::string& coef) {
  const auto v = fem.column(coef), e = exact.column(coef);
  if (v.size() != e.size())
    throw ComputeError("max_abs_difference: sweeps '" + fem.spec.label + "' and '" + exact.spec.label +
                       "' differ in length");
  double worst = 0;
  for (std::size_t i = 0; i < v.size(); ++i) worst = std::max(worst, std::abs(v[i] - e[i]));
  return worst;
}

std::string max_difference_table(const ComparisonRun& run, const std::string& first_header,
                                 const std::vector<std::string>& coefs) {
  std::vector<std::vector<std::string>> t;
  for (std::size_t k = 0; k < run.plan.sweeps.size(); ++k)
    for (const auto& r : run.arrays)
      for (const auto& f : r.fem) {
        std::vector<std::string> row{run.plan.sweeps[k].label, "`" + r.setup.array.name + "`", f.label};
        for (const auto& coef : coefs) row.push_back(fmt(max_abs_difference(f.sweeps[k], r.exact.sweeps[k], coef), 5));
        t.push_back(row);
      }
  std::vector<std::string> header{first_header, "array", "source"};
  for (const auto& c : coefs) header.push_back("max abs diff " + c.substr(0, c.find('_')));
  return md_table(header, t);
}

std::string fe_solution_text(const std::string& dir, const std::vector<FemSource>& sources,
                             const std::string& interp) {
  std::ostringstream s;
  s << "FE solution `" << dir << "` (" << solve_description(dir) << "), used through ";
  for (std::size_t i = 0; i < sources.size(); ++i)
    s << (i ? " and " : "") << "`" << sources[i].spec << "`"
      << (sources[i].label == "grid" ? " (" + interp + " interpolation)" : "");
  return s.str();
}

}  // namespace magenc
