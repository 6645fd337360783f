// Assembly of the scalar-potential system (scaled units, units.hpp):
//   Int_Omega mu_r grad psi . grad v dV + Int_Gamma (2/r) psi v dS = Int_Omega Br . grad v dV
// psi in T*mm, Br in T (remanence vector, zero outside the magnet), r = |x| in mm
// on the truncation sphere Gamma (dipole Robin condition d psi/dn = -2 psi/r).
#pragma once
#include <Eigen/Sparse>
#include <vector>

#include "fe_space.hpp"
#include "mesh.hpp"

namespace magenc::fem {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Stiffness matrix K (num_dofs^2, symmetric): volume term with per-cell mu_r
// (n_tets), plus the Robin term on mesh.boundary_faces when robin is true
// (air, mu_r = 1, there). Element work runs on `threads` OpenMP threads
// (thread-local triplets, merged in element order): the result is bitwise
// independent of the thread count.
SparseMatrix assemble_stiffness(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                bool robin, int threads);

// Load vector f_i = Int Br . grad N_i (T*mm^2) with per-cell Br (3 x n_tets, T).
Eigen::VectorXd assemble_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::Matrix3Xd& br_cell);

// Dofs on the outer boundary (vertices and, for P2, edges of boundary faces), sorted.
std::vector<int> boundary_dofs(const TetMesh& mesh, const FeSpace& space);

// psi = 0 on the given dofs: rows and columns replaced by the identity, rhs by 0.
void apply_zero_dirichlet(SparseMatrix& K, Eigen::VectorXd& f, const std::vector<int>& dofs);

}  // namespace magenc::fem
