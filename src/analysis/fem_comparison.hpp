// FEM field vs exact field, case by case: the studies real_field and airgap run
// every mounting case on a solved FE field (fem:DIR and/or grid:DIR/FILE.vti)
// and on the exact field of the same magnet, and report each FEM coefficient
// beside the exact one and their difference. This header holds the computation
// they share (the tables, plots and summaries are report/comparison_run.hpp's):
//   FemSources                     the solved directory and its FEM field sources
//                                  (opened by field_solver/field_io/solved_field.hpp)
//   comparison_inputs_from_config  the FEM sources with the exact field, base mount
//                                  and probe setups of the configuration
//   run_comparison                 all sweeps on all sources, fits, FEM/exact pairs
//   AcceptanceRule                 |FEM - exact| <= max(rel*|exact|, abs_deg)
//                                  (judged cell by cell in fem_field_studies.hpp)
//   comparison_csv                 long table: one row per case, source and coefficient
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "analysis/sweep.hpp"
#include "core/config.hpp"
#include "fields/analytic_field.hpp"
#include "fields/field_source.hpp"
#include "probe/mounting.hpp"
#include "probe/spectrum.hpp"

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
  std::string spec;       // open_field_source spec: "fem:DIR" or "grid:DIR/box.vti"
  FieldSourcePtr field;
};

// The FEM field sources of a study and what its solve.json says (fem_sources_from_config).
struct FemSources {
  std::string dir;                // fem_field.dir (solve_field output directory)
  std::vector<FemSource> sources; // fem_field.sources, in order; the first is plotted
  std::string description;        // facts of the solve for summaries ("order 2, ..."; "" when unreadable)
  double mu_r = 0;                // magnet.mu_r of the solve (NaN if not recorded)
};

// Checks that fem_field.dir holds what the listed fem_field.sources need
// (mesh.vtu for fem, the grid file for grid), that it is a solve of the
// configured magnet and plane, and opens the sources. A missing directory or
// file throws one InputError line, e.g.
//   "fem_field.dir 'output/field' has no mesh.vtu: run solve_field --set output.mesh_vtu=true --out output/field".
FemSources fem_sources_from_config(const Config& cfg);

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

// What a FEM-vs-exact study reads from its configuration.
struct ComparisonInputs {
  std::string dir;                              // fem_field.dir (solve_field output directory)
  std::vector<FemSource> sources;               // fem_field.sources, in order; the first is plotted
  std::string solve_description;                // FemSources::description
  double solve_mu_r = 0;                        // FemSources::mu_r
  std::shared_ptr<const AnalyticField> exact;   // exact field of the [magnet] keys
  Mount base;                                   // [mount] (mm)
  std::vector<ProbeSetup> setups;               // one per study.arrays entry ([sensor] keys for r0, plane, steps)
};

// Takes the opened FEM sources (fem_sources_from_config, called
// first so a missing solve directory is the error reported), reads [magnet],
// [mount], study.arrays (comma list of probe arrays) and checks sensor.array
// (unused by these studies, still validated).
ComparisonInputs comparison_inputs_from_config(const Config& cfg, FemSources fem);

// All results of one probe array on one field (a FEM source or the exact field).
struct SourceRun {
  std::string label;                       // FemSource label ("grid", "fem") or "exact"
  std::string field;                       // FieldSource::name() (spectra column `field`)
  std::optional<AngleErrorResult> ideal;   // at ComparisonPlan::ideal, when the plan has one
  std::vector<AngleErrorResult> points;    // one per ComparisonPlan::points entry
  std::vector<SweepResult> sweeps;         // one per ComparisonPlan::sweeps entry
};

// One probe array run on every FEM source and on the exact field.
struct ArrayComparison {
  ProbeSetup setup;
  std::vector<SourceRun> fem;  // per FEM source, in ComparisonInputs::sources order
  SourceRun exact;
  // The FEM sources in order, then the exact field.
  std::vector<const SourceRun*> all() const;
};

// What every array runs on every source.
struct ComparisonPlan {
  std::string study;                    // fits.csv `study` column
  std::vector<SweepSpec> sweeps;        // swept cases; SweepSpec::label names them in tables
  std::vector<std::string> fit_coefs;   // spectra columns fitted with a cubic over each sweep (and plotted)
  std::optional<Mount> ideal;           // a single mount tabulated as sweep "ideal" in spectra/comparison rows
  std::vector<Mount> points;            // further single mounts, computed but not tabulated
};

struct ComparisonRun {
  ComparisonPlan plan;
  std::vector<ArrayComparison> arrays;  // one per setup, in order
  std::vector<FitRow> fits;             // per array: exact, then each FEM source; per sweep, per coefficient
  std::vector<ComparedCase> compared;   // per array and FEM source: the ideal mount (if any), then each sweep's rows
};

// Runs plan on every setup, on each FEM source and on `exact`.
ComparisonRun run_comparison(const std::vector<FemSource>& sources, const FieldSource& exact,
                             const std::vector<ProbeSetup>& setups, const ComparisonPlan& plan);

// Spectra-table rows: per array, each FEM source then the exact field; per
// source the ideal mount (extra column sweep = "ideal") if the plan has one,
// then every sweep row; each row carries extra columns sweep and source.
std::vector<SpectrumRow> comparison_spectra_rows(const ComparisonRun& run);

// Largest |FEM - exact| of coef over two sweeps of equal length (deg).
double max_abs_difference(const SweepResult& fem, const SweepResult& exact, const std::string& coef);
}  // namespace magenc
