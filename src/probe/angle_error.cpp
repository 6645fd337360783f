#include "probe/angle_error.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/magnet.hpp"

namespace magenc {

namespace {

// Setup and mount must describe a usable probe path (see angle_error()).
void validate_setup(const ProbeSetup& setup, const Mount& mount) {
  const bool point = reads_in_plane(setup.principle);
  if (point != setup.array.is_point())
    throw InputError("sensor.array = '" + setup.array.name + "' does not apply to sensor.principle = " +
                     principle_name(setup.principle) + ": allowed " +
                     (point ? "point" : "two, diff4, ring:N"));
  setup.area.validate();
  setup.window.validate();
  if (!point && !(std::isfinite(setup.r0_mm) && setup.r0_mm > 0))
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
  setup.chain.validate_for(setup.principle);
  setup.env.validate_for(setup.principle);
  if (mount.magnet_tilted() && !(std::isfinite(setup.magnet_height_mm) && setup.magnet_height_mm > 0))
    throw InputError("magnet.height_mm = " + num(setup.magnet_height_mm) +
                     " (pivot of the magnet tilt) is out of range: allowed (0, 1000] mm");
  if (!setup.center_mm.allFinite())
    throw InputError("sensor.center_mm is not finite: allowed finite [x, y] in mm");
  const ChipOrientation& o = setup.orientation;
  if (!(o.direction == 1 || o.direction == -1) || !(std::isfinite(o.zero_deg) && std::abs(o.zero_deg) <= 360.0))
    throw InputError("sensor.direction = " + std::to_string(o.direction) + ", sensor.zero_deg = " + num(o.zero_deg) +
                     ": allowed direction 1 or -1 and zero_deg in [-360, 360] deg");
  // A probe circle about the axis must not pass over it; a circle centred elsewhere (sensor.center_mm)
  // is the chip's business (resolve_orientation and the winding checks).
  const double offsets_mm = std::hypot(mount.sx_mm, mount.sy_mm) + std::hypot(mount.dx_mm, mount.dy_mm);
  if (!point && setup.center_mm.isZero(0.0) && setup.r0_mm - offsets_mm <= 0)
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

// The in-plane principles need Bx, By.
void check_source_serves_principle(const FieldSource& field, const ProbeSetup& setup) {
  if (!reads_in_plane(setup.principle) || field.gives_full_vector()) return;
  throw InputError("sensor.principle = " + principle_name(setup.principle) +
                   " reads the in-plane field Bx, By, but the " + field.name() +
                   " field source gives only Bz on a plane: allowed bz with this source (use analytic, fem:DIR, "
                   "a 3-D box.vti grid or a table with Bx, By)");
}

// Nominal sensor-frame position of probe k: r0 (cos b_k, sin b_k), or the die centre for the point array.
Eigen::Vector2d nominal_xy_mm(const ProbeSetup& setup, std::size_t k) {
  if (setup.array.is_point()) return Eigen::Vector2d::Zero();
  const double b_rad = deg_to_rad(setup.array.angle_deg[k]);
  return {setup.r0_mm * std::cos(b_rad), setup.r0_mm * std::sin(b_rad)};
}

// Fixed-frame probe positions (sensor tilt included) and their rotor-frame
// circles: radius rho_k about the axis, height z_k.
std::vector<Eigen::Vector3d> fixed_probe_positions(const ProbeSetup& setup, const MountKinematics& kin) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t k = 0; k < setup.array.size(); ++k) {
    if (setup.array.is_point()) {
      out.push_back(kin.fixed_position_mm(0.0, 0.0));
      continue;
    }
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
void check_paths_outside_magnet(const Magnet& mag, const ProbeSetup& setup, const Mount& mount) {
  if (mount.magnet_tilted() && std::abs(setup.magnet_height_mm - mag.height_mm) > 1e-9 * mag.height_mm)
    throw InputError("magnet tilt pivot: the probe setup's magnet height " + num(setup.magnet_height_mm) +
                     " mm differs from the analytic field's magnet.height_mm = " + num(mag.height_mm) +
                     " mm: allowed the same magnet");
  const double sg = std::abs(std::sin(deg_to_rad(mount.magnet_tilt_deg)));
  const double cg = std::cos(deg_to_rad(mount.magnet_tilt_deg));
  const double half = mag.top_z_mm(), L = mag.height_mm;
  // A sensing area reaches half its diagonal from each probe (conservative: the test uses the centre's circle).
  const double reach = L * sg + (setup.area.point() ? 0.0 : setup.area.plate_mm * std::sqrt(0.5));
  const double r_hull = mag.radius_mm + reach;
  // A ring's bore: a path that stays within Ri - reach of the magnet's axis passes through the air inside.
  const double ri_hull = mag.is_ring() ? mag.inner_radius_mm - reach : -1.0;
  const double z_lo = mount.magnet_tilted() ? -half - mag.radius_mm * sg : -half;
  const double z_hi = mount.magnet_tilted() ? -half + L * cg + mag.radius_mm * sg : half;
  const MountKinematics kin(mount, setup.plane_z_mm, mag.height_mm, setup.center_mm);
  const std::vector<Eigen::Vector3d> fixed = fixed_probe_positions(setup, kin);
  const double d_mm = std::hypot(mount.dx_mm, mount.dy_mm);
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    const double z_mm = fixed[k].z();
    if (z_mm > z_hi || z_mm < z_lo) continue;  // this probe's path passes above (or below) the magnet
    const double rho_mm = std::hypot(fixed[k].x(), fixed[k].y());
    const double closest_mm = std::abs(rho_mm - d_mm), farthest_mm = rho_mm + d_mm;
    if (closest_mm <= r_hull && farthest_mm >= ri_hull)
      throw InputError("probe path enters the magnet: at z = " + num(z_mm) + " mm (mount.dz_mm = " +
                       num(mount.dz_mm) + ") probe " + std::to_string(k) + " comes within " +
                       num(closest_mm) + " mm of the magnet's axis, magnet radius " + num(mag.radius_mm) +
                       (mag.is_ring() ? " mm, inner radius " + num(mag.inner_radius_mm) : std::string()) +
                       " mm, half height " + num(half) + " mm" +
                       (mount.magnet_tilted() ? " (tilted magnet: hull radius " + num(r_hull) + " mm, z in [" +
                                                    num(z_lo) + ", " + num(z_hi) + "] mm)"
                                              : std::string()) +
                       ": allowed paths outside the magnet (plane above its top face, radius > R or within a ring's bore)");
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
  const MountKinematics kin(mount, setup.plane_z_mm, setup.magnet_height_mm, setup.center_mm);
  const std::vector<Eigen::Vector3d> fixed = fixed_probe_positions(setup, kin);
  Eigen::Matrix3Xd p(3, M * K);
  if (normals) normals->resize(3, M * K);
  for (Eigen::Index m = 0; m < M; ++m) {
    const double c = std::cos(theta_rad[m]), s = std::sin(theta_rad[m]);  // once per theta, for every probe
    const Eigen::Vector3d n = normals ? kin.direction_to_magnet(kin.n_fixed, c, s) : Eigen::Vector3d();
    for (Eigen::Index k = 0; k < K; ++k) {
      p.col(m * K + k) = kin.point_to_magnet(fixed[static_cast<std::size_t>(k)], c, s);
      if (normals) normals->col(m * K + k) = n;
    }
  }
  return p;
}

// Sampling points of the probes with a sensing area (or of the in-plane spot): 3 x (M*K*Q) positions,
// column (m*K + k)*Q + q = node q of probe k at theta_m (Q = 1 for points: then the columns of
// probe_paths_at_rad), and the per-theta directions in the magnet frame: the die normal n and, for the
// in-plane principles, the die axes x' = Rs x, y' = Rs y (3 x M each).
struct AreaSamples {
  Eigen::Matrix3Xd p_mm;
  Eigen::Matrix3Xd n, ex, ey;
  std::vector<double> w;  // Q weights (sum 1)
};

AreaSamples area_samples(const ProbeSetup& setup, const Mount& mount, const Eigen::VectorXd& theta_rad,
                         bool normals, bool axes) {
  AreaSamples a;
  std::vector<double> u, v;
  setup.area.nodes(u, v, a.w);
  const auto M = theta_rad.size();
  const auto K = static_cast<Eigen::Index>(setup.array.size());
  const auto Q = static_cast<Eigen::Index>(a.w.size());
  const MountKinematics kin(mount, setup.plane_z_mm, setup.magnet_height_mm, setup.center_mm);
  std::vector<Eigen::Vector3d> fixed;  // K*Q fixed-frame points
  for (Eigen::Index k = 0; k < K; ++k) {
    const Eigen::Vector2d c = nominal_xy_mm(setup, static_cast<std::size_t>(k));
    for (Eigen::Index q = 0; q < Q; ++q)
      fixed.push_back(kin.fixed_position_mm(c.x() + u[static_cast<std::size_t>(q)], c.y() + v[static_cast<std::size_t>(q)]));
  }
  a.p_mm.resize(3, M * K * Q);
  if (normals) a.n.resize(3, M);
  if (axes) {
    a.ex.resize(3, M);
    a.ey.resize(3, M);
  }
  const Eigen::Vector3d x_fixed = kin.Rs.col(0), y_fixed = kin.Rs.col(1);
  for (Eigen::Index m = 0; m < M; ++m) {
    const double c = std::cos(theta_rad[m]), s = std::sin(theta_rad[m]);  // once per theta
    for (Eigen::Index j = 0; j < K * Q; ++j)
      a.p_mm.col(m * K * Q + j) = kin.point_to_magnet(fixed[static_cast<std::size_t>(j)], c, s);
    if (normals) a.n.col(m) = kin.direction_to_magnet(kin.n_fixed, c, s);
    if (axes) {
      a.ex.col(m) = kin.direction_to_magnet(x_fixed, c, s);
      a.ey.col(m) = kin.direction_to_magnet(y_fixed, c, s);
    }
  }
  return a;
}

// The bz readings (M*K, column m*K + k) of probes with a sensing area: the weighted mean of n.B (Bz
// without a tilt) over each probe's nodes.
Eigen::VectorXd bz_area_readings(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                                 const Eigen::VectorXd& theta_rad) {
  const bool tilted = mount.tilted();
  const AreaSamples a = area_samples(setup, mount, theta_rad, tilted, false);
  const auto M = theta_rad.size();
  const auto K = static_cast<Eigen::Index>(setup.array.size());
  const auto Q = static_cast<Eigen::Index>(a.w.size());
  Eigen::VectorXd comp;
  if (!tilted) {
    comp = field.Bz_T(a.p_mm);
  } else {
    const Eigen::Matrix3Xd Bv = field.B_T(a.p_mm);
    comp.resize(Bv.cols());
    for (Eigen::Index m = 0; m < M; ++m)
      for (Eigen::Index j = 0; j < K * Q; ++j) comp[m * K * Q + j] = a.n.col(m).dot(Bv.col(m * K * Q + j));
  }
  Eigen::VectorXd B = Eigen::VectorXd::Zero(M * K);
  for (Eigen::Index i = 0; i < M * K; ++i)
    for (Eigen::Index q = 0; q < Q; ++q) B[i] += a.w[static_cast<std::size_t>(q)] * comp[i * Q + q];
  return B;
}

// The in-plane components (M x 2: b1 = x'.B, b2 = y'.B, T) at the spot, mean over its sensing area.
Eigen::MatrixXd inplane_readings(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                                 const Eigen::VectorXd& theta_rad) {
  const AreaSamples a = area_samples(setup, mount, theta_rad, false, true);
  const auto M = theta_rad.size();
  const auto Q = static_cast<Eigen::Index>(a.w.size());
  const Eigen::Matrix3Xd Bv = field.B_T(a.p_mm);
  Eigen::MatrixXd b(M, 2);
  for (Eigen::Index m = 0; m < M; ++m) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (Eigen::Index q = 0; q < Q; ++q) mean += a.w[static_cast<std::size_t>(q)] * Bv.col(m * Q + q);
    b(m, 0) = a.ex.col(m).dot(mean);
    b(m, 1) = a.ey.col(m).dot(mean);
  }
  return b;
}

// The error (deg) of the electrical angle psi_deg at theta_deg with the chip's direction and zero:
// wrap(direction psi + turns zero - turns theta) / turns (turns = 2 for amr, whose error lies in (-90, 90]).
double oriented_error_deg(const ChipOrientation& o, double psi_deg, double theta_deg, int turns) {
  return wrap_deg(o.direction * psi_deg + turns * (o.zero_deg - theta_deg)) / turns;
}

// The pipeline at rotor angles theta_rad (theta_deg: the same angles in degrees, as reported).
// check_winding (uniform samples of a whole turn, in-plane principles): the field direction at the spot,
// atan2(-b2, -b1), must turn once per turn.
AngleErrorResult angle_error_at_rad(const FieldSource& field, const ProbeSetup& setup, const Mount& mount_20C,
                                    const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& theta_rad,
                                    bool check_winding = false) {
  if (setup.orientation.any_auto())
    return angle_error_at_rad(field, resolve_orientation(field, setup), mount_20C, theta_deg, theta_rad, check_winding);
  // 0. The environment: the mount (air gap) at the temperature; the chain's offsets below.
  setup.env.validate_for(setup.principle);
  const Mount mount = setup.env.mount_at_temperature(mount_20C);
  // 1. Validate the setup, the mount, the source's ability to serve a tilt and
  //    the principle, and (exact field) that no path enters the magnet.
  validate_setup(setup, mount);
  check_source_serves_tilt(field, mount);
  check_source_serves_principle(field, setup);
  if (const Magnet* magnet = field.exact_magnet()) check_paths_outside_magnet(*magnet, setup, mount);

  const auto M = theta_rad.size();
  const auto K = static_cast<Eigen::Index>(setup.array.size());
  const SignalChain::Applied chain = setup.env.chain_at_temperature(setup.chain).applied(setup.principle);
  // The environment's part of the readings: the magnet's field times Br(T)/Br, plus the stray field's
  // constant part of each reading (the sensor does not turn).
  const bool env = !setup.env.neutral();
  const double br_scale = setup.env.br_scale();
  std::vector<double> stray_T;
  if (env) {
    std::vector<Eigen::Vector2d> xy;
    for (std::size_t k = 0; k < setup.array.size(); ++k) xy.push_back(nominal_xy_mm(setup, k));
    const MountKinematics kin(mount, setup.plane_z_mm, setup.magnet_height_mm, setup.center_mm);
    stray_T = stray_readings_T(setup.env.stray, kin, xy, setup.area, reads_in_plane(setup.principle));
  }
  const bool identity = setup.orientation.identity();
  AngleErrorResult res;
  res.theta_deg = theta_deg;
  res.orientation = setup.orientation;
  res.eps_deg.resize(M);
  res.probe_B_T.resize(M, K);
  res.channels.resize(M, 2);
  auto check_finite = [&](Eigen::Index m) {
    if (!std::isfinite(res.eps_deg[m]))
      throw ComputeError(field.name() + " field gave a non-finite angle at theta = " + num(theta_deg[m]) +
                         " deg");
  };

  if (setup.principle == SensorPrinciple::Bz) {
    // 2. All probe positions, then one batch field evaluation (OpenMP inside).
    //    No tilt: every normal is z, so the reading is Bz (cheaper kernel).
    //    A tilt: reading n.B from the full vector. A sensing area: the mean over its nodes.
    Eigen::VectorXd B;
    if (!setup.area.point()) {
      B = bz_area_readings(field, setup, mount, theta_rad);
    } else if (!mount.tilted()) {
      B = field.Bz_T(probe_paths_at_rad(setup, mount, theta_rad));
    } else {
      Eigen::Matrix3Xd normals;
      const Eigen::Matrix3Xd p = probe_paths_at_rad(setup, mount, theta_rad, &normals);
      const Eigen::Matrix3Xd Bv = field.B_T(p);
      B = (Bv.array() * normals.array()).colwise().sum().transpose();
    }
    if (env)
      for (Eigen::Index i = 0; i < B.size(); ++i) B[i] = br_scale * B[i] + stray_T[static_cast<std::size_t>(i % K)];

    // 3. Channels, signal chain, angle and error per theta.
    for (Eigen::Index m = 0; m < M; ++m) {
      double ch_cos = 0, ch_sin = 0;
      for (Eigen::Index k = 0; k < K; ++k) {
        const double b = B[m * K + k];
        res.probe_B_T(m, k) = b;
        ch_cos += setup.array.w_cos[k] * b;
        ch_sin += setup.array.w_sin[k] * b;
      }
      chain(ch_cos, ch_sin);
      res.channels(m, 0) = ch_cos;
      res.channels(m, 1) = ch_sin;
      const double phi_rad = std::atan2(ch_sin, ch_cos);
      if (setup.pole_pairs != 1)  // incremental reading of a multipole track: wrap(phi_e - p theta) / p
        res.eps_deg[m] = oriented_error_deg(setup.orientation, rad_to_deg(phi_rad), theta_deg[m], setup.pole_pairs);
      else
        res.eps_deg[m] = identity ? wrap_deg(rad_to_deg(phi_rad - theta_rad[m]))
                                  : oriented_error_deg(setup.orientation, rad_to_deg(phi_rad), theta_deg[m], 1);
      check_finite(m);
    }
    // Field window: the peak |reading| of each probe over the turn; min and max over the probes.
    const Eigen::VectorXd peak_T = res.probe_B_T.cwiseAbs().colwise().maxCoeff().transpose();
    res.field_min_mT = peak_T.minCoeff() * 1e3;
    res.field_max_mT = peak_T.maxCoeff() * 1e3;
  } else {
    // 2. The in-plane components at the spot (mean over its area), from the full vector.
    res.inplane_B_T = inplane_readings(field, setup, mount, theta_rad);
    if (env) {
      res.inplane_B_T *= br_scale;
      res.inplane_B_T.col(0).array() += stray_T[0];
      res.inplane_B_T.col(1).array() += stray_T[1];
    }
    // 3. Channels by principle, signal chain, angle (electrical angle psi; amr: phi = psi/2) and error.
    const int turns = reading_turns(setup);
    double winding_deg = 0, field_prev = 0, field_first = 0;
    for (Eigen::Index m = 0; m < M; ++m) {
      const double b1 = res.inplane_B_T(m, 0), b2 = res.inplane_B_T(m, 1);
      const double mag = std::hypot(b1, b2);
      res.probe_B_T(m, 0) = mag;
      double u_c = -b1, u_s = -b2;  // inplane: the field points against M above a diametric magnet
      if (setup.principle == SensorPrinciple::Xmr) {
        u_c /= mag;
        u_s /= mag;
      } else if (setup.principle == SensorPrinciple::Amr) {
        const double alpha = std::atan2(-b2, -b1);
        u_c = std::cos(2.0 * alpha);
        u_s = std::sin(2.0 * alpha);
      }
      chain(u_c, u_s);
      res.channels(m, 0) = u_c;
      res.channels(m, 1) = u_s;
      const double psi_deg = rad_to_deg(std::atan2(u_s, u_c));
      // eps = wrap(phi - theta); amr: phi = psi/2 modulo 180, eps = wrap(psi - 2 theta)/2 in (-90, 90].
      res.eps_deg[m] = identity ? wrap_deg(psi_deg - turns * theta_deg[m]) / turns
                                : oriented_error_deg(setup.orientation, psi_deg, theta_deg[m], turns);
      check_finite(m);
      // The field's own direction (before the channels and the chain) must turn once per turn.
      const double field_deg = rad_to_deg(std::atan2(-b2, -b1));
      if (m == 0) field_first = field_deg;
      else winding_deg += wrap_deg(field_deg - field_prev);
      field_prev = field_deg;
    }
    if (check_winding && M > 1) {
      winding_deg += wrap_deg(field_first - field_prev);
      if (std::abs(winding_deg - 360.0 * setup.pole_pairs * setup.orientation.direction) > 180.0)
        throw InputError("the field direction at the sensing spot turns " + num(winding_deg / 360.0) +
                         " times per turn, not " +
                         (setup.pole_pairs == 1 ? std::string("once") : std::to_string(setup.pole_pairs) + " times") +
                         (setup.orientation.direction == 1 ? "" : " backwards") +
                         " as sensor.direction = " + std::to_string(setup.orientation.direction) +
                         " expects (mount |s| + |d| = " +
                         num(std::hypot(mount.sx_mm, mount.sy_mm) + std::hypot(mount.dx_mm, mount.dy_mm)) +
                         " mm, the spot too far off the axis): allowed mounts where the in-plane field turns with "
                         "the rotor, sensor.direction -1 (or auto) where it turns backwards");
    }
    const Eigen::VectorXd mag = res.probe_B_T.col(0);
    res.field_min_mT = mag.minCoeff() * 1e3;
    res.field_max_mT = mag.maxCoeff() * 1e3;
  }
  res.in_window = setup.window.contains(res.field_min_mT, res.field_max_mT);
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
  setup.speed.validate();
  if (setup.speed.acts())
    throw InputError("speed.rpm = " + num(setup.speed.rpm) +
                     " needs the uniform samples of a whole turn, not arbitrary angles: allowed 0 here");
  return angle_error_at_rad(field, setup, mount, theta_deg, theta_deg * (kPi / 180.0));
}

AngleErrorResult angle_error(const FieldSource& field, const ProbeSetup& setup, const Mount& mount) {
  validate_setup(setup, mount);  // before the sample grid is built from setup.steps
  AngleErrorResult res = angle_error_at_rad(field, setup, mount, uniform_theta_deg(setup.steps),
                                            uniform_theta_rad(setup.steps), /*check_winding=*/true);
  // 4. At a speed: the chip's timing on the channels of the whole turn (probe/speed.hpp).
  setup.speed.validate();
  if (setup.speed.acts()) {
    // The timing chain recomputes the angle from the channels as an on-axis chip reads it (direction 1,
    // zero 0, no trim); an oriented chip at speed is refused rather than read without its orientation.
    if (!res.orientation.identity())
      throw InputError("speed.rpm = " + num(setup.speed.rpm) +
                       " with sensor.direction, sensor.zero_deg or sensor.gain_trim set: allowed speed.rpm = 0 for an "
                       "oriented chip (side-shaft, off-axis), or the default orientation at speed");
    setup.speed.apply(res.channels, res.eps_deg, reading_turns(setup));
    for (Eigen::Index m = 0; m < res.eps_deg.size(); ++m)
      if (!std::isfinite(res.eps_deg[m]))
        throw ComputeError(field.name() + " field gave a non-finite angle at speed, theta = " +
                           num(res.theta_deg[m]) + " deg");
  }
  // 5. Spectrum of the uniform samples.
  res.spectrum = spectrum_of(res.eps_deg, setup.multipole ? setup.pole_pairs : 0);
  return res;
}

Spectrum error_spectrum(const FieldSource& field, const ProbeSetup& setup, const Mount& mount) {
  return angle_error(field, setup, mount).spectrum;
}

namespace {
// At the nominal mount no sensing point (probe or spot centre) may lie in the configured magnet's material.
void check_nominal_points_outside_magnet(const Config& cfg, const ProbeSetup& s) {
  if (!cfg.has("magnet.radius_mm") || !cfg.has("magnet.inner_radius_mm")) return;
  const Magnet magnet = Magnet::from_config(cfg);
  for (std::size_t k = 0; k < s.array.size(); ++k) {
    const Eigen::Vector2d p = s.center_mm + nominal_xy_mm(s, k);
    if (!magnet.contains_mm(p.x(), p.y(), s.plane_z_mm)) continue;
    throw InputError("sensor.center_mm = [" + num(s.center_mm.x()) + ", " + num(s.center_mm.y()) +
                     "], sensor.r0_mm = " + num(s.r0_mm) + ", sensor.plane_height_mm = " +
                     num(cfg.real("sensor.plane_height_mm")) + " put sensing point " + std::to_string(k + 1) + " at (" +
                     num(p.x()) + ", " + num(p.y()) + ", " + num(s.plane_z_mm) + ") mm in the magnet (magnet.radius_mm = " +
                     num(magnet.radius_mm) + ", magnet.inner_radius_mm = " + num(magnet.inner_radius_mm) +
                     ", magnet.height_mm = " + num(magnet.height_mm) + "): allowed points outside its material");
  }
}

// Winding of atan2(u_s, u_c) over the rows of a whole turn (turns, signed).
double channel_winding_turns(const Eigen::MatrixXd& ch) {
  double w = 0;
  const Eigen::Index M = ch.rows();
  for (Eigen::Index m = 0; m < M; ++m) {
    const Eigen::Index n = (m + 1) % M;
    w += wrap_deg(rad_to_deg(std::atan2(ch(n, 1), ch(n, 0)) - std::atan2(ch(m, 1), ch(m, 0))));
  }
  return w / 360.0;
}

// |first-harmonic amplitude| of column c over a uniform turn at `turns` per turn.
double harmonic_amplitude_of(const Eigen::MatrixXd& ch, Eigen::Index c, int turns) {
  double re = 0, im = 0;
  const Eigen::Index M = ch.rows();
  for (Eigen::Index m = 0; m < M; ++m) {
    const double a = 2.0 * kPi * turns * static_cast<double>(m) / static_cast<double>(M);
    re += ch(m, c) * std::cos(a);
    im += ch(m, c) * std::sin(a);
  }
  return 2.0 * std::hypot(re, im) / static_cast<double>(M);
}
}  // namespace

ProbeSetup resolve_orientation(const FieldSource& field, const ProbeSetup& setup) {
  const ChipOrientation& o = setup.orientation;
  if (!o.any_auto()) return setup;
  ProbeSetup nominal = setup;
  nominal.chain = SignalChain{};
  nominal.env = Environment{};
  nominal.orientation = ChipOrientation{};
  const int turns = reading_turns(setup);
  const Eigen::VectorXd th_deg = uniform_theta_deg(setup.steps), th_rad = th_deg * (kPi / 180.0);
  const AngleErrorResult raw = angle_error_at_rad(field, nominal, Mount{}, th_deg, th_rad);
  const double winding = channel_winding_turns(raw.channels);
  if (std::abs(std::abs(winding) - turns) > 0.5)
    throw InputError("the sensor's angle winds " + num(winding) + " times per turn at the nominal mount (sensor.center_mm, "
                     "sensor.plane_height_mm): allowed placements where it turns with the rotor, for sensor.direction, "
                     "sensor.zero_deg or sensor.gain_trim = auto");
  ProbeSetup out = setup;
  out.orientation = ChipOrientation{};
  out.orientation.direction = o.direction_auto ? (winding > 0 ? 1 : -1) : o.direction;
  out.orientation.zero_deg = o.zero_auto ? 0.0 : o.zero_deg;
  nominal.orientation.direction = out.orientation.direction;
  if (o.gain_auto) {
    const double trim = harmonic_amplitude_of(raw.channels, 0, turns) / harmonic_amplitude_of(raw.channels, 1, turns);
    out.chain.gain_mismatch = (1.0 + setup.chain.gain_mismatch) * trim - 1.0;
    nominal.chain.gain_mismatch = trim - 1.0;
  }
  if (o.zero_auto) {
    nominal.orientation.zero_deg = 0.0;
    const AngleErrorResult trimmed = angle_error_at_rad(field, nominal, Mount{}, th_deg, th_rad);
    double c = 0, sn = 0;
    for (Eigen::Index m = 0; m < trimmed.eps_deg.size(); ++m) {
      const double a = deg_to_rad(turns * trimmed.eps_deg[m]);  // amr: the error is modulo 180 deg
      c += std::cos(a);
      sn += std::sin(a);
    }
    out.orientation.zero_deg = -rad_to_deg(std::atan2(sn, c)) / turns;
  }
  return out;
}

ProbeSetup sensor_setup_from_config(const Config& cfg, const std::string& array_spec, const std::string& what) {
  ProbeSetup s;
  s.principle = parse_principle(cfg.str("sensor.principle"));
  std::string spec = array_spec;
  if (reads_in_plane(s.principle) && spec != "point") {
    const KeySpec* array_key = cfg.find("sensor.array");
    const std::string def = array_key ? array_key->default_value : "";
    if (what == "sensor.array" && spec == def) spec = "point";  // the default is not a choice
    else
      throw InputError(what + " = '" + array_spec + "' does not apply to sensor.principle = " +
                       principle_name(s.principle) + ": allowed point");
  } else if (!reads_in_plane(s.principle) && spec == "point") {
    throw InputError(what + " = 'point' does not apply to sensor.principle = bz: allowed two, diff4, ring:N");
  }
  check_principle_keys(cfg);  // after the array (named as given: --array or a study list), then the other keys
  s.array = ProbeArray::parse(spec, what);
  s.r0_mm = cfg.real("sensor.r0_mm");
  s.plane_z_mm = sensing_plane_z_mm(cfg);
  s.steps = static_cast<int>(cfg.integer("sensor.steps"));
  s.chain = SignalChain::from_config(cfg);
  s.chain.validate_for(s.principle);
  s.magnet_height_mm = cfg.real("magnet.height_mm");
  s.area.plate_mm = cfg.real("sensor.plate_mm");
  s.area.plate_points = static_cast<int>(cfg.integer("sensor.plate_points"));
  s.area.validate();
  s.window.min_mT = cfg.real("sensor.field_min_mT");
  s.window.max_mT = cfg.real("sensor.field_max_mT");
  s.window.validate();
  s.env = Environment::from_config(cfg);
  s.env.validate_for(s.principle);
  s.speed = SpeedChain::from_config(cfg);
  const std::vector<double> center = cfg.reals("sensor.center_mm");
  if (center.size() != 2)
    throw InputError("sensor.center_mm has " + std::to_string(center.size()) + " numbers: allowed [x, y] in mm");
  s.center_mm = {center[0], center[1]};
  s.orientation = ChipOrientation::from_config(cfg);
  apply_multipole_reading(cfg, s);
  check_nominal_points_outside_magnet(cfg, s);
  return s;
}

int reading_turns(const ProbeSetup& setup) { return electrical_turns(setup.principle) * setup.pole_pairs; }

void apply_multipole_reading(const Config& cfg, ProbeSetup& setup) {
  const std::string pattern = cfg.str("magnet.pattern");
  if (pattern != "axial_multipole" && pattern != "radial_multipole") return;
  const long p = cfg.integer("magnet.pole_pairs");
  if (p < 1)
    throw InputError("magnet.pattern = " + pattern + " with magnet.pole_pairs = " + std::to_string(p) +
                     " is out of range: allowed pole_pairs >= 1 for a multipole pattern");
  setup.pole_pairs = static_cast<int>(p);
  setup.multipole = true;
  if (setup.array.is_point()) return;
  const double Ri = cfg.real("magnet.inner_radius_mm"), R = cfg.real("magnet.radius_mm");
  if (!(setup.r0_mm >= Ri && setup.r0_mm <= R))
    throw InputError("sensor.r0_mm = " + num(setup.r0_mm) + " is not over the track of magnet.inner_radius_mm = " +
                     num(Ri) + ", magnet.radius_mm = " + num(R) + ": allowed inner_radius_mm <= r0_mm <= radius_mm");
  for (double& b : setup.array.angle_deg) b /= static_cast<double>(p);
}

}  // namespace magenc
