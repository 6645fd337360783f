// Reports of the FEM-driven probe studies (analysis/fem_field_studies.hpp):
// each writes spectra.csv, comparison.csv, fits.csv (write_comparison_tables),
// its plots and summary.md into the study folder.
//   real_field  eps.png, harmonics.png, coefficients_<offset>.png,
//               differences_<offset>.png; the summary carries the acceptance table
//   airgap      eps.png, coefficients_<case>.png, differences_<case>.png
#pragma once
#include "analysis/study_setup.hpp"
#include "analysis/fem_field_studies.hpp"
#include "core/config.hpp"
#include "report/study_output.hpp"

namespace magenc {

// cfg: the [magnet] and [sensor] values quoted in the summary.
void write_real_field_report(StudyOutput& out, const RealFieldResult& result, const StudySetup& setup);

void write_airgap_report(StudyOutput& out, const AirgapResult& result);

}  // namespace magenc
