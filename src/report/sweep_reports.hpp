// Reports of the one-offset sweep studies (analysis/offset_sweeps.hpp): each
// writes the study's tables, plots and summary.md into the study folder.
//   linear_model  spectra.csv (column `sweep`), fits.csv, eps.png, harmonics.png,
//                 coefficients.png, summary.md (with the docs/physics.md check)
//   exact_field   spectra.csv, fits.csv, eps.png, harmonics.png,
//                 coefficients_<offset>.png, summary.md
#pragma once
#include "analysis/study_setup.hpp"
#include "analysis/offset_sweeps.hpp"
#include "core/config.hpp"
#include "report/study_output.hpp"

namespace magenc {

void write_linear_model_report(StudyOutput& out, const LinearModelResult& result);

// cfg: the [magnet] and [sensor] values quoted in the summary.
void write_exact_field_report(StudyOutput& out, const ExactFieldResult& result, const StudySetup& setup);

}  // namespace magenc
