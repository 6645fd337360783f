// Comparison of an FE solution with a reference field (e.g. the exact
// AnalyticField) on a grid: errors of Bz relative to the peak |Bz|.
#pragma once
#include "fe_solution.hpp"
#include "field_source.hpp"
#include "grids.hpp"

namespace magenc::fem {

struct BzErrorStats {
  long points = 0;
  double peak_T = 0;     // max |Bz_ref| on the grid (T)
  double max_abs_T = 0;  // max |Bz_fem - Bz_ref| (T)
  double rms_T = 0;      // RMS of Bz_fem - Bz_ref (T)
  double max_rel() const { return max_abs_T / peak_T; }  // relative to peak |Bz_ref|
  double rms_rel() const { return rms_T / peak_T; }
};

// Bz error of the FE solution against ref on every grid point (parallel).
BzErrorStats bz_error_on_grid(const FieldEvaluator& fem, const FieldSource& ref, const GridSpec& grid);

}  // namespace magenc::fem
