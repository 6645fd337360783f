// The FE solution as VTK (mesh.vtu: coordinates in mm, B in T, psi in T*mm).
// Array names are the stable contract of docs/interfaces.md. The grids (plane.vti,
// box.vti) are written by fields/grid.hpp's write_grid_vti.
#pragma once
#include <filesystem>

#include "field_solver/fe/fe_solution.hpp"

namespace magenc::fem {

// mesh.vtu: VTK_TETRA (P1) or VTK_QUADRATIC_TETRA (P2, psi at edge nodes kept);
// point data `psi` (T*mm); cell data `B` (T, 3), `region` (int), `mu_r`, `Br` (T, 3).
// Files are VTK XML with raw binary appended data (no base64); compress:
// zlib-compressed blocks (smaller, several times slower to write).
void write_solution_vtu(const std::filesystem::path& path, const FeSolution& sol, const Eigen::Matrix3Xd& B_cell_T,
                        bool compress = false);

// Reads a mesh.vtu written by write_solution_vtu back into a solution.
// Throws InputError naming the file and what is missing.
FeSolution read_solution_vtu(const std::filesystem::path& path);

}  // namespace magenc::fem
