#include "analysis/fem_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "fields/field_factory.hpp"
#include "fields/grid_field.hpp"
#include "report/study_output.hpp"
#include "report/study_plots.hpp"

namespace magenc {

namespace fs = std::filesystem;

std::vector<KeySpec> fem_field_keys(const std::string& default_grid_file) {
  return {
      string_key("fem_field.dir", "output/field", {}, "solve_field output directory (run solve_field --out DIR first)"),
      string_key("fem_field.sources", "grid,fem", {},
                 "comma-separated FEM field sources: grid (grid:DIR/grid_file, interpolated), fem (fem:DIR, "
                 "FE solution evaluated directly); the first is the one plotted"),
      string_key("fem_field.grid_file", default_grid_file, {"plane.vti", "box.vti"},
                 "grid of DIR that grid sources sample (plane.vti has no dz)"),
      string_key("fem_field.interp", "cubic", {"nearest", "linear", "cubic"}, "grid interpolation"),
  };
}

namespace {

nlohmann::json read_solve_json(const fs::path& dir) {
  std::ifstream in(dir / "solve.json");
  if (!in) return {};
  try {
    return nlohmann::json::parse(in);
  } catch (...) {
    return {};
  }
}

}  // namespace

std::string solve_mismatch(const fs::path& dir, const Config& cfg) {
  const nlohmann::json j = read_solve_json(dir);
  if (!j.contains("magnet")) return "";
  const auto differs = [](double a, double b) { return std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(b)); };
  for (const char* k : {"radius_mm", "height_mm", "br_T"}) {
    const double solved = j["magnet"].value(k, std::numeric_limits<double>::quiet_NaN());
    const double want = cfg.real(std::string("magnet.") + k);
    if (differs(solved, want))
      return "was solved with magnet." + std::string(k) + " = " + fmt(solved, 4) + ", the study uses " + fmt(want, 4) +
             ": solve again with the study's [magnet] keys";
  }
  if (j.contains("plane_z_mm")) {
    const double solved = j["plane_z_mm"].get<double>();
    const double want = 0.5 * cfg.real("magnet.height_mm") + cfg.real("sensor.plane_height_mm");
    if (differs(solved, want))
      return "has its sensing plane at z = " + fmt(solved, 4) + " mm, the study uses z_s = " + fmt(want, 4) +
             " mm (sensor.plane_height_mm)";
  }
  return "";
}

namespace {
}  // namespace

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
  const nlohmann::json j = read_solve_json(dir);
  if (j.empty()) return "";
  std::ostringstream s;
  try {
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
  if (!j.contains("magnet") || !j["magnet"].contains("mu_r")) return std::numeric_limits<double>::quiet_NaN();
  return j["magnet"]["mu_r"].get<double>();
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
  s.precision(10);
  s << "array,sweep,swept,x_mm,source,coef,value_deg,exact_deg,diff_deg\n";
  for (const auto& c : cases)
    for (const auto& coef : coefs) {
      const double v = c.value.column(coef), e = c.exact.column(coef);
      s << c.array << "," << c.sweep << "," << c.swept << "," << c.x_mm << "," << c.source << "," << coef << "," << v
        << "," << e << "," << (v - e) << "\n";
    }
  return s.str();
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
