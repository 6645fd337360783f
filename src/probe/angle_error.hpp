// The probe-path pipeline: field (magnet frame) -> mounting -> probe array ->
// angle -> error eps(theta) -> spectrum.
#pragma once
#include <Eigen/Core>

#include "fields/field_source.hpp"
#include "probe/mounting.hpp"
#include "probe/probe_array.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

struct ProbeSetup {
  ProbeArray array;           // probe angles and channel weights
  double r0_mm = 2.4;         // nominal probe radius
  double plane_z_mm = 4.55;   // sensing plane height in the magnet frame (z_s)
  int steps = 3600;           // M samples of theta over one turn (>= 16)
};

struct AngleErrorResult {
  Eigen::VectorXd theta_deg;  // M rotor angles, 360*m/M
  Eigen::VectorXd eps_deg;    // angle error wrap(phi - theta), degrees
  Eigen::MatrixXd probe_B_T;  // M x K probe readings (measured component, T)
  Spectrum spectrum;
};

// Probe positions for every theta: returns 3 x (M*K) in the magnet frame (mm),
// column m*K + k = probe k at theta_m.
Eigen::Matrix3Xd probe_paths_mm(const ProbeSetup& setup, const Mount& mount);
// The same for arbitrary rotor angles theta_deg (M values): 3 x (M*K).
Eigen::Matrix3Xd probe_paths_mm(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_deg);
// The M = steps uniform rotor angles 360*m/M of one turn, in degrees.
Eigen::VectorXd uniform_theta_deg(int steps);

// Runs the pipeline for one mounting case: all M*K probe positions, one batch
// field call (OpenMP inside the source), channels, atan2, wrap, spectrum.
// Throws InputError when
//  * the setup is invalid: r0 <= 0 or NaN, steps < 16, non-finite plane height,
//    non-finite mount values, non-zero tilt;
//  * the path is degenerate: r0 - |s| - |d| <= 0 (a probe circle may pass over
//    the rotation axis, the angle no longer turns once per turn) - any field;
//  * for the exact field (AnalyticField): a probe path enters the magnet or
//    touches its surface (radius <= R while |z_s + dz| <= L/2). The test is
//    exact (closest approach | |p_k + s| - |d| | of each probe's circle), not
//    just at the samples. A sensing plane above the top face (the normal case,
//    h + dz > 0) always passes; a plane within the magnet's height is allowed
//    only with every probe path outside radius R (a sensor beside the magnet).
//    The field itself is defined inside too (B includes mu0*M0), but a probe
//    inside a magnet is not a mounting the program should silently answer.
//    grid:/fem: sources reject points outside their region themselves.
// Throws ComputeError if the field gives a non-finite angle.
AngleErrorResult angle_error(const FieldSource& field, const ProbeSetup& setup, const Mount& mount);

// The error curve at arbitrary rotor angles theta_deg (any order, any spacing; e.g. a measured curve's
// angles): theta_deg, eps_deg and probe_B_T are filled, spectrum is left empty (it needs uniform samples).
// setup.steps is not used. Same validation and errors as angle_error().
AngleErrorResult angle_error_at(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                                const Eigen::VectorXd& theta_deg);
// Convenience: only the spectrum.
Spectrum error_spectrum(const FieldSource& field, const ProbeSetup& setup, const Mount& mount);

}  // namespace magenc
