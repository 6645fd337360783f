// FEM field vs exact field, case by case (issue "FEM-driven probe studies"):
// the studies real_field and airgap run every mounting case on a solved FE
// field (fem:DIR and/or grid:DIR/FILE.vti) and on the exact field of the same
// magnet, and report each FEM coefficient beside the exact one and their
// difference. This header holds what they share:
//   fem_sources_from_config  the solved directory and the FEM field sources
//                            ([fem_field] keys), with a one-line error naming
//                            solve_field when the directory is not there
//   AcceptanceRule           |FEM - exact| <= max(rel*|exact|, abs_deg)
//   comparison_csv           long table: one row per case, source and coefficient
//   difference_figure        FEM - exact vs the swept offset, per coefficient
// The run itself (every sweep on every source, fits, tables, plots) is
// comparison_run.hpp's.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "io/plot.hpp"
#include "probe/spectrum.hpp"
#include "analysis/sweep.hpp"

namespace magenc {

// The [fem_field] keys of the FEM-driven studies:
//   fem_field.dir        solve_field output directory (mm, T)          default output/field
//   fem_field.sources    comma list of "fem" (FE solution evaluated directly) and
//                        "grid" (grid:DIR/<grid_file>, interpolated)   default "grid,fem"
//   fem_field.grid_file  the .vti of DIR that grid sources sample      default given per study
//   fem_field.interp     grid interpolation nearest|linear|cubic       default cubic
std::vector<KeySpec> fem_field_keys(const std::string& default_grid_file);

// One FEM field source of a study.
struct FemSource {
  std::string label;      // "fem" or "grid" (table column `source`, plot legends)
  std::string spec;       // make_field_source spec: "fem:DIR" or "grid:DIR/box.vti"
  FieldSourcePtr field;
};

// Checks that fem_field.dir holds what the listed sources need (mesh.vtu for
// fem, the grid file for grid) and builds the sources (fem: needs
// register_fem_field_scheme() to have been called). A missing directory or
// file throws one InputError line, e.g.
//   "fem_field.dir 'output/field' has no mesh.vtu: run solve_field first (solve_field --out output/field)".
std::vector<FemSource> fem_sources_from_config(const Config& cfg);

// Why the solve in DIR does not fit the configured magnet and sensing plane
// (magnet.radius_mm, height_mm, br_T, z_s differ from DIR/solve.json), e.g.
// "was solved with magnet.radius_mm = 2, the study uses 3: ..."; "" when it
// fits or solve.json records no magnet.
std::string solve_mismatch(const std::filesystem::path& dir, const Config& cfg);

// Selected facts of DIR/solve.json for summaries ("order 2, 230k elements,
// mu_r 1.05, ..."); "" when the file is missing or unreadable.
std::string solve_description(const std::filesystem::path& dir);
// magnet.mu_r recorded in DIR/solve.json, or NaN when absent.
double solve_mu_r(const std::filesystem::path& dir);

// The acceptance rule for a FEM coefficient against the exact one:
// |value - exact| <= max(rel * |exact|, abs_deg).
struct AcceptanceRule {
  double rel = 0.02;       // fraction of |exact|
  double abs_deg = 0.002;  // deg
  double tolerance_deg(double exact_deg) const;
  bool pass(double value_deg, double exact_deg) const;
};

// One mounting case on one FEM source, with the same case on the exact field.
struct ComparedCase {
  std::string array;    // "two", ...
  std::string sweep;    // case label ("ideal", "sx", "dz (dx=0.05)", ...)
  std::string swept;    // swept variable ("sx_mm", ..., "" for the ideal mount)
  double x_mm = 0;      // its value
  std::string source;   // FemSource label
  Spectrum value;       // on the FEM source
  Spectrum exact;       // on the exact field
};

// Pairs the rows of a FEM sweep with the rows of the same sweep on the exact
// field (same spec, same setup); ComputeError if they do not match.
std::vector<ComparedCase> compare_sweeps(const SweepResult& fem, const SweepResult& exact,
                                         const std::string& source);

// Long table, one row per case and coefficient:
// array,sweep,swept,x_mm,source,coef,value_deg,exact_deg,diff_deg
// (diff = value - exact), for the coefficients listed.
std::string comparison_csv(const std::vector<ComparedCase>& cases, const std::vector<std::string>& coefs);

// A labelled pair of sweeps (FEM source and exact field, same spec).
struct DifferenceCase {
  std::string label;          // legend entry (enhanced text)
  const SweepResult* value;   // on the FEM source
  const SweepResult* exact;   // on the exact field
};
// One panel per coefficient: value - exact (deg) vs the swept offset.
PlotSpec difference_figure(const std::string& title, const std::string& xlabel,
                           const std::vector<DifferenceCase>& cases, const std::vector<std::string>& coefs,
                           int columns = 2);

}  // namespace magenc
