// Mounting kinematics (physics.md): where probe k sits in the magnet frame at
// rotor angle theta, for static eccentricity s (sensor off the rotation axis),
// dynamic eccentricity d (magnet off the axis) and air-gap offset dz:
//   q_k(theta) = Rot(-theta) * (p_k + s) - d,   z = z_s + dz.
// Tilt of the sensor is designed in (fields present) but must be zero until
// implemented: a non-zero tilt is rejected with an InputError.
#pragma once
#include <Eigen/Core>

#include "core/config.hpp"

namespace magenc {

struct Mount {
  double sx_mm = 0, sy_mm = 0;  // static eccentricity (sensor centre), sensor frame
  double dx_mm = 0, dy_mm = 0;  // dynamic eccentricity (magnet centre), magnet frame
  double dz_mm = 0;             // air-gap offset, + = farther from the magnet
  double tilt_x_deg = 0;        // sensor tilt about x (not yet implemented: must be 0)
  double tilt_y_deg = 0;        // sensor tilt about y (not yet implemented: must be 0)

  static Mount from_config(const Config& cfg);
  void validate() const;  // finite values; tilt == 0
  // Largest in-plane distance a probe at radius r0 can reach from the magnet
  // axis: r0 + |s| + |d|.
  double max_probe_radius_mm(double r0_mm) const;
};

// Position (magnet frame, mm) of a probe with nominal sensor-frame position
// (px, py) at rotor angle theta_rad, on a sensing plane at height plane_z_mm.
Eigen::Vector3d probe_position_mm(const Mount& m, double px_mm, double py_mm, double theta_rad,
                                  double plane_z_mm);

// Normal of the sensing element in the magnet frame at theta (for tilt; (0,0,1) now).
Eigen::Vector3d probe_normal(const Mount& m, double theta_rad);

}  // namespace magenc
