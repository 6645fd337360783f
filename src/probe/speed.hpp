// The signal chain of a turning encoder (docs/physics.md "Speed: the error of a turning encoder").
// At a constant speed of rpm revolutions per minute (omega = 2 pi rpm / 60 rad/s, theta = omega t) the
// chip's timing acts on the channels (u_c, u_s) of one turn in the steady state: the per-turn Fourier
// component k of a channel is multiplied by
//   H_k = exp(-i k omega tau) / (1 + i k omega / omega_c),   omega_c = 2 pi filter_hz (no filter: 1),
// tau = delay_us on the cos channel and delay_us + skew_us on the sin channel (sequential sampling). The
// angle follows (atan2), then the prediction (none, or ideal: the output angle advanced by
// omega delay + atan(p omega / omega_c) / p, p the channel's electrical turns per turn: a perfect speed
// compensation), then a zero-order hold at sample_hz (first sample at theta = 0; 0 = continuous). Every
// time constant acts only when rpm != 0: at rpm 0 the pipeline never enters the chain.
#pragma once
#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/config.hpp"

namespace magenc {

enum class Prediction { None, Ideal };

struct SpeedChain {
  double rpm = 0;            // speed.rpm (signed: the direction of rotation)
  double delay_us = 0;       // sensor.delay_us: both channels
  double skew_us = 0;        // sensor.skew_us: the sin channel later still
  double filter_hz = 0;      // sensor.filter_hz: first-order low-pass corner of each channel (0 = none)
  double sample_hz = 0;      // sensor.sample_hz: zero-order hold of the output (0 = continuous)
  Prediction prediction = Prediction::None;  // sensor.prediction

  // The chain is entered only at a speed.
  bool moving() const { return rpm != 0.0; }
  // At a speed with any timing: the chain changes the result (moving() and a delay, skew, filter or hold).
  bool acts() const { return moving() && (delay_us > 0 || skew_us > 0 || filter_hz > 0 || sample_hz > 0); }
  double omega_rad_s() const;
  // Reads speed.rpm and sensor.delay_us, skew_us, filter_hz, sample_hz, prediction; validate().
  static SpeedChain from_config(const Config& cfg);
  // Finite values, delay, skew, filter and sample rate >= 0, prediction only at a speed, sample_hz either 0
  // or at least twice the rotation frequency |rpm| / 60 (InputError naming the keys).
  void validate() const;
  // The mean lag of the output angle (degrees, positive = behind the rotor) that an ideal prediction
  // removes for a channel of p electrical turns per turn: omega delay + atan(p omega / omega_c) / p.
  double lag_deg(int p = 1) const;

  // The steady-state chain on the M uniform samples of one turn (theta_m = 2 pi m / M): channels (M x 2:
  // u_c, u_s) are replaced by the filtered and delayed channels, eps_deg (M) by the angle error of the
  // output: wrap(psi - p theta) / p after the prediction and the hold (p = electrical turns per turn).
  void apply(Eigen::MatrixXd& channels, Eigen::VectorXd& eps_deg, int p = 1) const;

  // apply() in two parts, for callers that take the angles in bulk in between (analysis/fast_pipeline):
  // filter() replaces the channels by the delayed, filtered ones and returns their spectrum; output() turns
  // eps_deg, the error of those channels' angle (wrap(psi - p theta) / p), into the output's (prediction, hold);
  // with the hold and cos_out, sin_out (M values each), also the output's direction theta + eps as a unit vector.
  struct FilteredTurn {
    int M = 0;
    std::vector<std::complex<double>> c, s;  // unscaled DFT coefficients k = 0..M/2 of u_c', u_s'
    int kmax = 0;                            // the last k the hold's evaluations between grid angles use
  };
  FilteredTurn filter(Eigen::MatrixXd& channels) const;
  void output(const FilteredTurn& turn, Eigen::VectorXd& eps_deg, int p = 1, double* cos_out = nullptr,
              double* sin_out = nullptr) const;
};

std::string prediction_name(Prediction p);
Prediction parse_prediction(const std::string& text);

// The keys of the turning encoder: speed.rpm and the chip's timing sensor.delay_us, sensor.skew_us,
// sensor.filter_hz, sensor.sample_hz, sensor.prediction.
std::vector<KeySpec> speed_keys();

}  // namespace magenc
