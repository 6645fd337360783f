#include "analysis/fem_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "fields/field_factory.hpp"
#include "fields/grid_field.hpp"

namespace magenc {

namespace fs = std::filesystem;

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

namespace {

// DIR/solve.json, or {} when there is none. A file that is there but is not a JSON object (truncated,
// corrupted) is an InputError, not a silently skipped check.
nlohmann::json read_solve_json(const fs::path& dir) {
  std::ifstream in(dir / "solve.json");
  if (!in) return {};
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError((dir / "solve.json").string() + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object()) throw InputError((dir / "solve.json").string() + ": not a JSON object (expected solve_field's record)");
  return j;
}

// A number of solve.json (NaN when absent); InputError when present with another type.
double json_number(const nlohmann::json& obj, const char* key, const fs::path& dir) {
  if (!obj.is_object() || !obj.contains(key)) return std::numeric_limits<double>::quiet_NaN();
  const auto& v = obj.at(key);
  if (!v.is_number())
    throw InputError((dir / "solve.json").string() + ": '" + key + "' is not a number (expected solve_field's record)");
  return v.get<double>();
}

}  // namespace

std::string solve_mismatch(const fs::path& dir, const Config& cfg) {
  const nlohmann::json j = read_solve_json(dir);
  if (!j.contains("magnet")) return "";
  if (!j["magnet"].is_object())
    throw InputError((dir / "solve.json").string() + ": 'magnet' is not an object (expected solve_field's record)");
  const auto differs = [](double a, double b) { return std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(b)); };
  for (const char* k : {"radius_mm", "height_mm", "br_T"}) {
    const double solved = json_number(j["magnet"], k, dir);
    const double want = cfg.real(std::string("magnet.") + k);
    if (differs(solved, want))
      return "was solved with magnet." + std::string(k) + " = " + fmt(solved, 4) + ", the study uses " + fmt(want, 4) +
             ": solve again with the study's [magnet] keys";
  }
  {  // solves written before the key existed had no elevation
    const double solved = j["magnet"].value("magnetization_elevation_deg", 0.0);
    const double want = cfg.real("magnet.magnetization_elevation_deg");
    if (differs(solved, want))
      return "was solved with magnet.magnetization_elevation_deg = " + fmt(solved, 4) + ", the study uses " +
             fmt(want, 4) + ": solve again with the study's [magnet] keys";
  }
  if (j.contains("plane_z_mm")) {
    const double solved = json_number(j, "plane_z_mm", dir);
    const double want = 0.5 * cfg.real("magnet.height_mm") + cfg.real("sensor.plane_height_mm");
    if (differs(solved, want))
      return "has its sensing plane at z = " + fmt(solved, 4) + " mm, the study uses z_s = " + fmt(want, 4) +
             " mm (sensor.plane_height_mm)";
  }
  return "";
}

std::vector<FemSource> fem_sources_from_config(const Config& cfg) {
  const fs::path dir = cfg.str("fem_field.dir");
  const auto labels = split_list(cfg.str("fem_field.sources"), "fem_field.sources");
  const std::string hint = ": run solve_field first (solve_field --out " + dir.string() + ")";
  if (!fs::is_directory(dir)) throw InputError("fem_field.dir '" + dir.string() + "' is not a directory" + hint);
  FieldOptions opts;
  opts.interp = parse_interp(cfg.str("fem_field.interp"), "fem_field.interp");
  std::vector<FemSource> out;
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
    if (std::any_of(out.begin(), out.end(), [&](const FemSource& s) { return s.label == l; }))
      throw InputError("fem_field.sources: '" + l + "' listed twice");
    out.push_back({l, spec, nullptr});
  }
  // The solve's magnet and plane must be the study's: the exact field beside it
  // is built from the study's [magnet] keys.
  if (const std::string why = solve_mismatch(dir, cfg); !why.empty())
    throw InputError("fem_field.dir '" + dir.string() + "' " + why);
  for (auto& s : out) s.field = make_field_source(s.spec, cfg, opts);
  return out;
}

std::string solve_description(const fs::path& dir) {
  std::ostringstream s;
  try {
    const nlohmann::json j = read_solve_json(dir);
    if (j.empty()) return "";
    s << "order " << j.value("order", 0) << ", " << j.value("elements", 0L) << " tetrahedra, "
      << j.value("dofs", 0L) << " dofs";
    if (j.contains("domain")) {
      const auto& d = j["domain"];
      s << ", " << d.value("segments", 0) << " segments on the curved face, h_zone " << fmt(d.value("h_zone_mm", 0.0), 3)
        << " mm, outer radius " << fmt(d.value("outer_radius_mm", 0.0), 1) << " mm";
    }
    if (j.contains("magnet")) s << ", magnet mu_r " << fmt(j["magnet"].value("mu_r", 0.0), 3);
    if (j.contains("plane_grid")) s << ", plane grid step " << fmt(j["plane_grid"].value("step_mm", 0.0), 3) << " mm";
    if (j.contains("box_grid")) s << ", box grid step " << fmt(j["box_grid"].value("step_mm", 0.0), 3) << " mm";
    s << ", solve " << fmt(j.value("t_total_s", 0.0), 1) << " s";
  } catch (...) {
    return "";
  }
  return s.str();
}

double solve_mu_r(const fs::path& dir) {
  const nlohmann::json j = read_solve_json(dir);
  if (!j.contains("magnet")) return std::numeric_limits<double>::quiet_NaN();
  return json_number(j["magnet"], "mu_r", dir);
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

}  // namespace magenc
