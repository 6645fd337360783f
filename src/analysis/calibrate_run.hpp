// What the calibrate executable and the Python module's calibrate() do between reading their arguments and
// writing their outputs (docs/interfaces.md "calibrate"): the factory correction from a measured curve, a
// correction table written before, or the simulated calibration state calibration.at; then, on request,
// the residual of another measured curve or of the configured run state after that correction.
#pragma once
#include <functional>
#include <string>

#include <Eigen/Core>

#include "analysis/calibration.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

struct CalibrateRequest {
  std::string measured;    // calibration curve CSV (the formats diagnose reads; ogp needs theta_deg,u_cos,u_sin), or ""
  std::string correction;  // a correction.csv written before, or ""
  std::string apply;       // a curve CSV to correct, "run" (the configured mount), or "" (no residual)
  int error_sign = 1;      // +1: error_deg = sensor - reference; -1: the opposite
};

// The field of the simulated states, opened on first use (a measured curve or a correction file needs none).
using FieldGetter = std::function<const FieldSource&()>;

// The correction and where it came from (the correction file's or the curve's path, or
// "simulated calibration.at"). cfg: calibration.method, sensor.*; what: the name that chose the array
// in error messages (--array or sensor.array). InputError: both measured and correction, method none
// without a correction file, ogp without raw channels.
struct CalibrationSource {
  Correction correction;
  std::string source;
};
CalibrationSource calibrate_correction(const CalibrateRequest& req, const Config& cfg, const std::string& what,
                                       const FieldGetter& field);

// A curve after the correction: the samples, the error before and after (deg).
struct CalibrationResidual {
  std::string curve;   // req.apply
  std::string method;  // the correction's method name
  Eigen::VectorXd theta_deg, error_deg, residual_deg;
  std::string csv() const;   // theta_deg,error_deg,residual_deg
  std::string json() const;  // pp before and after, mean after, c_1..c_8 of the residual (least squares)
};
CalibrationResidual calibrate_residual(const CalibrateRequest& req, const Correction& corr, const Config& cfg,
                                       const ProbeSetup& setup, const FieldGetter& field);

}  // namespace magenc
