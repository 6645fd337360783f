// Report of the study fem_convergence (studies/fem_convergence/fem_convergence_engine.hpp): writes
// convergence.csv, convergence.png, faceting.csv and truncation.csv (when those
// runs ran), potential.csv and shaft_potential.csv (when those comparisons ran)
// and summary.md into the study folder.
#pragma once
#include <string>

#include "studies/fem_convergence/fem_convergence_engine.hpp"
#include "report/study_output.hpp"

namespace magenc {

// The CSV tables, one line per solve.
std::string convergence_csv(const FemConvergenceResult& r);
std::string faceting_csv(const std::vector<FacetingRun>& runs);
std::string truncation_csv(const std::vector<TruncationRun>& runs);
std::string potential_csv(const PotentialComparison& pc);

void write_fem_convergence_report(StudyOutput& out, const FemConvergenceResult& r);

}  // namespace magenc
