// The one-offset sweep studies linear_model and exact_field as library calls:
// configuration in, typed result out (the report is report/sweep_reports.hpp's).
//   linear_model  the linear field Bz = k*x: an ideal mount, then each mounting
//                 offset alone swept over 0..sweep.max_mm, cubic fits, each offset
//                 alone at sweep.reference_mm, and the check against the sanity
//                 values of docs/physics.md
//   exact_field   the same sweeps on a configured field source (default: the
//                 exact field of the magnet) for several probe arrays, plus an
//                 air-gap sweep dz with a residual dynamic eccentricity; every
//                 reference case also on the linear field
// The sweep keys the studies share (also real_field and airgap) are declared
// here once.
#pragma once
#include <string>
#include <vector>

#include "analysis/sweep.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "io/tables.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

// study.arrays: comma-separated probe arrays, default "two,diff4,ring:8".
KeySpec study_arrays_key();
// sweep.points, sweep.max_mm, sweep.reference_mm, sweep.offsets, sweep.coefs (in
// that order); reference_use says what the reference offset is used for (help text).
std::vector<KeySpec> offset_sweep_keys(const std::string& reference_use);
// dz_sweep.points, dz_sweep.min_mm, dz_sweep.max_mm (in that order); start_note
// is appended to the help of dz_sweep.min_mm.
std::vector<KeySpec> dz_sweep_keys(const std::string& start_note = "");

// The [sweep] keys, read and checked.
struct OffsetSweepOptions {
  std::vector<std::string> offsets;  // swept one at a time ("sx_mm", ...)
  std::vector<std::string> coefs;    // spectra columns fitted with a cubic
  double reference_mm = 0;           // offset of the reference cases (mm)
  std::vector<double> values_mm;     // 0..sweep.max_mm in sweep.points values (mm)
  // Reads sweep.*; InputError for an unknown offset or coefficient name.
  static OffsetSweepOptions from_config(const Config& cfg);
};

// Sanity values of docs/physics.md ("Linear field model"): r0 = 2.4 mm, array
// `two`, 0.1 mm offsets, quoted to 3 decimals.
struct PhysicsMdValue {
  const char* swept;   // "sx_mm", ...
  const char* coef;    // "a0_deg", ...
  double value_deg;    // as docs/physics.md quotes it
};
const std::vector<PhysicsMdValue>& physics_md_linear_values();

// One computed value beside docs/physics.md's.
struct PhysicsMdComparison {
  std::string swept, coef;
  double computed_deg = 0, quoted_deg = 0;
  bool agrees = false;  // |computed - quoted| <= kPhysicsMdToleranceDeg
};
// docs/physics.md rounds to 3 decimals.
inline constexpr double kPhysicsMdToleranceDeg = 0.0015;

struct LinearModelResult {
  ProbeSetup setup;                       // [sensor] keys, sensor.array
  Mount base;                             // [mount] (mm)
  OffsetSweepOptions options;
  AngleErrorResult ideal;                 // at base
  std::vector<SweepResult> sweeps;        // one per options.offsets entry
  std::vector<FitRow> fits;               // per sweep, per options.coefs entry
  std::vector<AngleErrorResult> refs;     // each offset alone at options.reference_mm
  bool physics_md_applies = false;        // the configuration is docs/physics.md's
  std::vector<PhysicsMdComparison> physics_md;  // when it applies: one per quoted value of a swept offset
  int physics_md_mismatches() const;
};
// The linear_model study: reads [sensor], [mount] and [sweep]; `study` names the fits.
LinearModelResult run_linear_model(const Config& cfg, const std::string& study);

// One mounting case at the reference offset, on one array, study field and linear field.
struct ReferenceCase {
  std::string label;         // "sx = 0.10 mm"
  std::string swept;         // sx_mm, ..., or dz_mm
  Mount mount;
  AngleErrorResult field;    // study field
  AngleErrorResult linear;   // linear model
};

// Everything exact_field computes for one probe array.
struct ArraySweeps {
  ProbeSetup setup;
  AngleErrorResult ideal;               // at the base mount
  std::vector<SweepResult> sweeps;      // one per offset, then the dz sweep
  std::vector<ReferenceCase> refs;      // one per offset, then dz at the reference with the residual dx
};

struct ExactFieldResult {
  std::string field;                    // FieldSource::name() of study.field
  Mount base;                           // [mount] (mm)
  OffsetSweepOptions options;
  std::vector<double> dz_values_mm;     // dz_sweep.min_mm..max_mm
  Mount dz_base;                        // base with dx += dz_sweep.residual_dx_mm
  std::vector<ArraySweeps> arrays;      // one per study.arrays entry
  std::vector<FitRow> fits;             // per array, per sweep, per coefficient
  double floor_deg = 0, relative = 0;   // summary.floor_deg, summary.relative
};
// The exact_field study: reads study.*, [sweep], [dz_sweep], [summary], [sensor], [mount], [magnet].
ExactFieldResult run_exact_field(const Config& cfg, const std::string& study);

}  // namespace magenc
