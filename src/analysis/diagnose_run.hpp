// What the diagnose executable and the Python module's diagnose() do between reading their arguments and
// writing their outputs (docs/interfaces.md "Measured error curves and diagnose"): read and check the
// measured curves and the per-curve known values, open the field source, choose the Jacobian's step and the
// field that decides the default free set, and fit (analysis/diagnosis_fit.hpp). One function, so that both
// give the same answer for the same arguments.
#pragma once
#include <string>
#include <vector>

#include "analysis/diagnosis_fit.hpp"
#include "core/config.hpp"

namespace magenc {

struct DiagnoseRequest {
  std::vector<std::string> measured;     // curve CSV paths (one joint fit)
  std::string field = "analytic";        // field source spec (fields/field_factory, fem:DIR)
  std::string interp = "cubic";          // grid interpolation of grid:/table: sources
  std::vector<std::string> free;         // parameter names to fit (empty: what the curves identify)
  std::vector<std::string> curve_sets;   // per-curve known values "N:key=value" | "N:key+=value"
  bool fixed_zero = false;               // no free zero offset per curve
  int error_sign = 1;                    // +1: error_deg = sensor - reference; -1: the opposite
  double max_gap_deg = 30.0;             // largest allowed gap between samples, (0, 180] deg
  int starts = 6;                        // start points of the fit
  unsigned seed = 1;                     // seed of the random starts
  double cond_limit = 1e4;               // condition number above which directions are not identifiable
  double fd_step = 0;                    // central-difference step in typical sizes (0: by field)
  // The names the caller's user knows the options by, for one-line errors.
  std::string array_name = "sensor.array";
  std::string max_gap_name = "--max-gap";
};

struct DiagnoseRun {
  std::vector<CurveInput> curves;
  DiagnosisOptions options;  // as fitted (identifiability_field cleared: it lived only during the fit)
  DiagnosisResult result;
};

// Everything is read and checked before the fit: InputError (one line naming the option) for a bad curve,
// a bad --curve-set, an unknown free name, a gap limit out of range or a field that cannot be opened.
// ComputeError (one line) when no start converged or the fit does not explain the curves
// (DiagnosisResult::unexplained). A best start stopped at its iteration cap is a result with
// converged = false (fit.json "converged": false; the executable says so on stderr).
DiagnoseRun run_diagnose(const DiagnoseRequest& req, const Config& cfg);

}  // namespace magenc
