// One FEM-vs-exact comparison run, the orchestration the studies real_field and
// airgap share (issue "FEM-driven probe studies"): every probe array runs the
// same sweeps (and optional single mounts) on each FEM field source and on the
// exact field of the same magnet; every sweep gets its cubic fits and every FEM
// sweep is paired with the exact one (fem_comparison.hpp). The studies only
// choose the sweeps and write their own summary text.
//   comparison_inputs_from_config  the FEM sources, exact field, base mount and
//                                  probe setups of the configuration
//   run_comparison                 all sweeps on all sources, fits, FEM/exact pairs
//   write_comparison_tables        spectra.csv, comparison.csv, fits.csv
//   write_comparison_plots         coefficients_<tag>.png, differences_<tag>.png
//   max_difference_table           largest |FEM - exact| per sweep (markdown)
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fields/analytic_field.hpp"
#include "core/config.hpp"
#include "analysis/fem_comparison.hpp"
#include "probe/mounting.hpp"
#include "report/study_output.hpp"
#include "report/study_plots.hpp"
#include "analysis/sweep.hpp"

namespace magenc {

// What a FEM-vs-exact study reads from its configuration.
struct ComparisonInputs {
  std::string dir;                              // fem_field.dir (solve_field output directory)
  std::vector<FemSource> sources;               // fem_field.sources, in order; the first is plotted
  std::shared_ptr<const AnalyticField> exact;   // exact field of the [magnet] keys
  Mount base;                                   // [mount] (mm)
  std::vector<ProbeSetup> setups;               // one per study.arrays entry ([sensor] keys for r0, plane, steps)
};

// Reads [fem_field] (fem_sources_from_config: a missing solve directory fails
// first), [magnet], [mount], study.arrays (comma list of probe arrays) and
// checks sensor.array (unused by these studies, still validated). Needs
// register_fem_field_scheme() to have been called when "fem" is a source.
ComparisonInputs comparison_inputs_from_config(const Config& cfg);

// All results of one probe array on one field (a FEM source or the exact field).
struct SourceRun {
  std::string label;                       // FemSource label ("grid", "fem") or "exact"
  std::string field;                       // FieldSource::name() (spectra column `field`)
  std::optional<AngleErrorResult> ideal;   // at ComparisonPlan::ideal, when the plan has one
  std::vector<AngleErrorResult> points;    // one per ComparisonPlan::points entry
  std::vector<SweepResult> sweeps;         // one per ComparisonPlan::sweeps entry
};

struct ArrayRun {
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
  std::vector<ArrayRun> arrays;         // one per setup, in order
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

// Writes spectra.csv (comparison_spectra_rows), comparison.csv (every spectra
// coefficient of run.compared) and fits.csv into out.
void write_comparison_tables(StudyOutput& out, const ComparisonRun& run);

// The plot inputs of sweep k: per array, the first FEM source and the exact
// field (coefficient plot, legend "<array> <source>"); per array every FEM
// source against the exact field (difference plot).
std::vector<SweepCase> coefficient_cases(const ComparisonRun& run, std::size_t k);
std::vector<DifferenceCase> difference_cases(const ComparisonRun& run, std::size_t k);

// Titles and file-name tag of the two plots of one sweep.
struct SweepPlotText {
  std::string tag;                  // coefficients_<tag>.png, differences_<tag>.png
  std::string xlabel;               // swept offset axis, e.g. "dz [mm]"
  std::string coefficients_title;   // coefficient_figure title
  std::string differences_title;    // difference_figure title
};
// Writes coefficients_<tag> (plan.fit_coefs with their fits) and
// differences_<tag> (diff_coefs) for sweep k into dir; returns the two PNG names.
std::vector<std::string> write_comparison_plots(const std::filesystem::path& dir, const ComparisonRun& run,
                                                std::size_t k, const SweepPlotText& text,
                                                const std::vector<std::string>& diff_coefs);

// Largest |FEM - exact| of coef over two sweeps of equal length (deg).
double max_abs_difference(const SweepResult& fem, const SweepResult& exact, const std::string& coef);

// Markdown table, one row per sweep, array and FEM source (in that nesting):
// first_header (the sweep label), array, source, then "max abs diff <c>" per
// coefficient, fmt(value, 5).
std::string max_difference_table(const ComparisonRun& run, const std::string& first_header,
                                 const std::vector<std::string>& coefs);

// "FE solution `DIR` (solve facts), used through `grid:...` (cubic interpolation) and `fem:DIR`"
// for summaries; interp is fem_field.interp.
std::string fe_solution_text(const std::string& dir, const std::vector<FemSource>& sources,
                             const std::string& interp);

}  // namespace magenc
