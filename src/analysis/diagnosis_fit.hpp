// diagnose: from measured angle-error curves back to their causes (docs/interfaces.md, "Measured error curves
// and diagnose"). Fits chosen parameters of the forward model (mounting offsets, tilts, signal-chain
// errors; the probe pipeline angle_error_at() on any field source) plus a free zero offset between the two
// encoders per curve, by nonlinear least squares (Ceres, Levenberg-Marquardt, bounds), from several starts
// (the problem has mirror-image minima). Residuals are wrapped angle differences
//   r_i = wrap(eps_model(theta_i; p) + zero_c - eps_measured_i)   [deg].
// The Jacobian is taken by central differences (the forward model is a black box) in scaled parameters
// u = p / scale (scale = the parameter's typical magnitude), step 1e-4 in u.
// Uncertainty: sigma^2 = RSS/(N - p) * (J^T J)^-1 at the optimum (physical units), through the SVD of the
// column-normalised Jacobian; directions whose singular value is below 1/cond_limit of the largest cannot
// be separated by the data: they are reported (parameters, shared harmonics), and their sigma is infinite.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "analysis/measured_curve.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

// What a fit parameter writes into: the mount and the probe setup (signal chain) of one curve.
struct ModelState {
  Mount mount;
  ProbeSetup setup;
};

// One row of the parameter table: adding a model parameter to the fitter is one line in
// fit_parameters() (diagnosis_fit.cpp).
struct FitParameter {
  std::string name;       // short name for --free: "sx", "tilt_x", "offset_cos", "gain", ...
  std::string key;        // configuration key: "mount.sx_mm", "sensor.gain_mismatch"
  std::string json_name;  // name in fit.json (the key's leaf): "sx_mm", "gain_mismatch"
  std::string unit;       // "mm", "deg", "mT", "" (dimensionless)
  double lower, upper;    // bounds of the fit
  double scale;           // typical magnitude: scaling, random starts, finite-difference step
  std::function<void(ModelState&, double)> set;
  std::function<double(const ModelState&)> get;
  std::string what;       // plain words for reports
};

// The model parameters diagnose can fit, in order of preference for the default free set.
const std::vector<FitParameter>& fit_parameters();
// By short name ("sx") or json name ("sx_mm") or key ("mount.sx_mm"); InputError listing the names.
const FitParameter& fit_parameter(const std::string& name);
int fit_parameter_index(const std::string& name);
// --free names with aliases expanded: "magnet_tilt" -> magnet_tilt_x, magnet_tilt_y.
std::vector<std::string> expand_free_names(const std::vector<std::string>& names);

// A known per-curve change: key = value (absolute, that parameter is then known for this curve) or
// key += value (a known shift added to the shared fitted value, e.g. a rig move).
struct CurveOverride {
  int param = -1;      // index in fit_parameters()
  double value = 0;
  bool add = false;    // true: +=, false: =
};
// Parses "N:key=value" or "N:key+=value" (N 1-based curve number <= curves); InputError otherwise.
std::pair<int, CurveOverride> parse_curve_set(const std::string& text, int curves);

// One measured curve with its own probe setup and overrides.
struct CurveInput {
  MeasuredCurve curve;
  ModelState base;                       // the configured mount and setup (fixed parameters' values)
  std::vector<CurveOverride> overrides;  // applied after the shared parameters
};

struct DiagnosisOptions {
  std::vector<std::string> free;  // short names; empty: default_free_set()
  bool free_zero = true;          // a free zero offset (DC) per curve
  int starts = 6;                 // start points (1: the configured values only)
  unsigned seed = 1;              // random starts
  double cond_limit = 1e4;        // condition number of the column-normalised Jacobian
  double min_effect_deg = 1e-3;   // default free set: RMS change of the curve per typical size, at least
  double nominal_noise_deg = 0.0127;  // default free set: noise per sample (the AM8192B's quantization,
                                      // 360/8192/sqrt(12) deg, alone)
  double max_sigma_rel = 0.25;    // default free set: predicted sigma at that noise, in typical sizes, at most
  double nominal_shift = 0.5;     // default free set: evaluated at the configured values + this many typical
                                  // sizes on every parameter (an exactly ideal mount hides second-order effects)
  int max_iterations = 100;
  double fd_step = 1e-4;          // central-difference step in typical sizes: 1e-4 suits the exact field
                                  // (smooth, ~1e-12 accurate); piecewise FE/grid fields need ~1e-2, or the
                                  // derivative sees element-to-element kinks (diagnose sets it by field)
  // Field on which the default free set is chosen (null: the fitted field). diagnose passes the exact field of
  // the configured magnet when fitting on an FE or grid field, so that discretisation artefacts do not make
  // physically confounded parameters look separable.
  const FieldSource* identifiability_field = nullptr;
};

// A fitted or fixed value.
struct ParamValue {
  std::string name, json_name, unit;
  double value = 0;
  double sigma = 0;       // 1 sigma; infinity when not identifiable; 0 for fixed
  bool free = false;
};

// Parameters (and directions) the data cannot separate.
struct Confounding {
  std::vector<std::string> names;   // json names of the parameters in the direction
  std::vector<double> weights;      // their components in the singular vector (column-normalised)
  double rel_singular = 0;          // singular value / largest
  std::string harmonics;            // "DC and the 2nd harmonic"
  std::string text;                 // plain words
};

// Per-curve result.
struct CurveFit {
  Eigen::VectorXd fitted_deg;    // model + zero offset at the measured angles
  Eigen::VectorXd residual_deg;  // wrap(fitted - measured)
  double residual_rms_deg = 0;
  Eigen::VectorXd measured_h, fitted_h, residual_h;  // harmonics_ls (a0, a1, b1, ..., a8, b8)
};

// Another minimum as good as the best one (cost within 1 %) but far from it: the data cannot choose.
struct AlternativeMinimum {
  double cost = 0;             // 0.5 * RSS
  std::vector<double> values;  // free variables in the order of DiagnosisResult::free
};

struct DiagnosisResult {
  std::vector<ParamValue> params;     // every table parameter (free or fixed), then the zero offsets
  std::vector<std::string> free;      // json names of the free parameters (fit order)
  Eigen::MatrixXd correlation;        // free x free (NaN where sigma is infinite)
  Eigen::VectorXd singular_values;    // column-normalised Jacobian, descending
  double condition = 0;               // s_max / s_min
  std::vector<Confounding> confounded;
  std::vector<std::string> not_identifiable;  // json names
  std::vector<CurveFit> curves;
  double residual_rms_deg = 0;        // over all curves
  double rss_deg2 = 0;
  int n_points = 0, n_free = 0;
  std::vector<AlternativeMinimum> alternatives;  // equally good minima elsewhere (e.g. mirror images)
  std::vector<double> start_costs;    // final 0.5*RSS of each start (the last: the mirror of the best)
  bool starts_thinned = false;        // start costs are on curves thinned to <= 360 samples
  int best_start = 0;
  int iterations = 0;                 // of the best start
  std::string default_free_note;      // how the default free set was chosen (empty when --free was given)
  // Whether the fit is an answer (fit_judgement). converged: the best start's optimizer met its tolerances
  // (false: it stopped at DiagnosisOptions::max_iterations; termination: the optimizer's words).
  bool converged = true;
  std::string termination;
  // The share of the curves' variation (about each curve's mean with a free zero offset) the fit explains,
  // 1 - RSS / RSS of the curves, and the share of the residual's power in harmonics 1..8 of theta.
  double explained_fraction = 1, residual_harmonic_share = 0;
  // Non-empty when the fit explains less than half of the curves' RMS (explained_fraction < 0.75) and its
  // residual is mostly harmonics 1..8 (share > 0.5): a structured error the model cannot make (wrong array,
  // r0, field or error sign), not noise; then the values are no diagnosis.
  std::string unexplained;
  double fit_seconds = 0;
};

// Column loading text: the harmonics (DC, 1st, ...) holding >= 10 % of the largest amplitude of v(theta).
std::string harmonic_loading(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& v);

// The default free set: greedy in table order at a nominal point (the configured values + nominal_shift
// typical sizes on every parameter), keeping a parameter only if it moves the curve by at least
// min_effect_deg RMS per typical size, the column-normalised Jacobian (with the free zero offsets) stays
// below cond_limit, and no kept parameter's predicted sigma at nominal_noise_deg exceeds max_sigma_rel typical
// sizes. note explains each parameter left out (partners: the kept columns that combine into its column).
std::vector<std::string> default_free_set(const FieldSource& field, const std::vector<CurveInput>& curves,
                                          const DiagnosisOptions& opts, std::string* note = nullptr);

// The joint fit of all curves (shared parameters, one zero offset per curve).
DiagnosisResult diagnose_curves(const FieldSource& field, const std::vector<CurveInput>& curves,
                                const DiagnosisOptions& opts);

// Model error curve of one curve input for given full parameter values (table order).
Eigen::VectorXd model_curve_deg(const FieldSource& field, const CurveInput& c, const std::vector<double>& values);

}  // namespace magenc
