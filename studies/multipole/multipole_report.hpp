// The multipole study's outputs (docs/multipole.md): interpolation.csv, eccentricity.csv, pole_errors.csv,
// nonius_box.csv (with a nonius), their plots and summary.md.
#pragma once
#include "multipole_engine.hpp"
#include "report/study_output.hpp"

namespace magenc {

void write_multipole_report(StudyOutput& out, const MultipoleStudyResult& r);

}  // namespace magenc
