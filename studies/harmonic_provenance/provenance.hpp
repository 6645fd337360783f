// Harmonic provenance: where the spurious harmonics of a sampled field come
// from. The exact field of a perfect cylinder is the ground truth: with it
// every harmonic of an ideal mount is zero, and under an offset the harmonics
// it gives are physical. A field source under test (a grid of the exact field
// at spacing h with an interpolation mode, or an FE solution) is run through
// the same probe pipeline; its harmonics minus the exact ones are artefacts.
//
// The study harmonic_provenance as library calls: ProvenanceOptions from the
// configuration, run_grid_provenance (the exact field through plane grids),
// then add_fe_solution once per FE solution (solved in the study with
// field_solver/field_io/fem_variant.hpp or read from a solve_field directory). The
// report is studies/harmonic_provenance/provenance_report.hpp's.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "field_solver/field_io/solve_facts.hpp"
#include "fields/analytic_field.hpp"
#include "fields/grid_field.hpp"
#include "probe/angle_error.hpp"

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

// The [provenance] keys (provenance.fem_variants: see field_solver/field_io/fem_variant.hpp).
inline constexpr const char* kFemVariantsKey = "provenance.fem_variants";
std::vector<KeySpec> provenance_keys();


// The study's options, read and checked (solve_field directories included)
// before anything is computed.
struct ProvenanceOptions {
  ProbeSetup setup;                      // [sensor] keys, sensor.array
  std::vector<ProvenanceCase> cases;     // ideal, sx and dx of offset_mm
  std::vector<double> spacings_mm;       // grid spacings h, coarse to fine
  std::string spacings_text;             // provenance.spacings_mm as configured (for the summary)
  std::vector<Interp> modes;             // interpolation modes of the exact-field grids
  std::string interps_text;              // provenance.interps as configured
  double half_width_mm = 0;              // plane grids span [-w, w] in x and y
  double offset_mm = 0;                  // size of the sx and dx cases
  double floor_deg = 0;                  // exact c_n at or above this is physical
  std::vector<std::string> fem_dirs;     // solve_field output directories (the caller checks them: SolvedFieldDir)
  std::string grid_interp;               // provenance.fem_grid_interp: "none" or an interpolation mode
  bool via_grid() const { return grid_interp != "none"; }
  static ProvenanceOptions from_config(const Config& cfg);
};

// An FE solution of the study: solved in-process (a variant) or read from a solve_field directory.
struct FeSolution {
  std::string label;   // variant label or directory
  std::string origin;  // "solved here" or the directory
  FeSolveFacts facts;
};

struct ProvenanceRun {
  ProvenanceOptions options;
  std::shared_ptr<const AnalyticField> exact;  // exact field of the [magnet] keys
  std::vector<Spectrum> exact_spectra;         // per case, on the exact field
  std::vector<ProvenanceRow> rows;             // grid rows first (n_grid_rows), then per FE solution
  std::size_t n_grid_rows = 0;
  std::vector<FeSolution> fe;                  // in the order added
  // The row of (source, variant, case); ComputeError when there is none.
  const ProvenanceRow& row(const std::string& source, const std::string& variant, const std::string& case_label) const;
};

// The exact field of cfg's [magnet] keys sampled on plane grids per options
// (grid_sampling_scan), with the exact spectra of every case.
ProvenanceRun run_grid_provenance(const Config& cfg, const ProvenanceOptions& options);

// Adds the rows of one FE solution: evaluated directly (source "fem") and,
// when plane is given, through that plane grid with options.grid_interp
// (source "fem_grid", variant "<label> via plane grid").
void add_fe_solution(ProvenanceRun& run, const FeSolution& solution, const FieldSource& field, const GridData* plane);

}  // namespace magenc
