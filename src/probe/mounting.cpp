#include "probe/mounting.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "core/defaults.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

Mount Mount::from_config(const Config& cfg) {
  Mount m;
  m.sx_mm = cfg.real("mount.sx_mm");
  m.sy_mm = cfg.real("mount.sy_mm");
  m.dx_mm = cfg.real("mount.dx_mm");
  m.dy_mm = cfg.real("mount.dy_mm");
  m.dz_mm = cfg.real("mount.dz_mm");
  m.tilt_x_deg = cfg.real("mount.tilt_x_deg");
  m.tilt_y_deg = cfg.real("mount.tilt_y_deg");
  m.magnet_tilt_deg = cfg.real("mount.magnet_tilt_deg");
  m.magnet_tilt_azimuth_deg = cfg.real("mount.magnet_tilt_azimuth_deg");
  m.validate();
  return m;
}

void Mount::validate() const {
  require_finite({{"mount.sx_mm", sx_mm},
                  {"mount.sy_mm", sy_mm},
                  {"mount.dx_mm", dx_mm},
                  {"mount.dy_mm", dy_mm},
                  {"mount.dz_mm", dz_mm},
                  {"mount.tilt_x_deg", tilt_x_deg},
                  {"mount.tilt_y_deg", tilt_y_deg},
                  {"mount.magnet_tilt_deg", magnet_tilt_deg},
                  {"mount.magnet_tilt_azimuth_deg", magnet_tilt_azimuth_deg}});
  const std::pair<const char*, double> tilts[] = {
      {"mount.tilt_x_deg", tilt_x_deg}, {"mount.tilt_y_deg", tilt_y_deg}, {"mount.magnet_tilt_deg", magnet_tilt_deg}};
  for (const auto& [name, v] : tilts)
    if (std::abs(v) > kMaxTilt_deg)
      throw InputError(std::string(name) + " = " + num(v) + " is out of range: allowed [-" + num(kMaxTilt_deg) +
                       ", " + num(kMaxTilt_deg) + "] deg");
}

double Mount::max_probe_radius_mm(double r0_mm) const {
  return r0_mm + std::hypot(sx_mm, sy_mm) + std::hypot(dx_mm, dy_mm);
}

Eigen::Matrix3d rot_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, c, -s, 0, s, c;
  return R;
}

Eigen::Matrix3d rot_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d R;
  R << c, 0, s, 0, 1, 0, -s, 0, c;
  return R;
}

Eigen::Matrix3d rot_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  return R;
}

Eigen::Matrix3d rot_axis(const Eigen::Vector3d& u, double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, u.normalized()).toRotationMatrix();
}

MountKinematics::MountKinematics(const Mount& m, double plane_z_mm, double magnet_height_mm,
                                 const Eigen::Vector2d& center_mm) {
  Rs = rot_y(deg_to_rad(m.tilt_y_deg)) * rot_x(deg_to_rad(m.tilt_x_deg));
  const double psi = deg_to_rad(m.magnet_tilt_azimuth_deg);
  RtT = rot_axis(Eigen::Vector3d(-std::sin(psi), std::cos(psi), 0.0), deg_to_rad(m.magnet_tilt_deg)).transpose();
  if (!m.magnet_tilted()) RtT.setIdentity();  // exactly, so that zero tilt reproduces the five-offset kinematics
  if (!m.sensor_tilted()) Rs.setIdentity();
  magnet_tilted = m.magnet_tilted();
  c_mm = Eigen::Vector3d(m.sx_mm, m.sy_mm, plane_z_mm + m.dz_mm);
  if (!center_mm.isZero(0.0)) c_mm.head<2>() += center_mm;  // on the axis: s itself, bit for bit
  d_mm = Eigen::Vector3d(m.dx_mm, m.dy_mm, 0.0);
  P_mm = Eigen::Vector3d(0.0, 0.0, -0.5 * magnet_height_mm);
  n_fixed = Rs.col(2);
}

Eigen::Vector3d MountKinematics::fixed_position_mm(double px_mm, double py_mm) const {
  return c_mm + Rs * Eigen::Vector3d(px_mm, py_mm, 0.0);
}

Eigen::Vector3d MountKinematics::point_to_magnet(const Eigen::Vector3d& f, double theta_rad) const {
  // Rz(-theta) f, written out as in docs/physics.md (x = cos X + sin Y, y = -sin X + cos Y).
  const double c = std::cos(theta_rad), s = std::sin(theta_rad);
  const Eigen::Vector3d r(c * f.x() + s * f.y(), -s * f.x() + c * f.y(), f.z());
  if (!magnet_tilted) return r - d_mm;  // the five-offset kinematics, bit for bit
  return RtT * (r - d_mm - P_mm) + P_mm;
}

Eigen::Vector3d MountKinematics::direction_to_magnet(const Eigen::Vector3d& f, double theta_rad) const {
  const double c = std::cos(theta_rad), s = std::sin(theta_rad);
  const Eigen::Vector3d r(c * f.x() + s * f.y(), -s * f.x() + c * f.y(), f.z());
  return magnet_tilted ? Eigen::Vector3d(RtT * r) : r;
}

// The same with cos and sin of theta given (the in-plane and sensing-area paths share them per theta).
Eigen::Vector3d MountKinematics::point_to_magnet(const Eigen::Vector3d& f, double c, double s) const {
  // Rz(-theta) f, written out as in docs/physics.md (x = cos X + sin Y, y = -sin X + cos Y).
  const Eigen::Vector3d r(c * f.x() + s * f.y(), -s * f.x() + c * f.y(), f.z());
  if (!magnet_tilted) return r - d_mm;  // the five-offset kinematics, bit for bit
  return RtT * (r - d_mm - P_mm) + P_mm;
}

Eigen::Vector3d MountKinematics::direction_to_magnet(const Eigen::Vector3d& f, double c, double s) const {
  const Eigen::Vector3d r(c * f.x() + s * f.y(), -s * f.x() + c * f.y(), f.z());
  return magnet_tilted ? Eigen::Vector3d(RtT * r) : r;
}

Eigen::Vector3d probe_position_mm(const Mount& m, double px_mm, double py_mm, double theta_rad,
                                  double plane_z_mm, double magnet_height_mm) {
  const MountKinematics k(m, plane_z_mm, magnet_height_mm);
  return k.point_to_magnet(k.fixed_position_mm(px_mm, py_mm), theta_rad);
}

Eigen::Vector3d probe_normal(const Mount& m, double theta_rad) {
  const MountKinematics k(m, 0.0, 0.0);  // directions do not depend on the plane or the pivot
  return k.direction_to_magnet(k.n_fixed, theta_rad);
}

std::vector<KeySpec> Mount::keys() {
  const double big = defaults::kMaxLength_mm;
  return {
      real_key("mount.sx_mm", 0.0, -big, big, "mm", "static eccentricity x (sensor off axis)"),
      real_key("mount.sy_mm", 0.0, -big, big, "mm", "static eccentricity y"),
      real_key("mount.dx_mm", 0.0, -big, big, "mm", "dynamic eccentricity x (magnet off axis)"),
      real_key("mount.dy_mm", 0.0, -big, big, "mm", "dynamic eccentricity y"),
      real_key("mount.dz_mm", 0.0, -big, big, "mm", "air-gap offset (+ = farther from the magnet)"),
      real_key("mount.tilt_x_deg", 0.0, -45, 45, "deg", "sensor tilt a about x (first; Rs = Ry(b) Rx(a))"),
      real_key("mount.tilt_y_deg", 0.0, -45, 45, "deg", "sensor tilt b about y (second, fixed axes)"),
      real_key("mount.magnet_tilt_deg", 0.0, -45, 45, "deg",
               "magnet tilt g on the shaft, about the centre of its bottom face"),
      real_key("mount.magnet_tilt_azimuth_deg", 0.0, -360, 360, "deg",
               "azimuth psi (rotor frame) towards which the tilted magnet's top leans"),
  };
}

}  // namespace magenc
