// Comparison of an FE solution with a reference field (e.g. the exact
// AnalyticField) on a grid: errors of Bz relative to the peak |Bz|.
#pragma once
#include <memory>

#include "field_solver/fe/fe_solution.hpp"
#include "fields/field_source.hpp"
#include "fields/grid.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"

namespace magenc::fem {

struct BzErrorStats {
  long points = 0;
  double peak_T = 0;     // max |Bz_ref| on the grid (T)
  double max_abs_T = 0;  // max |Bz_fem - Bz_ref| (T)
  double rms_T = 0;      // RMS of Bz_fem - Bz_ref (T)
  double peak_B_T = 0;    // max |B_ref| on the grid (T)
  double rms_vec_T = 0;   // RMS of |B_fem - B_ref| (all three components, T)
  double max_rel() const { return max_abs_T / peak_T; }  // relative to peak |Bz_ref|
  double rms_rel() const { return rms_T / peak_T; }
  double rms_vec_rel() const { return rms_vec_T / peak_B_T; }  // relative to peak |B_ref|
};

// Bz error of the FE solution against ref on every grid point (parallel).
BzErrorStats bz_error_on_grid(const FieldEvaluator& fem, const FieldSource& ref, const GridData& grid);

// The exact field of a magnet: AnalyticField (uniform) or MultipoleField (a sector pattern).
std::shared_ptr<const FieldSource> exact_field_of(const Magnet& magnet);

// One FEM solve compared with the exact AnalyticField of the same magnet
// (meaningful for mu_r = 1 everywhere: the exact field has no permeability).
struct ExactComparison {
  SolveStats stats;
  BzErrorStats error;
  double peak_rss_mib = 0;  // process peak RSS after the solve
};
ExactComparison solve_and_compare_with_exact(const DomainSpec& domain, const SolverOptions& options, const GridData& grid);

}  // namespace magenc::fem
