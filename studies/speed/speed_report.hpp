// The speed study's outputs (docs/studies/speed.md): speed_vs_rpm.csv, commutation.csv, attenuation.csv,
// calibration_vs_rpm.csv, the plots speed_error.png, commutation.png, attenuation.png, calibration.png and
// summary.md.
#pragma once
#include "report/study_output.hpp"
#include "speed_engine.hpp"

namespace magenc {

void write_speed_report(StudyOutput& out, const SpeedStudyResult& r);

}  // namespace magenc
