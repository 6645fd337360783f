// FE variants of a study (field_solver/field_io/fem_variant.hpp): [[provenance.fem_variants]] tables
// {label, config, set} to solve_field configurations, checked before anything is solved.
#include <catch2/catch.hpp>
#include <string>

#include "studies/harmonic_provenance/provenance.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "field_solver/field_io/fem_variant.hpp"
#include "probe/common_keys.hpp"

using namespace magenc;

namespace {
Config study_config(const std::string& toml) {
  Config cfg(merge_schemas(common_keys(), provenance_keys()));
  cfg.load_toml_string(toml, "study.toml");
  return cfg;
}
const std::vector<std::filesystem::path> kSearch = {MAGENC_SOURCE_DIR};
}  // namespace

TEST_CASE("fem variants: label config and set of each table become the solve_field configuration",
          "[field_solver][contract]") {
  const Config cfg = study_config(
      "[magnet]\nradius_mm = 2.5\n"
      "[[provenance.fem_variants]]\nlabel = \"medium P2\"\nconfig = \"meshes/coarse.toml\"\n"
      "set = { fem.order = 2, mesh.h_zone_mm = 0.4, \"mesh.h_magnet_mm\" = 0.5 }\n"
      "[[provenance.fem_variants]]\nlabel = \"defaults P1\"\nset = { fem = { order = 1 } }\n");
  const auto variants = fem::fem_variants_from_config(cfg, kFemVariantsKey, kSearch);
  REQUIRE(variants.size() == 2);
  CHECK(variants[0].label == "medium P2");
  const Config& a = variants[0].solve_cfg;
  CHECK(a.integer("fem.order") == 2);
  CHECK(a.real("mesh.h_zone_mm") == 0.4);
  CHECK(a.real("mesh.h_magnet_mm") == 0.5);
  CHECK(a.real("magnet.radius_mm") == 2.5);  // the study's magnet
  CHECK(a.real("magnet.mu_r") == 1.0);       // compared with the exact field
  // The config file is applied first: coarse.toml's mesh (not the solve_field defaults) where set says nothing.
  Config coarse(fem::solve_field_schema());
  coarse.load_toml_file(std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml");
  Config defaults(fem::solve_field_schema());
  CHECK(a.real("mesh.h_air_mm") == coarse.real("mesh.h_air_mm"));
  CHECK(variants[1].label == "defaults P1");
  CHECK(variants[1].solve_cfg.integer("fem.order") == 1);
  CHECK(variants[1].solve_cfg.real("mesh.h_zone_mm") == defaults.real("mesh.h_zone_mm"));
  // The default of the key is the four variants of studies/harmonic_provenance/harmonic_provenance.toml.
  const Config def = study_config("");
  const auto d = fem::fem_variants_from_config(def, kFemVariantsKey, kSearch);
  REQUIRE(d.size() == 4);
  CHECK(d[3].label == "medium P2 D16");
  CHECK(d[3].solve_cfg.integer("mesh.symmetry_order") == 16);
  CHECK(fem::fem_variants_from_config(study_config("[provenance]\nfem_variants = []\n"), kFemVariantsKey, kSearch).empty());
}

TEST_CASE("fem variants: a bad table is one line naming provenance.fem_variants", "[field_solver][bad-input]") {
  for (const auto& [tables, reason] : std::vector<std::pair<std::string, std::string>>{
           {"[[provenance.fem_variants]]\nconfig = \"meshes/coarse.toml\"\n", "has no label"},
           {"[[provenance.fem_variants]]\nlabel = \"a\"\norder = 2\n", "unknown field 'order'"},
           {"[[provenance.fem_variants]]\nlabel = \"a\"\nset = { fem.order = \"2\" }\n", "fem.order must be an integer"},
           {"[[provenance.fem_variants]]\nlabel = \"a\"\n[[provenance.fem_variants]]\nlabel = \"a\"\n", "used twice"},
           {"[[provenance.fem_variants]]\nlabel = \"a\"\nset = { fem.no_such_key = 1 }\n", "unknown key 'fem.no_such_key'"},
           {"[[provenance.fem_variants]]\nlabel = \"a\"\nset = { sensor.plane_height_mm = 2 }\n", "cannot be set per variant"},
           {"[[provenance.fem_variants]]\nlabel = \"a\"\nconfig = \"meshes/no_such.toml\"\n", "not found"}}) {
    std::string error = "no error";
    try {
      (void)fem::fem_variants_from_config(study_config(tables), kFemVariantsKey, kSearch);
    } catch (const InputError& e) {
      error = e.what();
    }
    INFO(tables << "-> " << error);
    CHECK(error.find("provenance.fem_variants") != std::string::npos);
    CHECK(error.find(reason) != std::string::npos);
    CHECK(error.find('\n') == std::string::npos);
  }
}
