#include "fields/field_at.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "fields/magnet.hpp"

namespace magenc {

namespace {
std::string point_label(const Eigen::Matrix3Xd& p, Eigen::Index j) {
  return "point " + std::to_string(j + 1) + " (x_mm = " + num(p(0, j)) + ", y_mm = " + num(p(1, j)) +
         ", z_mm = " + num(p(2, j)) + ")";
}
}  // namespace

bool on_magnet_surface(const Magnet& m, const Vec3& p) {
  const double R = m.radius_mm, half = m.top_z_mm();
  const double tol = kSurfaceTolerance * std::max(R, half);
  const double r = std::hypot(p.x(), p.y()), az = std::abs(p.z());
  const bool curved = std::abs(r - R) <= tol && az <= half + tol;
  const double Ri = m.inner_radius_mm;
  const bool ends = std::abs(az - half) <= tol && r <= R + tol && (Ri == 0.0 || r >= Ri - tol);
  const bool bore = Ri > 0.0 && std::abs(r - Ri) <= tol && az <= half + tol;
  return curved || ends || bore;
}

Eigen::Matrix3Xd field_at(const FieldSource& field, const Eigen::Matrix3Xd& p) {
  if (!field.gives_full_vector())
    throw InputError("--field " + field.name() +
                     " gives Bz on the sensing plane only: allowed analytic, fem:DIR, grid:FILE.vti, table:FILE "
                     "(3-D grids and tables give B, 2-D ones the plane only)");
  for (Eigen::Index j = 0; j < p.cols(); ++j)
    if (!p.col(j).allFinite()) throw InputError(point_label(p, j) + " is not finite: allowed finite coordinates (mm)");
  if (const Magnet* magnet = field.exact_magnet())
    for (Eigen::Index j = 0; j < p.cols(); ++j)
      if (on_magnet_surface(*magnet, Vec3(p.col(j))))
        throw InputError(point_label(p, j) + " lies on the magnet's surface (radius " + num(magnet->radius_mm) +
                         " mm" + (magnet->is_ring() ? ", inner radius " + num(magnet->inner_radius_mm) + " mm" : std::string()) +
                         ", |z| = " + num(magnet->top_z_mm()) + " mm), where B jumps: allowed points inside or "
                         "outside the magnet");
  try {
    return field.B_T(p);  // batch (parallel): any refused point throws
  } catch (const InputError&) {
    // Name the first refused point in input order, whichever thread failed first.
    for (Eigen::Index j = 0; j < p.cols(); ++j) {
      try {
        (void)field.B_T(Vec3(p.col(j)));
      } catch (const InputError& e) {
        throw InputError(point_label(p, j) + ": " + e.what());
      }
    }
    throw;
  }
}

}  // namespace magenc
