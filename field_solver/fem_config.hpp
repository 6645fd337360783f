// Configuration of the FEM: [mesh], [fem], [grid], [shaft] keys (declared once,
// here) and their translation into the solver's structs.
#pragma once
#include <vector>

#include "core/config.hpp"
#include "geometry.hpp"
#include "fields/grid.hpp"
#include "magnetostatic_solver.hpp"

namespace magenc::fem {

// The FEM's own keys (without common_keys()).
std::vector<KeySpec> fem_keys();
// common_keys() + fem_keys(): the schema of solve_field.
std::vector<KeySpec> solve_field_schema();

struct FemSettings {
  DomainSpec domain;
  SolverOptions solver;
  GridData plane;  // sensing-plane grid (dims[2] == 1, at z_s; no values)
  GridData box;    // 3-D box around the plane (no values)
  double plane_z_mm = 0;  // z_s
  bool write_mesh_vtu = false;  // output.mesh_vtu: write mesh.vtu (fem:DIR and ParaView need it)
  bool compress = false;        // output.compress: zlib-compressed VTK blocks
};

// Reads and validates; InputError names the key (degenerate geometry,
// zone/box outside the domain, ...).
FemSettings fem_settings_from_config(const Config& cfg);

}  // namespace magenc::fem
