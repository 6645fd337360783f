// Outputs of the sensor_principles study (analysis/sensor_principles.hpp):
// spectra.csv (the spectra table, extra columns sensor, principle, case, tilts,
// field_min_mT, field_max_mT, in_window), principles.csv (one row per sensor:
// Monte Carlo statistics over the box, out-of-window count, field extremes and
// window margins), pp_heatmap.png (pp of each error alone per sensor),
// box_p99.png (p99 of pp over the box and the field over the box against each
// window), summary.md (which principle tolerates which error, and why, in numbers).
#pragma once
#include <string>

#include "analysis/study_setup.hpp"
#include "analysis/sensor_principles.hpp"
#include "core/config.hpp"
#include "report/study_output.hpp"

namespace magenc {

std::string principles_csv(const SensorPrinciplesResult& r);
void write_sensor_principles_report(const SensorPrinciplesResult& r, const SensorPrinciplesOptions& opt,
                                    const StudySetup& setup, StudyOutput& out);

}  // namespace magenc
