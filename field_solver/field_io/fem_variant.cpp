#include "field_solver/field_io/fem_variant.hpp"

#include <cmath>
#include <fstream>
#include <set>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace magenc::fem {

namespace fs = std::filesystem;

namespace {

bool settable(const std::string& key) {
  for (const char* p : {"mesh.", "fem.", "grid."})
    if (key.rfind(p, 0) == 0) return true;
  return false;
}

}  // namespace

std::vector<FemVariantSpec> parse_fem_variants(const ConfigTables& tables, const std::string& key) {
  std::vector<FemVariantSpec> out;
  std::set<std::string> labels;
  for (const auto& t : tables) {
    FemVariantSpec v;
    v.label = t.text("label");
    if (v.label.find(',') != std::string::npos)
      throw InputError(key + ": label '" + v.label + "' contains ',': allowed a label without ',' (it is a CSV cell)");
    if (!labels.insert(v.label).second)
      throw InputError(key + ": label '" + v.label + "' is used twice: allowed one table per label");
    v.config = t.text("config");
    v.settings = t.settings("set");
    out.push_back(std::move(v));
  }
  return out;
}

Config fem_variant_config(const FemVariantSpec& variant, const Config& study_cfg, const std::string& key,
                          const std::vector<fs::path>& search_dirs) {
  const std::string where = key + ": '" + variant.label + "': ";
  Config cfg(solve_field_schema());
  // The study's magnet and sensing plane, mu_r = 1 (the exact field's), quiet solver.
  const std::vector<std::string> fixed = {"magnet.radius_mm", "magnet.height_mm", "magnet.br_T", "magnet.magnetization_deg",
                                          "magnet.magnetization_elevation_deg", "magnet.inner_radius_mm",
                                          "sensor.plane_height_mm"};
  for (const auto& k : fixed) cfg.set_value(k, study_cfg.real(k));
  cfg.set_value("magnet.mu_r", 1.0);
  cfg.set_value("fem.progress_every", 0L);
  // The variants exist to show the total potential's discretization artefacts: with mu_r = 1 the reduced
  // potential (fem.potential = auto) is the exact field itself. A variant may still set fem.potential.
  cfg.set_value("fem.potential", to_string(Potential::Total));
  // Their ideal-mount harmonics that the D16 mesh's symmetry cancels vanish only to the CG tolerance
  // (c4 on meshes/coarse.toml: 7.5e-8 deg at the default 1e-8, 4.9e-10 deg at 1e-10). A variant may set it.
  cfg.set_value("fem.tolerance", 1e-10);
  try {
    if (const std::string& value = variant.config; !value.empty()) {
      fs::path file = value;
      if (file.is_relative())
        for (const auto& d : search_dirs)
          if (fs::is_regular_file(d / value)) {
            file = d / value;
            break;
          }
      if (!fs::is_regular_file(file)) {
        std::string dirs;
        for (const auto& d : search_dirs) dirs += (dirs.empty() ? "" : ", ") + d.string();
        throw InputError("config file '" + value + "' not found" +
                         (file.is_relative() && !dirs.empty() ? " (looked in " + dirs + ")" : ""));
      }
      cfg.load_toml_file(file.string());
    }
    for (const auto& [name, value] : variant.settings) {
      if (!settable(name))
        throw InputError("set: '" + name + "' cannot be set per variant: allowed mesh.*, fem.*, grid.* keys "
                         "(the magnet and sensing plane are the study's, with magnet.mu_r = 1)");
      std::string keys;
      bool known = false;
      for (const auto& k : cfg.schema())
        if (settable(k.key)) {
          keys += (keys.empty() ? "" : ", ") + k.key;
          known = known || k.key == name;
        }
      if (!known) throw InputError("set: unknown key '" + name + "': allowed " + keys);
      cfg.set_value(name, std::visit([](const auto& x) { return ConfigValue(x); }, value));
    }
    // A config file may hold any solve_field key: the magnet, the plane and the shaft must stay as above.
    for (const auto& k : fixed)
      if (cfg.real(k) != study_cfg.real(k))
        throw InputError("sets " + k + " = " + fmt(cfg.real(k), 4) + ", the study uses " + fmt(study_cfg.real(k), 4) +
                         ": variants differ only in mesh.*, fem.*, grid.* keys");
    if (cfg.real("magnet.mu_r") != 1.0)
      throw InputError("sets magnet.mu_r = " + fmt(cfg.real("magnet.mu_r"), 4) +
                       ": variants are solved with mu_r = 1 (compared with the exact field)");
    if (cfg.flag("shaft.enabled")) throw InputError("enables the shaft: variants are the bare magnet (compared with the exact field)");
    (void)fem_settings_from_config(cfg);  // geometry and grids valid
  } catch (const InputError& e) {
    throw InputError(where + e.what());
  }
  return cfg;
}

SolvedFemField solve_fem_field(const Config& solve_cfg) {
  SolvedFemField r;
  r.settings = fem_settings_from_config(solve_cfg);
  MagnetostaticSolver solver(r.settings.domain, r.settings.solver);
  solver.run();
  r.stats = solver.stats();
  // The plane grid as solve_field writes it to plane.vti.
  r.plane = r.settings.plane;
  const Eigen::Matrix3Xd B = solver.evaluator().B_T(r.plane.points_mm());
  if (!B.allFinite()) throw ComputeError("B on the plane grid contains NaN");
  r.plane.set_B(B);
  r.plane.source = "plane grid of the in-process solve";
  r.plane.validate();
  r.field = std::make_shared<const FemField>(solver.solution());
  const DomainSpec& d = r.settings.domain;
  r.facts.order = r.stats.order;
  r.facts.elements = r.stats.elements;
  r.facts.dofs = r.stats.dofs;
  r.facts.iterations = r.stats.iterations;
  r.facts.h_magnet_mm = d.mesh.h_magnet_mm;
  r.facts.h_zone_mm = d.mesh.h_zone_mm;
  r.facts.h_core_mm = d.zone.core() ? d.mesh.h_core_mm : 0.0;
  r.facts.mu_r = d.magnet.mu_r;
  r.facts.t_total_s = r.stats.t_total_s;
  r.facts.plane_step_mm = r.plane.spacing_mm[0];
  r.facts.symmetry_order = d.mesh.symmetric ? d.mesh.symmetry_order : 1;
  return r;
}

std::vector<FemVariant> fem_variants_from_config(const Config& study_cfg, const std::string& key,
                                                 const std::vector<fs::path>& search_dirs) {
  std::vector<FemVariant> out;
  for (const auto& v : parse_fem_variants(study_cfg.tables(key), key))
    out.push_back({v.label, fem_variant_config(v, study_cfg, key, search_dirs)});
  return out;
}

}  // namespace magenc::fem
