// Output of the radius study (radius_scan.hpp): CSV tables, plots and the
// computed summary.md text. Every number in the summary comes from the
// RadiusScanResult; nothing is typed in.
//
// Files (docs/interfaces.md conventions):
//   radius.csv                one row per (field, array, r0): amplitude, worst
//                             corner, MC percentiles, noise, totals
//   radius_spectra.csv        spectra table of the six mounting cases per
//                             (field, array, r0), extra column `case`
//   radius_recommendation.csv one row per (field, array)
//   radius_validation.csv     surrogate vs direct pipeline
//   harmonics_<field>_<array>.png, percentiles_<field>.png, total_p99.png, bz_profile.png
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/study_setup.hpp"
#include "analysis/radius_scan.hpp"

namespace magenc {

// windowed: the field-window columns (mc_out_of_window, corners_out_of_window, field_min_mT,
// field_max_mT) after the standard ones (RadiusScanOptions::window set).
std::string radius_csv(const RadiusScanResult& r, bool windowed = false);
std::string recommendation_csv(const RadiusScanResult& r);
std::string validation_csv(const RadiusScanResult& r);

// Surrogate-vs-direct discrepancies of one field (over its validation rows).
struct ValidationSummary {
  int cases = 0;                   // validation rows
  double max_pp_diff_deg = 0;      // max |pp_surrogate - pp_direct|
  double max_rel_pp_diff = 0;      // max |pp_surrogate - pp_direct| / pp_direct over cases with pp_direct >= 0.01 deg
  double max_coef_diff_deg = 0;    // max |a_n, b_n surrogate - direct|
  double max_grid_pp_diff_deg = 0; // max |pp_direct(fast_steps) - pp_direct(direct_steps)|
  double max_model_pp_diff_deg = 0;// max |pp_surrogate - pp_direct(fast_steps)| (field model alone)
};
ValidationSummary summarize_validation(const RadiusScanResult& r, const std::string& field);

// Safe file-name part of an array name: "ring:8" -> "ring8".
std::string file_tag(const std::string& name);

// radius_budget.csv: field,array,r0_mm,group,p99_only_deg,p99_all_deg,share (radius_scan.hpp BudgetRow).
std::string budget_csv(const RadiusScanResult& r);
// budget.png: one panel per (field, array), bars of 100 * share per group (nothing when there is no budget).
void write_budget_plot(const RadiusScanResult& r, const std::filesystem::path& dir);

// Writes the plots into dir.
void write_radius_plots(const RadiusScanResult& r, const RadiusScanOptions& opt, const std::filesystem::path& dir);

// summary.md. notes: lines about which fields ran; wall_s: scan wall time.
std::string radius_summary_md(const RadiusScanResult& r, const RadiusScanOptions& opt, const StudySetup& setup,
                              const std::vector<std::string>& notes, double wall_s);

}  // namespace magenc
