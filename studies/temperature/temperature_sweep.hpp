// Temperature sweep (docs/physics.md "Environment: stray fields and temperature"): per sensor (bz arrays
// two, diff4, ring:N; inplane) the error spectrum and the field against the chip's window from
// temperature_min_C to temperature_max_C, for two mounts:
//  * "mount": the configured mount (mount.* keys) with the configured signal chain;
//  * "box p99": the Monte Carlo sample of the tolerance box whose pp at 20 C is nearest the box's 99th
//    percentile (per sensor; the same seeded samples for every sensor), with the same chain.
// At each temperature the probe setup's Environment (Br(T), offset and air-gap drift; coefficients from
// the configuration) goes through the pipeline (angle_error.hpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/tolerance.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

struct TemperatureOptions {
  std::vector<std::string> sensors = {"two", "diff4", "ring:8", "inplane"};
  double temperature_min_C = -40, temperature_max_C = 150, temperature_step_K = 10;
  ToleranceBox box;          // the box of the p99 mount
  long samples = 200;        // Monte Carlo samples of the box (at 20 C)
  std::uint64_t seed = 1;
  int steps = 360;           // theta samples per turn

  static std::vector<KeySpec> keys();  // [study], [tol] keys
  static TemperatureOptions from_config(const Config& cfg);
  std::vector<double> temperatures_C() const;
};

struct TemperaturePoint {
  double temperature_C = 20;
  double br_scale = 1;       // Br(T) / Br(20 C)
  Spectrum spectrum;
  double field_min_mT = 0, field_max_mT = 0;
  bool in_window = true;
  double margin_low_mT = 0, margin_high_mT = 0;  // field_min - window.min, window.max - field_max
};

struct TemperatureCurve {
  std::string sensor, mount_label;  // mount_label: "mount" or "box p99"
  Mount mount;
  std::vector<TemperaturePoint> points;
};

struct TemperatureResult {
  std::string field;
  Environment coefficients;     // the configured coefficients (temperature 20 C)
  FieldWindow window;           // the chip's window (sensor.field_min_mT, field_max_mT)
  std::vector<double> p99_pp_deg;  // per sensor: the box's 99th percentile of pp at 20 C
  std::vector<TemperatureCurve> curves;  // per sensor: mount, box p99
};

// base: the probe setup of the configuration (its Environment's coefficients are used, its temperature
// replaced at each point; a stray field of the configuration stays on).
TemperatureResult run_temperature_sweep(const FieldSource& field, const ProbeSetup& base, const Mount& mount,
                                        const TemperatureOptions& opt);

}  // namespace magenc
