// Study calibration: what is left of the factory correction (harmonics:N, lut:K, ogp; docs/physics.md
// "Calibration") after the encoder drifts from the state it was calibrated in: a Monte Carlo over the
// tolerance box for the factory state, one drift draw from the drift box per sample, the residual's p50/p99
// per sensor and method beside the uncalibrated p99, the budget of each drift key alone, the p99 against the
// drift size and the mean residual spectra. Computation in studies/calibration/calibration_study.*, outputs in
// studies/calibration/calibration_report.*.
//   calibration [--config studies/calibration/calibration.toml] [--set study.samples=10000] [--out DIR]
#include "studies/calibration/calibration_study.hpp"
#include "fields/field_factory.hpp"
#include "studies/calibration/calibration_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

const char* kStudy = "calibration";

void run(const Config& cfg, StudyOutput& out) {
  const CalibrationStudyOptions opt = CalibrationStudyOptions::from_config(cfg);
  const FieldSourcePtr field = make_field_source(cfg.str("study.field"), cfg);
  const CalibrationStudyResult result = run_calibration_study(*field, cfg, opt);
  write_calibration_report(result, opt, StudySetup::from_config(cfg), out);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy, "calibration: the residual of harmonics, lut and ogp corrections after a drift",
                   CalibrationStudyOptions::keys(), argc, argv, run);
}
