// The speed study's computation (docs/studies/speed.md; docs/physics.md "Speed: the error of a turning
// encoder"): the configured sensor, mount and field at speeds 0..study.rpm_max through the probe
// pipeline's steady-state chain (probe/speed.hpp):
//  * sweep: for every timing of study.timing_* (a chip's delay, filter and update rate) without and with
//    the ideal prediction, the spectrum of the error (mean lag a0, pp, harmonics) at every speed;
//  * commutation: for every pole-pair count p of study.pole_pairs, the electrical error p eps and the
//    torque factor cos(p eps) (mean and least over the turn) of each sweep point;
//  * attenuation: the configured (eccentric) mount behind a first-order filter at study.filter_hz alone:
//    every harmonic at speed against its static value;
//  * calibration: a correction (study.calibration_method) taken at rest and one taken at
//    study.calibration_rpm with the delay and filter of study.calibration_timing (its hold left out: a sawtooth whose
//    phase is the sampling's, not the angle's, which no table of the angle removes), both run at every
//    speed: pp and the largest |error| (the mean lag counts) of the residual.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/config.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

struct SpeedTiming {
  std::string name;
  double delay_us = 0, filter_hz = 0, sample_hz = 0;
};

struct SpeedStudyOptions {
  std::vector<SpeedTiming> timings;
  double rpm_max = 30000;
  int rpm_points = 31;
  double filter_hz = 1000;              // the attenuation part's filter
  std::vector<long> pole_pairs = {4};
  std::string calibration_method = "harmonics:8";
  double calibration_rpm = 3000;
  SpeedTiming calibration_timing;      // study.calibration_timing (one of the timings; "" = the first)
  int steps = 720;

  static std::vector<KeySpec> keys();  // study.* keys
  // InputError naming the key: timing lists of different lengths, a sample rate below twice the fastest
  // rotation frequency.
  static SpeedStudyOptions from_config(const Config& cfg);
  std::vector<double> rpms() const;  // 0..rpm_max in rpm_points steps
};

struct SpeedPoint {
  std::string timing;
  Prediction prediction = Prediction::None;
  double rpm = 0;
  Spectrum spectrum;
};

struct CommutationPoint {
  std::string timing;
  Prediction prediction = Prediction::None;
  double rpm = 0;
  int pole_pairs = 1;
  double electrical_mean_deg = 0, electrical_max_deg = 0;  // p a0 and max |p eps|
  double torque_mean = 1, torque_min = 1;                  // cos(p eps) over the turn
};

struct AttenuationPoint {
  double rpm = 0;
  Spectrum spectrum;
};

struct SpeedCalibrationPoint {
  double rpm = 0;
  double pp_raw_deg = 0, pp_cal_rest_deg = 0, pp_cal_moving_deg = 0;
  double max_raw_deg = 0, max_cal_rest_deg = 0, max_cal_moving_deg = 0;  // max |eps|: the lag included
};

struct SpeedStudyResult {
  std::string field, array;
  Mount mount;
  SpeedStudyOptions options;
  std::vector<SpeedPoint> sweep;
  std::vector<CommutationPoint> commutation;
  std::vector<AttenuationPoint> attenuation;
  std::vector<SpeedCalibrationPoint> calibration;
};

SpeedStudyResult run_speed_study(const FieldSource& field, const ProbeSetup& base, const Mount& mount,
                                 const SpeedStudyOptions& opt);

}  // namespace magenc
