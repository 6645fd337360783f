// Outputs of the study steel_parts (studies/steel_parts/steel_parts_result.hpp): steel_parts.csv
// (one row per solve, array and mounting case), solves.csv (one row per solve:
// iterations, residuals, the part's largest |B|), profile.png (Bz along x on the
// sensing plane with the field window), harmonics.png (c1..c4 per solve under
// sx and dx), summary.md.
#pragma once
#include <string>

#include "studies/steel_parts/steel_parts_result.hpp"
#include "report/study_output.hpp"

namespace magenc {

std::string steel_parts_cases_csv(const SteelPartsResult& r);
std::string steel_parts_solves_csv(const SteelPartsResult& r);
void write_steel_parts_report(StudyOutput& out, const SteelPartsResult& r);

}  // namespace magenc
