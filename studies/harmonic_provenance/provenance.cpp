#include "studies/harmonic_provenance/provenance.hpp"

#include <cmath>
#include <map>

#include "analysis/fem_comparison.hpp"
#include "analysis/sweep.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "fields/magnet.hpp"

namespace magenc {

namespace {

// A grid spacing in a variant name: 6 significant digits ("0.05").
std::string h_text(double h) { return fmt_sig(h, 6); }

// The default variants (as studies/harmonic_provenance/harmonic_provenance.toml lists them), one TOML inline array.
const char* kDefaultVariants =
    "[{ label = \"coarse P1\", config = \"meshes/coarse.toml\", set = { fem.order = 1 } }, "
    "{ label = \"coarse P2\", config = \"meshes/coarse.toml\", set = { fem.order = 2 } }, "
    "{ label = \"medium P2\", config = \"meshes/coarse.toml\", set = { fem.order = 2, mesh.h_zone_mm = 0.4, mesh.h_magnet_mm = 0.5 } }, "
    "{ label = \"medium P2 D16\", config = \"meshes/coarse.toml\", "
    "set = { fem.order = 2, mesh.h_zone_mm = 0.4, mesh.h_magnet_mm = 0.5, mesh.symmetry_order = 16 } }]";

}  // namespace

std::vector<KeySpec> provenance_keys() {
  return {
      real_list_key("provenance.spacings_mm", {0.2, 0.1, 0.05, 0.025}, 0, 100, "mm", "grid spacings h (mm), coarse to fine", true),
      string_list_key("provenance.interps", {"nearest", "linear", "cubic"}, {}, "interpolation modes"),
      real_key("provenance.half_width_mm", 3.5, 0, 100, "mm", "plane grids span [-w, w] in x and y", true),
      real_key("provenance.offset_mm", 0.1, 0, 10, "mm", "size of the sx and dx cases", true),
      table_list_key(kFemVariantsKey,
                     {required(string_key("label", "", {}, "the variant's name in tables and plots (no ',')")),
                      string_key("config", "", {}, "a TOML file of solve_field keys (relative: to the working directory "
                                                   "or the magenc source tree)"),
                      settings_field("set", "mesh.*, fem.*, grid.* keys, applied after config")},
                     kDefaultVariants,
                     "FE variants solved here with magnet.mu_r = 1, each a table { label, config, set } "
                     "([[provenance.fem_variants]] sections; --set: an inline array [{ ... }, ...]); empty array: none"),
      string_list_key("provenance.fem_dirs", {}, {}, "solve_field output directories to include (may be empty)", 0),
      string_key("provenance.fem_grid_interp", "cubic", {"none", "nearest", "linear", "cubic"},
                 "also evaluate each FE solution through its plane grid (plane.vti) with this interpolation; none: directly only"),
      real_key("provenance.floor_deg", 1e-4, 0, 1, "deg", "exact c_n at or above this is physical", true),
  };
}

ProvenanceOptions ProvenanceOptions::from_config(const Config& cfg) {
  ProvenanceOptions o;
  o.setup = probe_setup_from_config(cfg, cfg.str("sensor.array"));
  o.spacings_text = cfg.str("provenance.spacings_mm");
  o.spacings_mm = cfg.reals("provenance.spacings_mm");
  o.interps_text = cfg.str("provenance.interps");
  for (const auto& m : cfg.strings("provenance.interps"))
    o.modes.push_back(parse_interp(m, "provenance.interps"));
  o.half_width_mm = cfg.real("provenance.half_width_mm");
  o.offset_mm = cfg.real("provenance.offset_mm");
  o.floor_deg = cfg.real("provenance.floor_deg");
  const Mount base = Mount::from_config(cfg);
  o.cases = {{"ideal", base},
             {"sx=" + fmt(o.offset_mm, 2), with_offset(base, "sx_mm", o.offset_mm)},
             {"dx=" + fmt(o.offset_mm, 2), with_offset(base, "dx_mm", o.offset_mm)}};
  o.fem_dirs = cfg.strings("provenance.fem_dirs");
  o.grid_interp = cfg.str("provenance.fem_grid_interp");
  return o;
}

const ProvenanceRow& ProvenanceRun::row(const std::string& source, const std::string& variant,
                                        const std::string& case_label) const {
  for (const auto& r : rows)
    if (r.source == source && r.variant == variant && r.case_label == case_label) return r;
  throw ComputeError("harmonic_provenance: no row " + source + " " + variant + " " + case_label);
}

ProvenanceRun run_grid_provenance(const Config& cfg, const ProvenanceOptions& options) {
  ProvenanceRun run;
  run.options = options;
  run.exact = std::make_shared<const AnalyticField>(Magnet::from_config(cfg));
  const auto& o = run.options;
  run.rows = grid_sampling_scan(*run.exact, o.setup, o.cases, o.spacings_mm, o.modes, o.half_width_mm);
  run.n_grid_rows = run.rows.size();
  for (const auto& c : o.cases) run.exact_spectra.push_back(error_spectrum(*run.exact, o.setup, c.mount));
  return run;
}

void add_fe_solution(ProvenanceRun& run, const FeSolution& solution, const FieldSource& field, const GridData* plane) {
  const auto& o = run.options;
  auto direct = field_scan(*run.exact, field, "fem", solution.label, o.setup, o.cases);
  run.rows.insert(run.rows.end(), direct.begin(), direct.end());
  if (plane) {
    const GridField g(*plane, parse_interp(o.grid_interp, "provenance.fem_grid_interp"));
    auto via = field_scan(*run.exact, g, "fem_grid", solution.label + " via plane grid", o.setup, o.cases);
    for (auto& x : via) {
      x.h_mm = plane->spacing_mm.x();
      x.interp = o.grid_interp;
    }
    run.rows.insert(run.rows.end(), via.begin(), via.end());
  }
  run.fe.push_back(solution);
}

std::vector<ProvenanceRow> grid_sampling_scan(const FieldSource& exact, const ProbeSetup& setup,
                                              const std::vector<ProvenanceCase>& cases,
                                              const std::vector<double>& spacings_mm,
                                              const std::vector<Interp>& modes, double half_width_mm) {
  std::vector<Spectrum> exact_spectra;
  for (const auto& c : cases) exact_spectra.push_back(error_spectrum(exact, setup, c.mount));
  std::vector<ProvenanceRow> rows;
  for (const double h : spacings_mm) {
    const int half = static_cast<int>(std::ceil(half_width_mm / h - 1e-9));
    const int n = 2 * half + 1;
    const GridData g = sample_grid(exact, Vec3(-half * h, -half * h, setup.plane_z_mm), Vec3(h, h, h), {n, n, 1}, true);
    for (const Interp m : modes) {
      const GridField field(g, m);
      for (std::size_t i = 0; i < cases.size(); ++i) {
        ProvenanceRow r;
        r.source = "grid";
        r.variant = interp_name(m) + " h=" + h_text(h);
        r.h_mm = h;
        r.interp = interp_name(m);
        r.case_label = cases[i].label;
        r.exact = exact_spectra[i];
        r.sampled = error_spectrum(field, setup, cases[i].mount);
        rows.push_back(std::move(r));
      }
    }
  }
  return rows;
}

std::vector<ProvenanceRow> field_scan(const FieldSource& exact, const FieldSource& field, const std::string& source,
                                      const std::string& variant, const ProbeSetup& setup,
                                      const std::vector<ProvenanceCase>& cases) {
  std::vector<ProvenanceRow> rows;
  for (const auto& c : cases) {
    ProvenanceRow r;
    r.source = source;
    r.variant = variant;
    r.case_label = c.label;
    r.exact = error_spectrum(exact, setup, c.mount);
    r.sampled = error_spectrum(field, setup, c.mount);
    rows.push_back(std::move(r));
  }
  return rows;
}

std::vector<HarmonicVerdict> harmonic_verdicts(const std::vector<ProvenanceRow>& rows, double floor_deg) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<const ProvenanceRow*>> by_case;
  for (const auto& r : rows) {
    if (!by_case.count(r.case_label)) order.push_back(r.case_label);
    by_case[r.case_label].push_back(&r);
  }
  std::vector<HarmonicVerdict> out;
  for (const auto& label : order) {
    const auto& rs = by_case[label];
    for (int n = 1; n <= kHarmonics; ++n) {
      HarmonicVerdict v;
      v.case_label = label;
      v.n = n;
      v.exact_deg = rs.front()->exact.c_deg[n];
      v.physical = v.exact_deg >= floor_deg;
      v.best_artifact_deg = 1e300;
      for (const auto* r : rs) {
        const double a = std::abs(r->sampled.c_deg[n] - r->exact.c_deg[n]);
        if (a >= v.worst_artifact_deg) {
          v.worst_artifact_deg = a;
          v.worst_variant = r->variant;
        }
        if (a < v.best_artifact_deg) {
          v.best_artifact_deg = a;
          v.best_variant = r->variant;
        }
      }
      out.push_back(v);
    }
  }
  return out;
}

}  // namespace magenc
