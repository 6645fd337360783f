// The diagnosis study's outputs (coverage of the round trip, the original study's anomalies).
#pragma once
#include "report/study_output.hpp"
#include "studies/diagnosis/diagnosis_study.hpp"

namespace magenc {

// The diagnosis study's outputs (studies/diagnosis/diagnosis.cpp) into its folder: coverage.csv, anomalies.csv,
// example_fit.png, example_harmonics.png (the example fit), summary.md.
void write_diagnosis_study_report(StudyOutput& out, const DiagnosisStudyResult& res);

}  // namespace magenc
