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
  setup.chain.validate();
  if (mount.magnet_tilted() && !(std::isfinite(setup.magnet_height_mm) && setup.magnet_height_mm > 0))
    throw InputError("magnet.height_mm = " + num(setup.magnet_height_mm) +
                     " (pivot of the magnet tilt) is out of range: allowed (0, 1000] mm");
  const double offsets_mm = std::hypot(mount.sx_mm, mount.sy_mm) + std::hypot(mount.dx_mm, mount.dy_mm);
  if (setup.r0_mm - offsets_mm <= 0)
    throw InputError("mounting offsets |s| + |d| = " + num(offsets_mm) + " mm reach the probe radius r0 = " +
                     num(setup.r0_mm) + " mm (degenerate probe path): allowed |s| + |d| < r0");
}

// A tilted probe needs the full B vector off the sensing plane.
void check_source_serves_tilt(const FieldSource& field, const Mount& mount) {
  if (!mount.tilted() || field.gives_full_vector()) return;
  const char* key = mount.tilt_x_deg != 0.0   ? "mount.tilt_x_deg"
                    : mount.tilt_y_deg != 0.0 ? "mount.tilt_y_deg"
                                              : "mount.magnet_tilt_deg";
  const double v = mount.tilt_x_deg != 0.0   ? mount.tilt_x_deg
                   : mount.tilt_y_deg != 0.0 ? mount.tilt_y_deg
                                             : mount.magnet_tilt_deg;
  throw InputError(std::string(key) + " = " + num(v) + " needs the full field vector in 3-D, but the " +
                   field.name() + " field source gives only Bz on a plane: allowed 0 with this source " +
                   "(use analytic, fem:DIR or a 3-D box.vti grid)");
}

// Fixed-frame probe positions (sensor tilt included) and their rotor-frame
// circles: radius rho_k about the axis, height z_k.
std::vector<Eigen::Vector3d> fixed_probe_positions(const ProbeSetup& setup, const MountKinematics& kin) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t k = 0; k < setup.array.size(); ++k) {
    const double b_rad = deg_to_rad(setup.array.angle_deg[k]);
    out.push_back(kin.fixed_position_mm(setup.r0_mm * std::cos(b_rad), setup.r0_mm * std::sin(b_rad)));
  }
  return out;
}

// For the exact field: no probe path may enter the magnet (or touch its
// surface, where B is discontinuous). Without a magnet tilt the path of probe k
// in the rotor frame is a circle of radius rho_k = |(c + Rs p_k)_xy| at height
// z_k about the axis, and the magnet a cylinder of radius R about d, so the
// closest approach is | rho_k - |d| | (exact, not just at the samples). With a
// magnet tilt g the magnet is replaced by a hull containing it: radius
// R + L|sin g| about d, z in [-L/2 - R|sin g|, -L/2 + L cos g + R|sin g|]
// (conservative; see angle_error.hpp).
void check_paths_outside_magnet(const AnalyticField& field, const ProbeSetup& setup, const Mount& mount) {
  const Magnet& mag = field.magnet();
  if (mount.magnet_tilted() && std::abs(setup.magnet_height_mm - mag.height_mm) > 1e-9 * mag.height_mm)
    throw InputError("magnet tilt pivot: the probe setup's magnet height " + num(setup.magnet_height_mm) +
                     " mm differs from the analytic field's magnet.height_mm = " + num(mag.height_mm) +
                     " mm: allowed the same magnet");
  const double sg = std::abs(std::sin(deg_to_rad(mount.magnet_tilt_deg)));
  const double cg = std::cos(deg_to_rad(mount.magnet_tilt_deg));
  const double half = mag.top_z_mm(), L = mag.height_mm;
  const double r_hull = mag.radius_mm + L * sg;
  const double z_lo = mount.magnet_tilted() ? -half - mag.radius_mm * sg : -half;
  const double z_hi = mount.magnet_tilted() ? -half + L * cg + mag.radius_mm * sg : half;
  const MountKinematics kin(mount, setup.plane_z_mm, mag.height_mm);
  const std::vector<Eigen::Vector3d> fixed = fixed_probe_positions(setup, kin);
  const double d_mm = std::hypot(mount.dx_mm, mount.dy_mm);
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    const double z_mm = fixed[k].z();
    if (z_mm > z_hi || z_mm < z_lo) continue;  // this probe's path passes above (or below) the magnet
    const double closest_mm = std::abs(std::hypot(fixed[k].x(), fixed[k].y()) - d_mm);
    if (closest_mm <= r_hull)
      throw InputError("probe path enters the magnet: at z = " + num(z_mm) + " mm (mount.dz_mm = " +
                       num(mount.dz_mm) + ") probe " + std::to_string(k) + " comes within " +
                       num(closest_mm) + " mm of the magnet's axis, magnet radius " + num(mag.radius_mm) +
                       " mm, half height " + num(half) + " mm" +
                       (mount.magnet_tilted() ? " (tilted magnet: hull radius " + num(r_hull) + " mm, z in [" +
                                                    num(z_lo) + ", " + num(z_hi) + "] mm)"
                                              : std::string()) +
                       ": allowed paths outside the magnet (plane above its top face or radius > R)");
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

// Positions (and, when normals != nullptr, unit normals) of every probe at every theta, magnet frame.
Eigen::Matrix3Xd probe_paths_at_rad(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_rad,
                                    Eigen::Matrix3Xd* normals = nullptr) {
  const auto M = theta_rad.size();
  const auto K = static_cast<Eigen::Index>(setup.array.size());
  const MountKinematics kin(mount, setup.plane_z_mm, setup.magnet_height_mm);
  const std::vector<Eigen::Vector3d> fixed = fixed_probe_positions(setup, kin);
  Eigen::Matrix3Xd p(3, M * K);
  if (normals) normals->resize(3, M * K);
  for (Eigen::Index m = 0; m < M; ++m) {
    const Eigen::Vector3d n = normals ? kin.direction_to_magnet(kin.n_fixed, theta_rad[m]) : Eigen::Vector3d();
    for (Eigen::Index k = 0; k < K; ++k) {
      p.col(m * K + k) = kin.point_to_magnet(fixed[static_cast<std::size_t>(k)], theta_rad[m]);
      if (normals) normals->col(m * K + k) = n;
    }
  }
  return p;
}

// The pipeline at rotor angles theta_rad (theta_deg: the same angles in degrees, as reported).
AngleErrorResult angle_error_at_rad(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                                    const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& theta_rad) {
  // 1. Validate the setup, the mount, the source's ability to serve a tilt and
  //    (exact field) that no path enters the magnet.
  validate_setup(setup, mount);
  check_source_serves_tilt(field, mount);
  if (const auto* exact = dynamic_cast<const AnalyticField*>(&field))
    check_paths_outside_magnet(*exact, setup, mount);

  // 2. All probe positions, then one batch field evaluation (OpenMP inside).
  //    No tilt: every normal is z, so the reading is Bz (cheaper kernel).
  //    A tilt: reading n.B from the full vector.
  const auto M = theta_rad.size();
  const auto K = static_cast<Eigen::Index>(setup.array.size());
  Eigen::VectorXd B;
  if (!mount.tilted()) {
    B = field.Bz_T(probe_paths_at_rad(setup, mount, theta_rad));
  } else {
    Eigen::Matrix3Xd normals;
    const Eigen::Matrix3Xd p = probe_paths_at_rad(setup, mount, theta_rad, &normals);
    const Eigen::Matrix3Xd Bv = field.B_T(p);
    B = (Bv.array() * normals.array()).colwise().sum().transpose();
  }

  // 3. Channels, signal chain, angle and error per theta.
  const SignalChain::Applied chain = setup.chain.applied();
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
    chain(ch_cos, ch_sin);
    const double phi_rad = std::atan2(ch_sin, ch_cos);
    res.eps_deg[m] = wrap_deg(rad_to_deg(phi_rad - theta_rad[m]));
    if (!std::isfinite(res.eps_deg[m]))
      throw ComputeError(field.name() + " field gave a non-finite angle at theta = " + num(theta_deg[m]) +
                         " deg");
  }
  return res;
}

}  // namespace

Eigen::Matrix3Xd probe_normals(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_deg) {
  Eigen::Matrix3Xd normals;
  probe_paths_at_rad(setup, mount, theta_deg * (kPi / 180.0), &normals);
  return normals;
}

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
