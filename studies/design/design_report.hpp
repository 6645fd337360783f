// Outputs of the design study (studies/design/design.cpp; docs/studies/design.md): design.csv (one row per
// design), design_pareto.csv, design_budget.csv, summary.md and the plots design_pareto.png (p99 against
// magnet volume per sensor, Pareto fronts drawn) and design_map.png (p99 over magnet radius x gap for the
// best sensor, the smallest p99 over the other variables in each cell).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "studies/design/design_study.hpp"

namespace magenc {

std::string design_csv(const DesignOptions& o, const DesignStudyResult& r);
std::string design_pareto_csv(const DesignOptions& o, const DesignStudyResult& r);
std::string design_budget_csv(const DesignOptions& o, const DesignStudyResult& r);
// The one-line verdict: "recommended: ..." or "no design meets the requirements (...)".
std::string design_verdict(const DesignOptions& o, const DesignStudyResult& r);
// ranks: MPI ranks the designs were split over; wall_s: the evaluation's wall time.
std::string design_summary_md(const DesignOptions& o, const DesignStudyResult& r, int ranks, double wall_s);
void write_design_plots(const DesignOptions& o, const DesignStudyResult& r, const std::filesystem::path& dir);

}  // namespace magenc
