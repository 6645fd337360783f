// The calibration study's computation (studies/calibration/calibration.cpp stays thin; docs/studies/calibration.md):
// a seeded Monte Carlo over the tolerance box for the factory (calibration) state; per sample a drift drawn
// from the drift box (a list of configuration keys with half-widths, added to the factory state's values:
// a re-mount within a smaller tolerance now, temperature and stray fields as further lines once those keys
// exist); for each sensor and method the p50/p99 of the residual pp at the drifted state beside the
// uncalibrated p99 there; the budget (each drift key alone); the p99 against the drift size (the whole
// drift box scaled); the mean residual spectrum per method.
// Reproducibility: factory sample i is ToleranceBox::case_sample(seed, i); drift j of sample i is a pure
// function of (seed, i, j) (SplitMix64), so results do not depend on the thread count; every sensor, method
// and scenario sees the same samples and draws (common random numbers).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "analysis/calibration.hpp"
#include "analysis/tolerance.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"

namespace magenc {

struct DriftKey {
  std::string key;          // a declared Real configuration key (mount.sx_mm, ...)
  double half_width = 0;    // the drift is uniform in +-half_width (the key's unit)
};

struct CalibrationStudyOptions {
  std::vector<std::string> sensors = {"two", "diff4", "inplane", "xmr"};
  std::vector<std::string> methods = {"harmonics:8", "lut:32", "ogp"};
  ToleranceBox box;                 // factory tolerance box
  long samples = 1000;
  std::uint64_t seed = 1;
  int mc_steps = 360;
  std::vector<DriftKey> drift;      // the drift box
  std::vector<double> scales = {0.25, 0.5, 1, 2};  // drift box scale factors of the p99-vs-size scan

  static std::vector<KeySpec> keys();  // [study], [tol], [drift]
  // InputError naming the key: unknown sensor or method, a drift key that is not a declared real key or is
  // a calibration.* or magnet.* key, a key given twice.
  static CalibrationStudyOptions from_config(const Config& cfg);
};

struct CalibrationSensorResult {
  std::string label;
  std::vector<std::string> scenarios;  // "factory" (no drift), "drift x<scale>" per scale, "<key> alone"
  Eigen::VectorXd uncal_p50, uncal_p99;  // per scenario: pp of the uncalibrated error (deg)
  Eigen::MatrixXd p50, p99;              // scenario x method: pp of the residual (deg)
  Eigen::MatrixXd mean_c;                // method x 8: mean c_n of the residual at drift scale 1 (deg)
  Eigen::VectorXd uncal_mean_c;          // 8: mean c_n of the uncalibrated error at drift scale 1
  std::size_t scale1 = 0;                // index of the scenario "drift x1" (the headline)
};

struct CalibrationStudyResult {
  std::string field;
  std::vector<CalibrationMethod> methods;
  std::vector<CalibrationSensorResult> sensors;
  double wall_s = 0;
};

// Runs the study on `field` with the run configuration `cfg` (magnet, sensor keys; mount keys are replaced
// by each factory sample).
CalibrationStudyResult run_calibration_study(const FieldSource& field, const Config& cfg,
                                             const CalibrationStudyOptions& opt);

}  // namespace magenc
