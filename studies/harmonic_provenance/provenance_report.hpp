// Report of the study harmonic_provenance (studies/harmonic_provenance/provenance.hpp): writes
// provenance.csv (spectra table + columns source, variant, h_mm, interp, case),
// artefacts_vs_h.png, ideal_harmonics.png, fem_artefacts.png (when FE
// solutions ran) and summary.md into the study folder.
#pragma once
#include "studies/harmonic_provenance/provenance.hpp"
#include "report/study_output.hpp"

namespace magenc {

void write_provenance_report(StudyOutput& out, const ProvenanceRun& run);

}  // namespace magenc
