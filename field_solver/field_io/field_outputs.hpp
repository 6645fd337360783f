// The outputs of a solve (docs/interfaces.md): plane.vti, box.vti, solve.json and,
// when asked (output.mesh_vtu), mesh.vtu; for pictures of a solve with parts, the
// solid bodies alone (bodies.vtu) and B on any grid (e.g. the axis plane y = 0).
#pragma once
#include <filesystem>
#include <string>

#include "field_solver/solve/fem_config.hpp"
#include "fields/grid.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"

namespace magenc::fem {

// Peak resident set size of this process so far (MiB, getrusage).
double peak_rss_mib();

// Evaluates the grids and writes plane.vti, box.vti, solve.json and, with
// output.mesh_vtu, mesh.vtu into dir (an AtomicDir's
// temporary directory). config_json: the configuration in use (echoed).
void write_field_outputs(const std::filesystem::path& dir, const FemSettings& settings, const MagnetostaticSolver& solver,
                         const std::string& config_json);

// The solid bodies of a solve: the cells of the magnet (region 1) and of every [[parts]] body
// (region >= kRegionPartFirst) as linear tetrahedra on their corner nodes, with mesh.vtu's arrays
// (point psi as stored, cell B, region, mu_r, Br). The air and the refinement zone are left out, so
// the file stays small (the parts' shapes for ParaView, e.g. their outlines on a slice).
void write_bodies_vtu(const std::filesystem::path& file, const MagnetostaticSolver& solver);

// B of the solve (T) at every node of `grid` (a grid without values: GridData::from_range), written
// as .vti with the point array `B` only. ComputeError when B is not finite.
void write_B_grid_vti(const std::filesystem::path& file, GridData grid, const MagnetostaticSolver& solver);

}  // namespace magenc::fem
