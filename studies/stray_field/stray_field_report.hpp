// Outputs of the stray_field study (studies/stray_field/stray_field_engine.hpp): levels.csv (worst pp and c1 over the
// directions at each test level, worst direction), curve.csv (the same vs magnitude), tolerated.csv
// (uniform field tolerated per threshold), wires.csv (conductor cases), error_vs_field.png (worst pp vs
// |B| per sensor), wires.png (pp vs current per distance and orientation), direction_map_<sensor>.png
// (pp over the sphere of directions at one magnitude), summary.md.
#pragma once
#include "analysis/study_setup.hpp"
#include "studies/stray_field/stray_field_engine.hpp"
#include "core/config.hpp"
#include "report/study_output.hpp"

namespace magenc {

std::string stray_levels_csv(const StrayFieldResult& r, const StrayFieldOptions& opt);
std::string stray_tolerated_csv(const StrayFieldResult& r);
void write_stray_field_report(const StrayFieldResult& r, const StrayFieldOptions& opt, const StudySetup& setup,
                              StudyOutput& out);

}  // namespace magenc
