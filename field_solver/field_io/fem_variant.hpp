// FE variants solved inside a study: what solve_field does, without files.
// A variant is a label plus solve_field settings applied on top of the
// defaults, one table of a study's table-list key (core/config.hpp):
//   [[provenance.fem_variants]]
//   label = "medium P2"                       # required; names the variant in tables (no ',')
//   config = "meshes/coarse.toml"             # optional: a TOML file of solve_field keys, loaded first
//   set = { fem.order = 2, mesh.h_zone_mm = 0.4 }   # optional: mesh.*, fem.*, grid.* keys, applied after config
// The magnet and sensing plane are the study's, with magnet.mu_r = 1, so the
// solution can be compared with the exact field (which has no permeability).
// Sample: build/bin/harmonic_provenance --set 'provenance.fem_variants=[{ label = "P1", config = "meshes/coarse.toml", set = { fem.order = 1 } }]'
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "field_solver/field_io/fem_field.hpp"
#include "field_solver/field_io/solve_facts.hpp"
#include "fields/grid_field.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"

namespace magenc::fem {

struct FemVariantSpec {
  std::string label;   // e.g. "coarse P1" (no ',': it is a CSV cell)
  std::string config;  // a TOML file of solve_field keys ("" for none), applied first
  std::vector<std::pair<std::string, ConfigScalar>> settings;  // "section.key" = value, applied after config
};

// The variants of the table-list key `key` (fields checked by Config). InputError
// naming `key` for a label with ',' or a label used twice.
std::vector<FemVariantSpec> parse_fem_variants(const ConfigTables& tables, const std::string& key);

// The solve_field Config of one variant: solve_field's defaults, the study's
// [magnet] keys and sensor.plane_height_mm with magnet.mu_r = 1 and
// fem.progress_every = 0, then the variant's config file, then its settings. A
// relative config file is looked up in each of search_dirs in turn. Only mesh.*, fem.*
// and grid.* may be set (a file that changes the magnet, the plane or enables
// the shaft is rejected); the settings are validated with
// fem_settings_from_config. Every error is one InputError line
// "<key>: 'LABEL': <reason>".
Config fem_variant_config(const FemVariantSpec& variant, const Config& study_cfg, const std::string& key,
                          const std::vector<std::filesystem::path>& search_dirs);

// A parsed variant with its solve_field Config.
struct FemVariant {
  std::string label;
  Config solve_cfg;
};
// Every variant of the study's `key` (parse_fem_variants, then fem_variant_config
// each): all are checked before any is solved.
std::vector<FemVariant> fem_variants_from_config(const Config& study_cfg, const std::string& key,
                                                 const std::vector<std::filesystem::path>& search_dirs);

// Facts of an FE solution for summaries (defined beside the provenance analysis that reports them).
using FemSolveFacts = magenc::FeSolveFacts;

// A solve made in this process.
struct SolvedFemField {
  FemSettings settings;
  SolveStats stats;
  FemSolveFacts facts;
  std::shared_ptr<const FemField> field;  // the FE solution, evaluated directly
  GridData plane;                         // B on settings.plane (what solve_field writes to plane.vti)
};

// Meshes, assembles, solves (MagnetostaticSolver) with fem_settings_from_config(cfg)
// and returns the solution as a field source plus its plane grid. ComputeError
// when the solve fails.
SolvedFemField solve_fem_field(const Config& solve_cfg);

}  // namespace magenc::fem
