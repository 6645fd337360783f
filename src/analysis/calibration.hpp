// The factory correction and what is left of it (docs/physics.md "Calibration"). A correction is taken
// from one calibration state A and applied at any run state B; it is a function of the sensor's own angle
// only, never of the true rotor angle theta:
//   harmonics:N  least squares of e(phi) = a0 + sum_{n<=N} a_n cos n phi + b_n sin n phi to the pairs
//                (phi_A(theta), eps_A(theta));
//   lut:K        K values at phi_k = 360 k/K, each the calibration error at phi_k by periodic linear
//                interpolation of the pairs sorted by phi; e(phi) is the periodic linear interpolation
//                of that table;
//   ogp          channel offsets, gain ratio and phase from the raw channels by a least-squares ellipse,
//                inverted before atan2.
// Corrected angle phi' = phi - e(phi), residual eps' = wrap(phi' - theta). Principles whose channel angle
// turns twice per turn (amr: the sensor's angle is known modulo 180 deg) are corrected in the channel
// angle psi = turns * phi: the table is e_psi(psi) of the pairs (turns phi_A, turns eps_A) and
// eps' = wrap(turns eps - e_psi(psi)) / turns; with turns = 1 (bz, inplane, xmr) this is the formula above.
#pragma once
#include <random>
#include <string>

#include <Eigen/Core>

#include "analysis/sensor_noise.hpp"
#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "probe/angle_error.hpp"

namespace magenc {

enum class CalibrationKind { None, Harmonics, Lut, Ogp };

struct CalibrationMethod {
  CalibrationKind kind = CalibrationKind::None;
  int order = 0;  // N of harmonics:N (1..kMaxHarmonics), K of lut:K (4..kMaxLut); 0 otherwise
  static constexpr int kMaxHarmonics = 256;
  static constexpr int kMaxLut = 65536;
  // "none", "harmonics:N", "lut:K", "ogp"; InputError naming `what` and the allowed values otherwise.
  static CalibrationMethod parse(const std::string& text, const std::string& what = "calibration.method");
  std::string name() const;  // the text parse() reads
  bool none() const { return kind == CalibrationKind::None; }
};

// The ellipse of two channels: u_c = oc + A cos psi, u_s = os + r A sin(psi + delta) (the signal chain's
// form with r = 1 + gain mismatch, delta = its phase error). Offsets in the channels' unit.
struct ChannelEllipse {
  double offset_cos = 0, offset_sin = 0;
  double gain_ratio = 1;  // r = amplitude of u_s / amplitude of u_c (> 0)
  double phase_deg = 0;   // delta, |delta| < 90
  // The channel angle psi (deg) of the channels after inverting the ellipse.
  double angle_deg(double u_c, double u_s) const;
};

// Least-squares ellipse through the points (u_c, u_s) (the conic a x^2 + b xy + c y^2 + d x + e y + f = 0
// with |(a..f)| = 1 minimizing the algebraic residual; exact for points on an ellipse). InputError when
// fewer than 6 points are given or they do not lie on an ellipse (e.g. all on a line).
ChannelEllipse fit_channel_ellipse(const Eigen::VectorXd& u_cos, const Eigen::VectorXd& u_sin);

struct Correction {
  CalibrationMethod method;
  int turns = 1;                  // channel-angle turns per mechanical turn (amr 2): the tables are in psi
  Eigen::VectorXd harmonics_deg;  // harmonics:N: (a0, a1, b1, ..., aN, bN) of e_psi (deg)
  Eigen::VectorXd lut_deg;        // lut:K: e_psi at psi_k = 360 k/K (deg)
  ChannelEllipse ellipse;         // ogp
  // e_psi(psi) in degrees (harmonics, lut; 0 for none and ogp).
  double e_deg(double psi_deg) const;
};

// A correction of the pairs (phi_deg, eps_deg) (the sensor's angle and its error at the calibration state;
// any order and spacing) for harmonics:N or lut:K (none gives an empty correction). InputError when the
// method is ogp (it needs channels), when the sizes differ, or (harmonics:N) there are fewer than 2N + 1
// pairs, (lut:K) fewer than 2.
Correction correct_pairs(const CalibrationMethod& method, const Eigen::VectorXd& phi_deg,
                         const Eigen::VectorXd& eps_deg, int turns = 1);
// An ogp correction of raw channels (M x 2, columns u_c, u_s).
Correction correct_channels(const Eigen::MatrixXd& channels, int turns = 1);

// The correction taken at a calibration run (angle_error's result at state A) for principle p: the pairs
// (theta + eps, eps), or its channels for ogp. With a readout (reference noise, quantization) the pairs are
// the observed ones (observe_curve, shared with diagnose); ogp takes the channels as they are.
Correction calibrate(const CalibrationMethod& method, const AngleErrorResult& at, SensorPrinciple p);
Correction calibrate(const CalibrationMethod& method, const AngleErrorResult& at, SensorPrinciple p,
                     const ReferenceReadout& readout, std::mt19937& rng);

// The residual eps' (deg) of a curve after the correction: from the pairs (theta, eps) for harmonics, lut
// and none (eps' = wrap(turns eps - e_psi(turns (theta + eps))) / turns); ogp needs the channels.
Eigen::VectorXd residual_of_pairs(const Correction& c, const Eigen::VectorXd& theta_deg,
                                  const Eigen::VectorXd& eps_deg);
// Peak-to-peak (deg) of residual_of_pairs(correct_pairs(method, theta + eps_cal, eps_cal, turns), theta,
// eps_run): the calibrated error of the Monte Carlo studies in one call. harmonics:N with at least
// 4 (2N + 1) pairs takes a faster route equal to that one up to round-off: cos(n t), sin(n t) by angle
// addition from one sincos per pair, and the normal equations built from the power sums of cos(m t),
// sin(m t), m <= 2N (the matrix is well conditioned for such an overdetermined fit; QR when its Cholesky
// factorisation fails). Other methods: the two calls.
double calibrated_pp_deg(const CalibrationMethod& method, const Eigen::VectorXd& theta_deg,
                         const Eigen::VectorXd& eps_cal_deg, const Eigen::VectorXd& eps_run_deg, int turns = 1);
// The same for one electrical turn (turns = 1) with the sensor's angles psi = theta + eps of the calibration
// state and of the run given as unit vectors (cos psi, sin psi: the normalized channels, FastPipeline's
// UnitAngles): no trigonometric call. Equal to the call above up to round-off.
double calibrated_pp_deg(const CalibrationMethod& method, const Eigen::VectorXd& theta_deg,
                         const Eigen::VectorXd& eps_cal_deg, const Eigen::VectorXd& cos_cal,
                         const Eigen::VectorXd& sin_cal, const Eigen::VectorXd& eps_run_deg,
                         const Eigen::VectorXd& cos_run, const Eigen::VectorXd& sin_run);
// The residual of a run (angle_error's result at state B): pairs, or channels for ogp.
Eigen::VectorXd residual_deg(const Correction& c, const AngleErrorResult& run);
// The run with eps replaced by the residual and the spectrum recomputed when the run was uniform
// (angle_error's result): what every output that evaluates a mount reports under a calibration.
AngleErrorResult corrected(const Correction& c, AngleErrorResult run);

// ---- The configured calibration (keys calibration.method, calibration.at; docs/interfaces.md) ----

// calibration.method parsed (InputError naming the key).
CalibrationMethod calibration_method(const Config& cfg);
// The configuration of the calibration state: cfg with calibration.at's keys set over it. InputError naming
// calibration.at and the key when a key is not declared, out of range, a calibration.* key, or a magnet.* key
// (the field source is the run's: a magnet change is a different field, not a calibration state).
Config calibration_state(const Config& cfg);
// The correction of calibration.method taken at the calibration state on `field` with the run's array
// (array_spec and what as sensor_setup_from_config takes them): none (empty) when the method is none.
Correction correction_from_config(const FieldSource& field, const Config& cfg, const std::string& array_spec,
                                  const std::string& what = "sensor.array");

// calibration.method and calibration.at, declared here beside their reader: only the executables that apply a
// calibration (error_spectrum, calibrate) declare them; everywhere else they are unknown keys, never silently
// ignored.
std::vector<KeySpec> calibration_keys();

}  // namespace magenc
