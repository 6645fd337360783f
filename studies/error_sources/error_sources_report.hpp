// Outputs of the error_sources study (studies/error_sources/error_sources_engine.hpp): tables,
// per-source coefficient plots, the harmonic heat map and summary.md.
//   spectra.csv            every sweep row (extra columns sweep, swept, value)
//   fits.csv               cubic fits, `swept` = the source (tilt_x_deg, ...)
//   harmonics.csv          which source makes which harmonic, per array: |a0|,
//                          c1..c8 and pp at each source's largest swept value
//   harmonics_heatmap.png  the same matrix as a heat map (log colour scale)
//   coefficients_<swept>.png, summary.md
#pragma once
#include <string>
#include <vector>

#include "analysis/study_setup.hpp"
#include "studies/error_sources/error_sources_engine.hpp"
#include "core/config.hpp"
#include "report/study_output.hpp"

namespace magenc {

// Reference values of docs/physics.md ("Beyond the five offsets"): exact field,
// default magnet, r0 = 2.4 mm, `two` array, the source alone at `value`.
struct SourceReference {
  std::string swept;   // source
  double value;        // its value (source unit)
  std::string coef;    // spectra column, e.g. "c2_deg"
  double expected_deg; // docs/physics.md's number
};
const std::vector<SourceReference>& physics_md_source_references();

// harmonics.csv: source,array,value,unit,c0_deg (= |a0|),c1_deg..c8_deg,pp_deg,dominant
std::string harmonics_csv(const ErrorSourcesRun& run, double floor_deg, double rel);

// "|a0| 0.806, c2 1.512" : the harmonics n >= 0 (|a0| for n = 0) with value
// >= max(floor_deg, rel * largest), largest first, at most max_count; "none" otherwise.
std::string signature_text(const HarmonicSignature& h, double floor_deg, double rel, int max_count = 3);

// Writes every output file of the study into out.
void write_error_sources_report(const ErrorSourcesRun& run, const StudySetup& setup, StudyOutput& out);

}  // namespace magenc
