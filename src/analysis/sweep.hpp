// One-offset sweeps: a base mounting case with one offset (sx, sy, dx, dy, dz
// or the probe radius r0) swept over a list of values, each value run through
// the probe-path pipeline (angle_error.hpp), giving one spectra-table row per
// value; then cubic fits (fit.hpp) of chosen spectrum coefficients against the
// swept value. Studies describe sweeps with SweepSpec and only call these.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "probe/angle_error.hpp"
#include "fields/field_source.hpp"
#include "probe/mounting.hpp"
#include "io/tables.hpp"

namespace magenc {

// The swept variables, as the fits table names them (docs/interfaces.md).
// Throws InputError naming `what` for any other name.
void check_swept_name(const std::string& swept, const std::string& what = "swept");

// Words for a swept variable: "sx_mm" -> "static eccentricity sx",
// "dx_mm" -> "dynamic eccentricity dx", "dz_mm" -> "air-gap offset dz",
// "r0_mm" -> "probe radius r0".
std::string offset_description(const std::string& swept);
// Its symbol: "sx_mm" -> "sx".
std::string offset_symbol(const std::string& swept);

// `base` with the offset named by swept ("sx_mm", "sy_mm", "dx_mm", "dy_mm",
// "dz_mm") set to value_mm. ("r0_mm" is not a mount offset: InputError.)
Mount with_offset(Mount base, const std::string& swept, double value_mm);

// n values from a to b inclusive (n >= 2), a + (b - a)*i/(n - 1), so that
// values on the grid (e.g. 0.1 of 0..0.5 in 26 points) come out exact.
std::vector<double> linspace(double a, double b, int n);

// Checks that each name is a spectra-table coefficient column (a0_deg, ...,
// c8_deg, pp_deg); InputError naming `what` and the allowed names otherwise.
void check_coef_names(const std::vector<std::string>& coefs, const std::string& what);

// ProbeSetup from [sensor] keys and the magnet height (z_s = L/2 + h); the
// array from array_spec ("two", "diff4", "ring:N", "point"; `what` names it in
// errors): sensor_setup_from_config() of probe/angle_error.hpp.
ProbeSetup probe_setup_from_config(const Config& cfg, const std::string& array_spec,
                                   const std::string& what = "sensor.array");

struct SweepSpec {
  std::string label;               // short case name for tables/plots, e.g. "dx", "dz (dx=0.05)"
  std::string swept;               // "sx_mm", "sy_mm", "dx_mm", "dy_mm", "dz_mm" or "r0_mm"
  std::vector<double> values_mm;   // swept values (mm), in plotting order
  Mount base;                      // the other offsets (the swept one is overwritten)
};

struct SweepResult {
  SweepSpec spec;
  std::string field;               // field source name ("linear", "analytic", ...)
  ProbeSetup setup;                // array, r0 (base value when r0 is swept), plane, steps
  std::vector<SpectrumRow> rows;   // one per swept value; extra column "sweep" = spec.label

  // The swept values and one spectra column (e.g. "c3_deg") over the sweep.
  std::vector<double> x_mm() const { return spec.values_mm; }
  std::vector<double> column(const std::string& coef) const;
};

// Runs the sweep. Each row carries extra column ("sweep", spec.label).
SweepResult run_sweep(const FieldSource& field, const ProbeSetup& setup, const SweepSpec& spec);

// Cubic fits of each coefficient column over the sweep; each FitRow has
// study, swept, coef, p and extra columns field, array, r0_mm, sweep (label).
std::vector<FitRow> fit_sweep(const SweepResult& sweep, const std::string& study,
                              const std::vector<std::string>& coefs);

// p3*x^3 + p2*x^2 + p1*x + p0 for p = {p3, p2, p1, p0}.
double eval_cubic(const std::array<double, 4>& p, double x);

// The fit of `coef` in fits (matching swept and sweep label), or nullptr.
const FitRow* find_fit(const std::vector<FitRow>& fits, const SweepResult& sweep,
                       const std::string& coef);

}  // namespace magenc
