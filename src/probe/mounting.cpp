#include "probe/mounting.hpp"

#include <cmath>
#include <string>

#include "core/errors.hpp"

namespace magenc {

Mount Mount::from_config(const Config& cfg) {
  Mount m;
  m.sx_mm = cfg.real("mount.sx_mm");
  m.sy_mm = cfg.real("mount.sy_mm");
  m.dx_mm = cfg.real("mount.dx_mm");
  m.dy_mm = cfg.real("mount.dy_mm");
  m.dz_mm = cfg.real("mount.dz_mm");
  m.validate();
  return m;
}

void Mount::validate() const {
  const std::pair<const char*, double> values[] = {
      {"mount.sx_mm", sx_mm}, {"mount.sy_mm", sy_mm}, {"mount.dx_mm", dx_mm},
      {"mount.dy_mm", dy_mm}, {"mount.dz_mm", dz_mm}, {"mount.tilt_x_deg", tilt_x_deg},
      {"mount.tilt_y_deg", tilt_y_deg}};
  for (const auto& [name, v] : values)
    if (!std::isfinite(v))
      throw InputError(std::string(name) + " is not a finite number: allowed a finite value");
  if (tilt_x_deg != 0.0 || tilt_y_deg != 0.0)
    throw InputError("mount.tilt_x_deg/tilt_y_deg: sensor tilt is not implemented yet: allowed 0");
}

double Mount::max_probe_radius_mm(double r0_mm) const {
  return r0_mm + std::hypot(sx_mm, sy_mm) + std::hypot(dx_mm, dy_mm);
}

Eigen::Vector3d probe_position_mm(const Mount& m, double px_mm, double py_mm, double theta_rad,
                                  double plane_z_mm) {
  const double c = std::cos(theta_rad), s = std::sin(theta_rad);
  const double X = px_mm + m.sx_mm, Y = py_mm + m.sy_mm;
  return {c * X + s * Y - m.dx_mm, -s * X + c * Y - m.dy_mm, plane_z_mm + m.dz_mm};
}

Eigen::Vector3d probe_normal(const Mount& /*m*/, double /*theta_rad*/) { return {0.0, 0.0, 1.0}; }

}  // namespace magenc
