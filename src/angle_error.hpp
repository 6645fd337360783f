// The probe-path pipeline: field (magnet frame) -> mounting -> probe array ->
// angle -> error eps(theta) -> spectrum.
#pragma once
#include <Eigen/Core>

#include "field_source.hpp"
#include "mounting.hpp"
#include "probe_array.hpp"
#include "spectrum.hpp"

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

// Runs the pipeline for one mounting case. Throws InputError if the probe
// circle reaches into the magnet radius region the field cannot serve, or the
// setup is invalid (r0 <= 0, steps < 16).
AngleErrorResult angle_error(const FieldSource& field, const ProbeSetup& setup, const Mount& mount);

// Convenience: only the spectrum.
Spectrum error_spectrum(const FieldSource& field, const ProbeSetup& setup, const Mount& mount);

}  // namespace magenc
