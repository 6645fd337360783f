// The one regular-grid type of magenc and its .vti files: B sampled on nodes
// (i, j, k) at origin_mm + (i*hx, j*hy, k*hz), values stored with i fastest,
// then j, then k (index i + nx*(j + ny*k), VTK image data order). dims[2] == 1
// is a plane at z = origin_mm.z. The FEM's sensing-plane and box grids
// (field_solver/solve/fem_config), the grids grid: sources interpolate
// (fields/grid_field) and field tables of other tools are all GridData; a grid
// that only describes where to sample has no values yet.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace magenc {

// Regular grid of B samples (magnet frame, mm; T).
struct GridData {
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();   // position of node (0,0,0)
  Eigen::Vector3d spacing_mm = Eigen::Vector3d::Ones();  // node spacing hx, hy, hz (> 0; hz unused when nz == 1)
  std::array<int, 3> dims{1, 1, 1};      // nodes per axis nx, ny, nz
  std::vector<double> Bx_T, By_T, Bz_T;  // node values (size nx*ny*nz); Bx_T/By_T empty when only Bz is known
  std::string source;                    // file name or description, used in messages

  std::size_t nodes() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
  bool has_B() const { return !Bx_T.empty(); }
  bool is_plane() const { return dims[2] == 1; }
  // Node positions (3 x nodes(), mm) in storage order.
  Eigen::Matrix3Xd points_mm() const;
  // Stores B (3 x nodes(), T) as Bx_T, By_T, Bz_T.
  void set_B(const Eigen::Matrix3Xd& B_T);
  // Throws InputError for inconsistent sizes, non-positive spacing, non-finite values.
  void validate() const;
  // A grid without values from [min, max] per axis and a step (mm); max is
  // rounded down to a whole number of steps.
  static GridData from_range(const Eigen::Vector3d& min_mm, const Eigen::Vector3d& max_mm,
                             const Eigen::Vector3d& step_mm);
};

// Reads VTK XML image data (.vti): point arrays `B` (3 comp., T) and/or `Bz`
// (T); Bz is taken from `Bz` when present, else from B's z component.
// InputError when the file is missing/unreadable, has neither array, or has a
// non-identity direction matrix; the file's structure (extent limits, one piece
// covering the whole extent, data block headers, closing tags) is checked
// before VTK reads it.
GridData read_grid_vti(const std::filesystem::path& file);

// How write_grid_vti stores the arrays: VTK XML appended data, raw binary by
// default (solve_field's plane.vti and box.vti).
struct VtiFormat {
  bool compress = false;  // zlib blocks (solve_field's output.compress)
  bool base64 = false;    // base64-encoded appended data (table_to_vti's files)
  bool with_bz = true;    // scalar array `Bz` before `B` (solve_field's box.vti has `B` only)
};

// Writes point arrays `Bz` (format.with_bz) and, when known, `B` (T, 3), atomically
// (temporary name, then rename). A plane is written with z spacing 1.
void write_grid_vti(const std::filesystem::path& file, const GridData& grid, const VtiFormat& format = {});

}  // namespace magenc
