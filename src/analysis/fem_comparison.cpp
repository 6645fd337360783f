#include "analysis/fem_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "field_solver/field_io/solved_field.hpp"

namespace magenc {

std::vector<KeySpec> fem_field_keys(const std::string& default_grid_file) {
  return {
      string_key("fem_field.dir", "output/field", {}, "solve_field output directory (run solve_field --out DIR first)"),
      string_list_key("fem_field.sources", {"grid", "fem"}, {},
                 "FEM field sources: grid (grid:DIR/grid_file, interpolated), fem (fem:DIR, "
                 "FE solution evaluated directly); the first is the one plotted"),
      string_key("fem_field.grid_file", default_grid_file, {"plane.vti", "box.vti"},
                 "grid of DIR that grid sources sample (plane.vti has no dz)"),
      string_key("fem_field.interp", "cubic", {"nearest", "linear", "cubic"}, "grid interpolation"),
  };
}

double AcceptanceRule::tolerance_deg(double exact_deg) const { return std::max(rel * std::abs(exact_deg), abs_deg); }

bool AcceptanceRule::pass(double value_deg, double exact_deg) const {
  return std::abs(value_deg - exact_deg) <= tolerance_deg(exact_deg);
}

std::vector<ComparedCase> compare_sweeps(const SweepResult& fem, const SweepResult& exact, const std::string& source) {
  if (fem.rows.size() != exact.rows.size() || fem.spec.swept != exact.spec.swept ||
      fem.setup.array.name != exact.setup.array.name)
    throw ComputeError("compare_sweeps: sweeps '" + fem.spec.label + "' and '" + exact.spec.label + "' do not match");
  std::vector<ComparedCase> out;
  for (std::size_t i = 0; i < fem.rows.size(); ++i)
    out.push_back({fem.setup.array.name, fem.spec.label, fem.spec.swept, fem.spec.values_mm[i], source,
                   fem.rows[i].spectrum, exact.rows[i].spectrum});
  return out;
}

std::string comparison_csv(const std::vector<ComparedCase>& cases, const std::vector<std::string>& coefs) {
  check_coef_names(coefs, "comparison coefficients");
  std::ostringstream s;
  s << "array,sweep,swept,x_mm,source,coef,value_deg,exact_deg,diff_deg\n";
  for (const auto& c : cases)
    for (const auto& coef : coefs) {
      const double v = c.value.column(coef), e = c.exact.column(coef);
      s << c.array << "," << c.sweep << "," << c.swept << "," << fmt_sig(c.x_mm, 10) << "," << c.source << "," << coef
        << "," << fmt_sig(v, 10) << "," << fmt_sig(e, 10) << "," << fmt_sig(v - e, 10) << "\n";
    }
  return s.str();
}

ComparisonInputs comparison_inputs_from_config(const Config& cfg, FemSources fem) {
  ComparisonInputs in;
  in.sources = std::move(fem.sources);
  in.solve_description = std::move(fem.description);
  in.solve_mu_r = fem.mu_r;
  in.exact = std::make_shared<const AnalyticField>(Magnet::from_config(cfg));
  in.base = Mount::from_config(cfg);
  const auto arrays = cfg.strings("study.arrays");
  ProbeArray::parse(cfg.str("sensor.array"));  // unused here (study.arrays), but still checked
  for (const auto& a : arrays) in.setups.push_back(probe_setup_from_config(cfg, a, "study.arrays"));
  in.dir = fem.dir;
  return in;
}

std::vector<const SourceRun*> ArrayComparison::all() const {
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
    ArrayComparison r;
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

double max_abs_difference(const SweepResult& fem, const SweepResult& exact, const std::string& coef) {
  const auto v = fem.column(coef), e = exact.column(coef);
  if (v.size() != e.size())
    throw ComputeError("max_abs_difference: sweeps '" + fem.spec.label + "' and '" + exact.spec.label +
                       "' differ in length");
  double worst = 0;
  for (std::size_t i = 0; i < v.size(); ++i) worst = std::max(worst, std::abs(v[i] - e[i]));
  return worst;
}

FemSources fem_sources_from_config(const Config& cfg) {
  namespace fs = std::filesystem;
  FemSources r;
  const fs::path dir = cfg.str("fem_field.dir");
  r.dir = dir.string();
  const auto labels = cfg.strings("fem_field.sources");
  const std::string hint = ": run solve_field first (solve_field --out " + dir.string() + ")";
  if (!fs::is_directory(dir)) throw InputError("fem_field.dir '" + dir.string() + "' is not a directory" + hint);
  FieldOptions opts;
  opts.interp = parse_interp(cfg.str("fem_field.interp"), "fem_field.interp");
  for (const auto& l : labels) {
    std::string file, spec;
    if (l == "fem") {
      file = "mesh.vtu";
      spec = "fem:" + dir.string();
    } else if (l == "grid") {
      file = cfg.str("fem_field.grid_file");
      spec = "grid:" + (dir / file).string();
    } else {
      throw InputError("fem_field.sources: '" + l + "' is not a FEM source: allowed grid, fem");
    }
    if (!fs::exists(dir / file))
      throw InputError("fem_field.dir '" + dir.string() + "' has no " + file +
                       (l == "fem" ? ": run solve_field --set output.mesh_vtu=true --out " + dir.string() : hint));
    if (std::any_of(r.sources.begin(), r.sources.end(), [&](const FemSource& s) { return s.label == l; }))
      throw InputError("fem_field.sources: '" + l + "' listed twice");
    r.sources.push_back({l, spec, nullptr});
  }
  // The solve's magnet and plane must be the study's: the exact field beside it
  // is built from the study's [magnet] keys.
  const SolvedFieldDir solved(dir);
  if (const std::string why = solved.mismatch(cfg); !why.empty())
    throw InputError("fem_field.dir '" + dir.string() + "' " + why);
  for (auto& s : r.sources) s.field = open_field_source(s.spec, cfg, opts);
  r.description = solved.description();
  r.mu_r = solved.mu_r();
  return r;
}

}  // namespace magenc
