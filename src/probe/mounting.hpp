// Mounting kinematics (docs/physics.md, "Mounting kinematics" and "Beyond the five
// offsets"). Frames: the magnet frame has the magnet centred at the origin (top
// face z = +L/2); the rotor frame turns with the magnet; the sensor (fixed)
// frame has the rotation axis as z.
//   * static eccentricity s = (sx, sy): sensor centre off its nominal position c0
//     (sensor.center_mm, default the rotation axis): the die centre is c0 + s;
//   * dynamic eccentricity d = (dx, dy): magnet centre off the axis (rotor frame);
//   * air-gap offset dz: sensing plane at z_s + dz;
//   * sensor tilt (a = tilt_x_deg, b = tilt_y_deg): the sensor turns about its
//     centre c = (sx, sy, z_s + dz) by Rs = Ry(b) Rx(a); probe k sits at
//     c + Rs (p_k, 0) and reads n.B with n = Rs (0, 0, 1);
//   * magnet tilt (g = magnet_tilt_deg, psi = magnet_tilt_azimuth_deg): in the
//     rotor frame the magnet is turned by g about u = (-sin psi, cos psi, 0)
//     through the pivot P = (0, 0, -L/2) (centre of its bottom face), then
//     shifted by d: a rotor-frame point r maps to the magnet frame as
//     q = Rt^T (r - d - P) + P, a direction n as Rt^T n.
// Probe k at rotor angle theta: fixed-frame position/normal, then Rz(-theta)
// into the rotor frame, then into the magnet frame as above. With all tilts zero
// this is q_k(theta) = Rot(-theta) (p_k + s) - d at height z_s + dz.
#pragma once
#include <Eigen/Core>

#include "core/config.hpp"
#include "core/defaults.hpp"

namespace magenc {

struct Mount {
  double sx_mm = 0, sy_mm = 0;       // static eccentricity (sensor centre), sensor frame
  double dx_mm = 0, dy_mm = 0;       // dynamic eccentricity (magnet centre), rotor frame
  double dz_mm = 0;                  // air-gap offset, + = farther from the magnet
  double tilt_x_deg = 0;             // sensor tilt a about x (applied first)
  double tilt_y_deg = 0;             // sensor tilt b about y (applied second, fixed axes)
  double magnet_tilt_deg = 0;        // magnet tilt g on the shaft (about the bottom-face centre)
  double magnet_tilt_azimuth_deg = 0;// azimuth psi towards which the magnet's top leans (rotor frame)

  // Reads mount.sx_mm .. dz_mm, tilt_x_deg, tilt_y_deg, magnet_tilt_deg, magnet_tilt_azimuth_deg.
  static Mount from_config(const Config& cfg);
  // The [mount] keys from_config reads (the air gap's temperature drift is Environment::keys()).
  static std::vector<KeySpec> keys();
  // Finite values; |tilts| <= kMaxTilt_deg (InputError naming the key otherwise).
  void validate() const;
  // Largest in-plane distance a probe at radius r0 can reach from the magnet
  // axis: r0 + |s| + |d| (five offsets; tilts not included).
  double max_probe_radius_mm(double r0_mm) const;
  bool sensor_tilted() const { return tilt_x_deg != 0.0 || tilt_y_deg != 0.0; }
  bool magnet_tilted() const { return magnet_tilt_deg != 0.0; }
  bool tilted() const { return sensor_tilted() || magnet_tilted(); }

  static constexpr double kMaxTilt_deg = 45.0;  // allowed |tilt| (sensor and magnet)
};

// The rigid motions of a mount, precomputed (rotation matrices).
struct MountKinematics {
  Eigen::Matrix3d Rs = Eigen::Matrix3d::Identity();  // sensor tilt Ry(b) Rx(a)
  Eigen::Matrix3d RtT = Eigen::Matrix3d::Identity(); // transpose of the magnet tilt Rt
  Eigen::Vector3d c_mm = Eigen::Vector3d::Zero();    // sensor centre (cx + sx, cy + sy, z_s + dz), fixed frame
  Eigen::Vector3d d_mm = Eigen::Vector3d::Zero();    // (dx, dy, 0), rotor frame
  Eigen::Vector3d P_mm = Eigen::Vector3d::Zero();    // pivot (0, 0, -L/2)
  Eigen::Vector3d n_fixed = Eigen::Vector3d::UnitZ();// probe normal Rs (0,0,1), fixed frame
  bool magnet_tilted = false;                        // false: RtT is the identity (skipped)

  // plane_z_mm: z_s (magnet frame); magnet_height_mm: L (pivot of the magnet tilt); center_mm: the die
  // centre's nominal position (sensor.center_mm; the static offsets add to it).
  MountKinematics(const Mount& m, double plane_z_mm, double magnet_height_mm,
                  const Eigen::Vector2d& center_mm = Eigen::Vector2d::Zero());
  // Fixed-frame position of the probe with nominal sensor-frame position (px, py).
  Eigen::Vector3d fixed_position_mm(double px_mm, double py_mm) const;
  // Fixed-frame point / direction -> magnet frame at rotor angle theta.
  Eigen::Vector3d point_to_magnet(const Eigen::Vector3d& fixed_mm, double theta_rad) const;
  Eigen::Vector3d direction_to_magnet(const Eigen::Vector3d& fixed_dir, double theta_rad) const;
  // The same with cos(theta), sin(theta) given (several points at one theta share them).
  Eigen::Vector3d point_to_magnet(const Eigen::Vector3d& fixed_mm, double cos_theta, double sin_theta) const;
  Eigen::Vector3d direction_to_magnet(const Eigen::Vector3d& fixed_dir, double cos_theta, double sin_theta) const;
};

// Rotations (right-handed), angles in radians.
Eigen::Matrix3d rot_x(double a_rad);
Eigen::Matrix3d rot_y(double a_rad);
Eigen::Matrix3d rot_z(double a_rad);
// Rotation by angle_rad about the unit axis u (Rodrigues).
Eigen::Matrix3d rot_axis(const Eigen::Vector3d& u, double angle_rad);

// Position (magnet frame, mm) of a probe with nominal sensor-frame position
// (px, py) at rotor angle theta_rad, on a sensing plane at height plane_z_mm.
// Full kinematics (tilts included); magnet_height_mm is L (magnet-tilt pivot).
Eigen::Vector3d probe_position_mm(const Mount& m, double px_mm, double py_mm, double theta_rad,
                                  double plane_z_mm, double magnet_height_mm = defaults::kMagnetHeight_mm);

// Normal of the sensing element in the magnet frame at theta: Rt^T Rz(-theta) Rs (0,0,1).
Eigen::Vector3d probe_normal(const Mount& m, double theta_rad);

}  // namespace magenc
