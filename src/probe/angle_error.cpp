#include "probe/angle_error.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "fields/analytic_field.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {

// Setup and mount must describe a usable probe path (see angle_error()).
void validate_setup(const ProbeSetup& setup, const Mount& mount) {
  if (!(std::isfinite(setup.r0_mm) && setup.r0_mm > 0))
    throw InputError("sensor.r0_mm = " + num(setup.r0_mm) + " is out of range: allowed (0, 1000] mm");
  if (setup.steps < 16)
    throw InputError("sensor.steps = " + std::to_string(setup.steps) +
                     " is out of range: allowed integer >= 16");
  if (!std::isfinite(setup.plane_z_mm))
    throw InputError("sensing plane height is not finite: allowed a finite value in mm");
  const std::size_t K = setup.array.size();
  if (K == 0 || setup.array.w_cos.size() != K || setup.array.w_sin.size() != K)
    throw InputError("sensor.array '" + setup.array.name + "' has no probes or inconsistent weights");
  mount.validate();
  const double offsets_mm = std::hypot(mount.sx_mm, mount.sy_mm) + std::hypot(mount.dx_mm, mount.dy_mm);
  if (setup.r0_mm - offsets_mm <= 0)
    throw InputError("mounting offsets |s| + |d| = " + num(offsets_mm) + " mm reach the probe radius r0 = " +
                     num(setup.r0_mm) + " mm (degenerate probe path): allowed |s| + |d| < r0");
}

// For the exact field: no probe path may enter the magnet (or touch its
// surface, where B is discontinuous). The path of probe k is a circle of
// radius |p_k + s| about -d at height z_s + dz, so its closest approach to the
// axis is | |p_k + s| - |d| |, checked exactly rather than at the samples.
void check_paths_outside_magnet(const AnalyticField& field, const ProbeSetup& setup, const Mount& mount) {
  const Magnet& mag = field.magnet();
  const double z_mm = setup.plane_z_mm + mount.dz_mm;
  if (std::abs(z_mm) > mag.top_z_mm()) return;  // plane above (or below) the magnet: always outside
  const double d_mm = std::hypot(mount.dx_mm, mount.dy_mm);
  for (std::size_t k = 0; k < setup.array.size(); ++k) {
    const double b_rad = deg_to_rad(setup.array.angle_deg[k]);
    const double r_mm = std::hypot(setup.r0_mm * std::cos(b_rad) + mount.sx_mm,
                                   setup.r0_mm * std::sin(b_rad) + mount.sy_mm);
    const double closest_mm = std::abs(r_mm - d_mm);
    if (closest_mm <= mag.radius_mm)
      throw InputError("probe path enters the magnet: at z = " + num(z_mm) + " mm (mount.dz_mm = " +
                       num(mount.dz_mm) + ") probe " + std::to_string(k) + " comes within " +
                       num(closest_mm) + " mm of the axis, magnet radius " + num(mag.radius_mm) +
                       " mm, half height " + num(mag.top_z_mm()) +
                       " mm: allowed paths outside the magnet (plane above its top face or radius > R)");
  }
}

}  // namespace

Eigen::VectorXd uniform_theta_deg(int steps) {
  Eigen::VectorXd theta_deg(steps);
  for (int m = 0; m < steps; ++m) theta_deg[m] = 360.0 * m / steps;
  return theta_deg;
}

namespace {

Eigen::VectorXd uniform_theta_rad(int steps) {
  Eigen::VectorXd theta_rad(steps);
  for (int m = 0; m < steps; ++m) theta_rad[m] = 2.0 * kPi * m / steps;
  return theta_rad;
}

Eigen::Matrix3Xd probe_paths_at_rad(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_rad) {
  const auto M = theta_rad.size();
  const std::size_t K = setup.array.size();
  Eigen::Matrix3Xd p(3, M * static_cast<Eigen::Index>(K));
  std::vector<double> px(K), py(K);
  for (std::size_t k = 0; k < K; ++k) {
    const double b_rad = deg_to_rad(setup.array.angle_deg[k]);
    px[k] = setup.r0_mm * std::cos(b_rad);
    py[k] = setup.r0_mm * std::sin(b_rad);
  }
  for (Eigen::Index m = 0; m < M; ++m) {
    for (std::size_t k = 0; k < K; ++k)
      p.col(m * static_cast<Eigen::Index>(K) + static_cast<Eigen::Index>(k)) =
          probe_position_mm(mount, px[k], py[k], theta_rad[m], setup.plane_z_mm);
  }
  return p;
}

// The pipeline at rotor angles theta_rad (theta_deg: the same angles in degrees, as reported).
AngleErrorResult angle_error_at_rad(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                                    const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& theta_rad) {
  // 1. Validate the setup, the mount and (exact field) that no path enters the magnet.
  validate_setup(setup, mount);
  if (const auto* exact = dynamic_cast<const AnalyticField*>(&field))
    check_paths_outside_magnet(*exact, setup, mount);

  // 2. All probe positions, then one batch field evaluation (OpenMP inside).
  const auto M = theta_rad.size();
  const auto K = static_cast<Eigen::Index>(setup.array.size());
  const Eigen::VectorXd B = field.Bz_T(probe_paths_at_rad(setup, mount, theta_rad));  // tilt == 0: normal is z

  // 3. Channels, angle and error per theta.
  AngleErrorResult res;
  res.theta_deg = theta_deg;
  res.eps_deg.resize(M);
  res.probe_B_T.resize(M, K);
  for (Eigen::Index m = 0; m < M; ++m) {
    double ch_cos = 0, ch_sin = 0;
    for (Eigen::Index k = 0; k < K; ++k) {
      const double b = B[m * K + k];
      res.probe_B_T(m, k) = b;
      ch_cos += setup.array.w_cos[k] * b;
      ch_sin += setup.array.w_sin[k] * b;
    }
    const double phi_rad = std::atan2(ch_sin, ch_cos);
    res.eps_deg[m] = wrap_deg(rad_to_deg(phi_rad - theta_rad[m]));
    if (!std::isfinite(res.eps_deg[m]))
      throw ComputeError(field.name() + " field gave a non-finite angle at theta = " + num(theta_deg[m]) +
                         " deg");
  }
  return res;
}

}  // namespace

Eigen::Matrix3Xd probe_paths_mm(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_deg) {
  return probe_paths_at_rad(setup, mount, theta_deg * (kPi / 180.0));
}

Eigen::Matrix3Xd probe_paths_mm(const ProbeSetup& setup, const Mount& mount) {
  return probe_paths_at_rad(setup, mount, uniform_theta_rad(setup.steps));
}

AngleErrorResult angle_error_at(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                                const Eigen::VectorXd& theta_deg) {
  return angle_error_at_rad(field, setup, mount, theta_deg, theta_deg * (kPi / 180.0));
}

AngleErrorResult angle_error(const FieldSource& field, const ProbeSetup& setup, const Mount& mount) {
  validate_setup(setup, mount);  // before the sample grid is built from setup.steps
  AngleErrorResult res =
      angle_error_at_rad(field, setup, mount, uniform_theta_deg(setup.steps), uniform_theta_rad(setup.steps));
  // 4. Spectrum of the uniform samples.
  res.spectrum = spectrum_of(res.eps_deg);
  return res;
}

Spectrum error_spectrum(const FieldSource& field, const ProbeSetup& setup, const Mount& mount) {
  return angle_error(field, setup, mount).spectrum;
}

}  // namespace magenc
