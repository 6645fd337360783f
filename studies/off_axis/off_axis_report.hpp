// The off_axis study's outputs (docs/studies/off_axis.md): readers.csv (p50/p99, nominal pp, mean
// spectrum, field window per reader), budget.csv (p99 with each mounting group alone), scan_side.csv and
// scan_gap.csv (p99 against the side-shaft read radius and the bore array's gap), field_map.csv; plots
// error_curves.png, p99_scans.png, spectra.png, field_map.png; summary.md.
#pragma once
#include "off_axis_engine.hpp"
#include "report/study_output.hpp"

namespace magenc {

void write_off_axis_report(const OffAxisResult& r, const OffAxisOptions& o, StudyOutput& out);

}  // namespace magenc
