// Grid field source: B sampled on a regular grid (the plane.vti / box.vti of
// solve_field, or any VTK image data with point arrays `B` [T, 3 components]
// and/or `Bz` [T]), interpolated at arbitrary points.
//
// Grid layout (VTK image data): node (i, j, k) sits at
//   origin_mm + (i*hx, j*hy, k*hz), i < nx, j < ny, k < nz,
// values stored with i fastest, then j, then k (index i + nx*(j + ny*k)).
// nz == 1 is a 2-D plane at z = origin_mm.z: it serves only that height
// (dz = 0); a point more than kPlaneTolerance_mm off it is an InputError that
// says to use box.vti. nz >= 2 is a 3-D box (air-gap offsets).
//
// Interpolation modes (tensor products over x, y and, for boxes, z):
//   nearest  value of the nearest node (what the original study did). Error
//            O(h), and the error depends on where a point falls in its cell:
//            on a probe circle this is NOT a function of the angle alone and
//            creates spurious harmonics (the study's 4th).
//   linear   bi-/trilinear: exact for fields linear in each coordinate,
//            error O(h^2), continuous.
//   cubic    4-point Lagrange per axis (nodes i-1..i+2 around the cell of the
//            point): exact for polynomials of degree <= 3 in each coordinate,
//            error O(h^4); continuous (first derivative jumps by O(h^3) at
//            cell faces). In the first and last cell of an axis the 4-node
//            stencil is shifted inward (one-sided, same order), so it always
//            stays inside the grid.
// A point is served iff it lies in the grid's closed extent (up to a relative
// rounding tolerance of 1e-9 of a cell); otherwise every evaluation throws an
// InputError naming the grid's source, the point and the grid extent. There is
// no extrapolation, silent or otherwise.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "fields/field_source.hpp"
#include "fields/grid.hpp"

namespace magenc {

enum class Interp { Nearest, Linear, Cubic };

// Parses "nearest", "linear", "cubic"; InputError naming `what` otherwise.
Interp parse_interp(const std::string& s, const std::string& what = "--interp");
std::string interp_name(Interp mode);

// Samples `field` at the nodes of a grid (batch, OpenMP). With bz_only, only
// Bz is evaluated and stored.
GridData sample_grid(const FieldSource& field, const Vec3& origin_mm, const Vec3& spacing_mm,
                     const std::array<int, 3>& dims, bool bz_only = false);

class GridField final : public FieldSource {
 public:
  // Points closer than this to a 2-D grid's plane count as on it.
  static constexpr double kPlaneTolerance_mm = 1e-6;

  // Throws InputError if the grid has too few nodes along an interpolated axis
  // for the mode (linear: 2, cubic: 4) or fails GridData::validate().
  // name: what name() returns ("grid" for .vti grids, "table" for field tables).
  GridField(GridData grid, Interp mode, std::string name = "grid");
  // Reads `file` with read_grid_vti.
  static std::shared_ptr<GridField> from_file(const std::filesystem::path& file, Interp mode);

  std::string name() const override { return name_; }
  // A 3-D box with the B vector serves tilted probes; a 2-D plane (or a grid with Bz only) does not.
  bool gives_full_vector() const override { return !grid_.is_plane() && grid_.has_B(); }
  Vec3 B_T(const Vec3& p_mm) const override;
  double Bz_T(const Vec3& p_mm) const override;
  // Batch versions: one bounds pass, then a mode-specialized loop (OpenMP), no
  // virtual call per sample. Throw InputError for the first point outside.
  Eigen::Matrix3Xd B_T(const Eigen::Matrix3Xd& p_mm) const override;
  Eigen::VectorXd Bz_T(const Eigen::Matrix3Xd& p_mm) const override;

  Interp mode() const { return mode_; }
  const GridData& grid() const { return grid_; }
  // True when p_mm can be served (inside the extent; on the plane for 2-D).
  bool contains(const Vec3& p_mm) const;
  // "x in [a, b] mm, y in [c, d] mm, z = e mm" (or z in [..] for boxes).
  std::string extent_text() const;

 private:
  [[noreturn]] void throw_outside(const Vec3& p_mm) const;
  void require_B() const;

  GridData grid_;
  Interp mode_;
  std::string name_;  // "grid" or "table"

};

}  // namespace magenc
