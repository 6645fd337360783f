// The calibration study's outputs (studies/calibration/calibration.cpp; docs/studies/calibration.md): residual.csv
// (p50/p99 per sensor, method and scenario beside the uncalibrated ones), budget (each drift key alone),
// p99_vs_drift.png (p99 of the residual against the drift box's scale, one panel per method),
// residual_spectra.png (mean c_n of the residual per method at the drift box), summary.md.
#pragma once
#include "analysis/study_setup.hpp"
#include "studies/calibration/calibration_study.hpp"
#include "report/study_output.hpp"

namespace magenc {

void write_calibration_report(const CalibrationStudyResult& r, const CalibrationStudyOptions& opt, const StudySetup& setup,
                              StudyOutput& out);

}  // namespace magenc
