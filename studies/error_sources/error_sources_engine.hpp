// Error sources beyond the five offsets (docs/physics.md, "Beyond the five
// offsets"): sensor tilt, magnet tilt, magnetization elevation and the signal
// chain (channel offsets, gain mismatch, phase error). Each source is one
// configuration key; a source sweep sets that key alone to each of a list of
// values (every other key as configured, normally an ideal mount), runs the
// probe pipeline and gives one spectra-table row per value, in the SweepResult
// of sweep.hpp, so fit_sweep, find_fit and coefficient_figure serve it as they
// serve the offset sweeps. The fits table names the source in its `swept`
// column (tilt_x_deg, magnet_tilt_deg, ..., gain_mismatch).
//
// A source of the magnet ([magnet] keys: magnetization elevation) changes the
// field itself: its sweep rebuilds the field from the field spec for every
// value, which only a field computed from the configured magnet can follow
// (`analytic`); other field sources are refused for it.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "analysis/sweep.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

struct ErrorSource {
  std::string swept;        // name in the fits table and in study.sources: "tilt_x_deg"
  std::string key;          // configuration key: "mount.tilt_x_deg"
  std::string symbol;       // short symbol for plots and tables (enhanced text): "tilt_x"
  std::string description;  // words: "sensor tilt about x"
  std::string unit;         // unit of the values: "deg", "mT", "" (a fraction)
  bool changes_field;       // true: the field is rebuilt per value (a [magnet] key)
  std::string range_key;    // study key of the sweep's upper end: "sweep.tilt_max_deg"
};

// The known sources, in the order of docs/physics.md.
const std::vector<ErrorSource>& error_sources();
// The source named `swept`; InputError naming `what` and the allowed names otherwise.
const ErrorSource& find_error_source(const std::string& swept, const std::string& what = "study.sources");

// Study keys of the source sweeps: sweep.points and each source's range_key
// (defaults: tilts 2 deg, elevation 5 deg, offsets 1 mT, gain 0.02, phase 2 deg).
std::vector<KeySpec> error_source_sweep_keys();

// "x [deg]" for axis labels ("gain_mismatch [1]" for fractions).
std::string source_axis_label(const ErrorSource& src);

// Sweeps src alone over values on one array. cfg supplies everything else
// (magnet, sensor, mount: usually all zero); base_setup the array, r0, plane
// and steps; field_spec and field the field (field is used as is unless
// src.changes_field, then make_field_source(field_spec, cfg with the value)
// is called per value and field_spec must be "analytic"). Each row carries the
// extra columns sweep (= src.symbol), swept (= src.swept) and value. The
// result's spec.values_mm holds the values in src.unit (not mm), spec.swept =
// src.swept.
SweepResult run_source_sweep(const Config& cfg, const std::string& field_spec, const FieldSource& field,
                             const ProbeSetup& base_setup, const ErrorSource& src, const std::vector<double>& values);

// Whether a source applies to a principle: the mT channel offsets not to xmr/amr, the relative ones
// only to them (probe/signal_chain.hpp). A sweep of a source that does not apply is left empty.
bool source_applies(const ErrorSource& src, SensorPrinciple p);
// The name of a sensor in tables and plots: its array (two, diff4, ring:N) or, for the one-spot
// principles, the principle (inplane, xmr, amr).
std::string sensor_label(const ProbeSetup& s);

// Harmonic signature of a source on an array: |a0| and c1..c8 at one value.
struct HarmonicSignature {
  std::string swept, array;     // source and array
  double value = 0;             // the source's value (src.unit)
  std::array<double, 9> c_deg{};  // c_deg[0] = |a0|, c_deg[n] = c_n (deg)
  double pp_deg = 0;
};
// The signature at the sweep's value closest to `value` (its last value when value is NaN).
HarmonicSignature harmonic_signature(const SweepResult& sweep, double value);

// All sweeps of a study: every source on every array, values 0..max in
// `points` steps, cubic fits of `coefs`.
struct ErrorSourcesRun {
  std::string field_spec;                          // as configured (study.field)
  std::string field;                               // FieldSource::name()
  std::vector<ProbeSetup> setups;                  // one per array
  std::vector<const ErrorSource*> sources;         // in study order
  std::vector<std::vector<SweepResult>> sweeps;    // [source][array]
  std::vector<FitRow> fits;                        // every sweep's fits
  std::vector<std::string> coefs;                  // fitted columns
  long sweep_points = 0;                           // sweep.points: values per source
  double floor_deg = 0, relative = 0;              // summary.floor_deg, summary.relative
};
// Reads study.field, study.sources, sweep.points, the range keys and
// sweep.coefs from cfg; the setups (array, r0, plane, steps) come from the caller.
ErrorSourcesRun run_error_sources(const Config& cfg, const std::vector<ProbeSetup>& setups, const std::string& study);

}  // namespace magenc
