// Outputs of the temperature study (studies/temperature/temperature_sweep.hpp): temperature.csv (one row per
// sensor, mount and temperature: Br(T)/Br, pp, a0, c1..c4, field extremes, window margins),
// pp_vs_temperature.png, field_vs_temperature.png, summary.md.
#pragma once
#include "analysis/study_setup.hpp"
#include "studies/temperature/temperature_sweep.hpp"
#include "core/config.hpp"
#include "report/study_output.hpp"

namespace magenc {

std::string temperature_csv(const TemperatureResult& r);
void write_temperature_report(const TemperatureResult& r, const TemperatureOptions& opt, const StudySetup& setup,
                              StudyOutput& out);

}  // namespace magenc
