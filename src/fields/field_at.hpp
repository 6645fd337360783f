// B at a list of points from any field source (docs/interfaces.md "field_at"; the
// field_at executable and the Python module's magenc.field_at).
#pragma once
#include <Eigen/Core>

#include "fields/field_source.hpp"
#include "fields/magnet.hpp"

namespace magenc {

// B (T, 3 x N) at points_mm (3 x N, magnet frame, mm). Every point must be one
// the source can give: InputError naming the first one (1-based index and
// coordinates) that is not finite, lies on the analytic magnet's surface
// (on_magnet_surface) or that the source refuses (outside a grid or
// table, off a 2-D plane, outside a FE mesh). Sources that know only Bz (the
// linear model) are refused too: field_at gives the full vector.
// Relative distance (times the magnet's larger size, R or L/2) within which a point counts as on the
// magnet's surface (a ring's bore face included), where B jumps and is not defined.
inline constexpr double kSurfaceTolerance = 1e-12;
bool on_magnet_surface(const Magnet& magnet, const Vec3& p_mm);

Eigen::Matrix3Xd field_at(const FieldSource& field, const Eigen::Matrix3Xd& points_mm);

}  // namespace magenc
