// The report side of a FEM-vs-exact comparison run (the run itself is
// analysis/fem_comparison.hpp's): tables, the coefficient and difference plots
// of each sweep, and the summary pieces the studies real_field and airgap share.
//   write_comparison_tables        spectra.csv, comparison.csv, fits.csv
//   write_comparison_plots         coefficients_<tag>.png, differences_<tag>.png
//   max_difference_table           largest |FEM - exact| per sweep (markdown)
//   fe_solution_text               which FE solution, used through which sources
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/fem_comparison.hpp"
#include "analysis/sweep.hpp"
#include "report/study_output.hpp"
#include "report/study_plots.hpp"

namespace magenc {

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

// Markdown table, one row per sweep, array and FEM source (in that nesting):
// first_header (the sweep label), array, source, then "max abs diff <c>" per
// coefficient, fmt(value, 5).
std::string max_difference_table(const ComparisonRun& run, const std::string& first_header,
                                 const std::vector<std::string>& coefs);

// "FE solution `DIR` (solve facts), used through `grid:...` (cubic interpolation) and `fem:DIR`"
// for summaries; interp is fem_field.interp.
std::string fe_solution_text(const std::string& dir, const std::string& description, const std::vector<FemSource>& sources,
                             const std::string& interp);

}  // namespace magenc
