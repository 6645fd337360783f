// Sensing principles side by side (docs/physics.md "Sensor principles"): the same
// magnet, field and tolerance box for Hall arrays reading Bz on a circle (bz:
// two, diff4, ring:N) and the one-spot principles (inplane, xmr, amr).
//  * one spectrum per mounting error alone (sx, sy, dx, dy, dz, sensor tilt
//    about x and y, magnet tilt) per sensor, direct pipeline (angle_error.hpp);
//  * a seeded Monte Carlo over the tolerance box (tolerance.hpp; the same
//    samples for every sensor): pp statistics over the samples whose field
//    lies in the sensor's window, the out-of-window samples counted apart;
//  * the field-window margin: how far the field extremes over the box stay
//    from the window (mT; negative = outside).
// Each sensor has its own field window (study keys window.<name>_min_mT /
// _max_mT, defaults: off except where the study's configuration sets them).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/tolerance.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "io/tables.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

// One sensor of the comparison: a label ("two", "inplane", ...) and its probe setup.
struct PrincipleSensor {
  std::string label;
  ProbeSetup setup;
};

// A sensor from a study list entry: "two", "diff4", "ring:N" (bz on r0) or "inplane", "xmr", "amr"
// (the point array); the rest (r0, plane, steps, chain, area) from `base`; the window as given.
// InputError naming `what` for anything else.
PrincipleSensor principle_sensor(const std::string& entry, const ProbeSetup& base, const std::string& what);

struct SensorPrinciplesOptions {
  std::vector<std::string> sensors = {"two", "diff4", "ring:8", "inplane", "xmr", "amr"};
  ToleranceBox box;             // tolerance box (half-widths; tilts in deg)
  long samples = 400;           // Monte Carlo samples (the same for every sensor)
  std::uint64_t seed = 1;
  int mc_steps = 360;           // theta samples per turn of the Monte Carlo cases
  double case_offset_mm = 0.1;  // single-error cases: sx, sy, dx, dy
  double case_dz_mm = 0.2;      // dz, with dx = case_residual_dx_mm (dz alone changes nothing)
  double case_residual_dx_mm = 0.05;
  double case_tilt_deg = 1.0;   // sensor tilt about x, about y; magnet tilt (azimuth 0)
  std::vector<FieldWindow> windows;  // one per sensor (same order)

  static std::vector<KeySpec> keys();  // [study], [tol], [window] keys
  static SensorPrinciplesOptions from_config(const Config& cfg);
};

// The single-error cases: label and mount.
std::vector<std::pair<std::string, Mount>> principle_cases(const SensorPrinciplesOptions& opt);

struct PrincipleSensorResult {
  std::string label;
  SensorPrinciple principle = SensorPrinciple::Bz;
  FieldWindow window;
  std::vector<AngleErrorResult> cases;  // per principle_cases(), spectra and field extremes
  double ideal_field_min_mT = 0, ideal_field_max_mT = 0;  // ideal mount
  SampleStats mc;                       // pp over the in-window MC samples (deg); n = 0: none inside
  long mc_out_of_window = 0;
  double mc_field_min_mT = 0, mc_field_max_mT = 0;  // field extremes over all samples
  // Window margins over the box: min over samples of (field_min - window.min) and of
  // (window.max - field_max), mT (inf when that side of the window is off).
  double margin_low_mT = 0, margin_high_mT = 0;
};

struct SensorPrinciplesResult {
  std::string field;     // FieldSource::name()
  std::vector<std::pair<std::string, Mount>> cases;
  std::vector<PrincipleSensorResult> sensors;
  std::vector<SpectrumRow> spectra;  // spectra table rows: every case x sensor; extra columns sensor,
                                     // principle, case, field_min_mT, field_max_mT, in_window
};

// Runs the comparison on `field` for the sensors of opt (setups from `base`: r0, plane, steps,
// magnet height). InputError when the field cannot serve an in-plane principle or a tilt.
SensorPrinciplesResult run_sensor_principles(const FieldSource& field, const ProbeSetup& base,
                                             const SensorPrinciplesOptions& opt);

}  // namespace magenc
