// Harmonic provenance: where the spurious harmonics of a sampled field come
// from. The exact field of a perfect cylinder is the ground truth: with it
// every harmonic of an ideal mount is zero, and under an offset the harmonics
// it gives are physical. A field source under test (a grid of the exact field
// at spacing h with an interpolation mode, or an FE solution) is run through
// the same probe pipeline; its harmonics minus the exact ones are artefacts.
#pragma once
#include <string>
#include <vector>

#include "probe/angle_error.hpp"
#include "fields/grid_field.hpp"

namespace magenc {

struct ProvenanceCase {
  std::string label;  // "ideal", "sx=0.1", ...
  Mount mount;
};

struct ProvenanceRow {
  std::string source;      // "grid" or "fem"
  std::string variant;     // e.g. "nearest h=0.05" or the FE directory
  double h_mm = 0;         // grid spacing (0 for fem)
  std::string interp;      // nearest/linear/cubic ("" for fem)
  std::string case_label;
  Spectrum exact, sampled; // exact field and the field under test
};

// Samples `exact` on a square plane grid [-half_width, half_width]^2 at z_s
// (nodes on multiples of h, so node (0,0) is on the axis) for each spacing,
// then runs every case through the pipeline with each mode.
std::vector<ProvenanceRow> grid_sampling_scan(const FieldSource& exact, const ProbeSetup& setup,
                                              const std::vector<ProvenanceCase>& cases,
                                              const std::vector<double>& spacings_mm,
                                              const std::vector<Interp>& modes, double half_width_mm);

// Runs every case with `field` (source "fem", variant = label) beside the exact field.
std::vector<ProvenanceRow> field_scan(const FieldSource& exact, const FieldSource& field, const std::string& source,
                                      const std::string& variant, const ProbeSetup& setup,
                                      const std::vector<ProvenanceCase>& cases);

// Verdict on harmonic n of one case: physical when the exact field gives
// c_n >= floor_deg; the artefact is the largest |c_n(sampled) - c_n(exact)|
// over `rows` of that case from the variants listed.
struct HarmonicVerdict {
  std::string case_label;
  int n = 0;
  double exact_deg = 0;           // c_n of the exact field
  bool physical = false;          // exact_deg >= floor_deg
  double worst_artifact_deg = 0;  // max |c_n(sampled) - c_n(exact)| over the rows
  std::string worst_variant;      // where that maximum occurs
  double best_artifact_deg = 0;   // min over the rows (the most refined, best interpolated)
  std::string best_variant;
};
std::vector<HarmonicVerdict> harmonic_verdicts(const std::vector<ProvenanceRow>& rows, double floor_deg);

}  // namespace magenc
