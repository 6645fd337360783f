// Facts of an FE solve for summaries and tables: what solve.json records
// (SolvedFieldDir::facts) and what an in-process solve reports (solve_fem_field).
#pragma once

namespace magenc {

struct FeSolveFacts {
  int order = 0;
  long elements = 0, dofs = 0, iterations = 0;
  double h_magnet_mm = 0, h_zone_mm = 0;  // target tet edge lengths (TetGen volume bounds)
  double h_core_mm = 0;                   // core cylinder about the plane; 0 = no core
  double mu_r = 0;                        // magnet.mu_r of the solve
  double t_total_s = 0;                   // mesh + assemble + solve + post-processing
  double plane_step_mm = 0;               // plane grid spacing
  int symmetry_order = 1;                 // mesh symmetry D_N (1: a whole-domain mesh, 2: mirror planes x, y)
};

}  // namespace magenc
