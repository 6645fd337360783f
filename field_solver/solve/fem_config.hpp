// Configuration of the FEM: [mesh], [fem], [grid], [shaft] keys (declared once,
// here) and their translation into the solver's structs.
#pragma once
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "field_solver/mesh/geometry.hpp"
#include "fields/grid.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"

namespace magenc::fem {

// The FEM's own keys (without common_keys()).
std::vector<KeySpec> fem_keys();
// common_keys() + fem_keys(): the schema of solve_field.
std::vector<KeySpec> solve_field_schema();

// [[parts]] of the configuration (material resolved to mu_r; geometry checked by DomainSpec::validate).
std::vector<PartSpec> parts_from_config(const Config& cfg);
// A part's material text (mu_r:VALUE, bh:FILE or a named material) as mu_r (a B-H curve: its initial
// slope, the curve held to iron_max_mu_r as read_bh_csv); InputError naming `what` and the allowed forms.
double part_material_mu_r(const std::string& material, const std::string& what, double iron_max_mu_r = kBhIronMaxMuR);
// The named materials ("a, b, ...") and the source of one ("" when unknown).
std::string part_material_names();
std::string part_material_source(const std::string& name);
// The B-H file of a material: bh:FILE -> FILE; a named material with a curve -> materials/NAME_bh.csv
// (in the working directory if there, else in the source tree); empty for a linear material.
std::filesystem::path part_material_bh_file(const std::string& material);

struct FemSettings {
  DomainSpec domain;
  SolverOptions solver;
  GridData plane;  // sensing-plane grid (dims[2] == 1, at z_s; no values)
  GridData box;    // 3-D box around the plane (no values)
  double plane_z_mm = 0;  // z_s
  bool write_mesh_vtu = false;  // output.mesh_vtu: write mesh.vtu (fem:DIR and ParaView need it)
  bool compress = false;        // output.compress: zlib-compressed VTK blocks
};

// Where the plane and box grids lie in x and y: about the die centre (sensor.center_mm,
// default [0, 0]). The grid.* windows are offsets from the centre; a side that does not reach
// the probe circle (sensor.r0_mm; 0 for the point array) moves out to r0 + kGridMarginAroundProbes_mm.
inline constexpr double kGridMarginAroundProbes_mm = 1.0;
struct SensorWindow {
  std::array<double, 2> centre_mm{0.0, 0.0};
  double r0_mm = 0;
  double lo(double offset_mm, int axis) const {
    return centre_mm[static_cast<size_t>(axis)] + (offset_mm <= -r0_mm ? offset_mm : -r0_mm - kGridMarginAroundProbes_mm);
  }
  double hi(double offset_mm, int axis) const {
    return centre_mm[static_cast<size_t>(axis)] + (offset_mm >= r0_mm ? offset_mm : r0_mm + kGridMarginAroundProbes_mm);
  }
};
SensorWindow sensor_window(const Config& cfg);

// Reads and validates; InputError names the key (degenerate geometry,
// zone/box outside the domain, ...).
FemSettings fem_settings_from_config(const Config& cfg);

}  // namespace magenc::fem
