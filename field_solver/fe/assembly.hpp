// Assembly of the scalar-potential system (scaled units, units.hpp):
//   Int_Omega mu_r grad psi . grad v dV + Int_Gamma (2/r) psi v dS = Int_Omega Br . grad v dV
// psi in T*mm, Br in T (remanence vector, zero outside the magnet), r = |x| in mm
// on the truncation sphere Gamma (dipole Robin condition d psi/dn = -2 psi/r).
#pragma once
#include <Eigen/Sparse>
#include <vector>

#include "field_solver/fe/fe_space.hpp"
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Stiffness matrix K (num_dofs^2, symmetric): volume term with per-cell mu_r
// (n_tets), plus the Robin term on mesh.boundary_faces when robin is true
// (air, mu_r = 1, there). The CSR pattern is built from the cell dofs; element
// matrices are computed on `threads` OpenMP threads in chunks of cells and added
// row-wise, every entry summed in element order, then the Robin faces in face
// order: K is bitwise independent of the thread count, and equal to the sum of
// the cell_stiffness / robin_face_matrix contributions taken in that order.
// chunk_cells (>= 1) only sets the buffer size (chunk_cells * dofs_per_cell^2
// doubles; the default's 6.5 MB for P2 stays in cache) and not the result; tests
// vary it to cross chunk boundaries. Fast on meshes numbered for locality
// (reorder_for_locality: a chunk's cells share most of their rows).
// Element matrices are exact closed forms (cell_stiffness).
SparseMatrix assemble_stiffness(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                bool robin, int threads, int chunk_cells = 8192);

// Element stiffness of cell t, Int mu_r grad N_i . grad N_j dV, in the top-left
// dofs_per_cell block of Ke (local order of FeSpace::cell_dofs): the closed form
// K_ij = sum_{p<=q} V grad L_p . grad L_q W_ij,pq with constant weights W (the means
// of products of linear functions over the tet), exactly symmetric.
void cell_stiffness(const TetMesh& mesh, int order, int t, double mu_r, Eigen::Matrix<double, 10, 10>& Ke);

// Robin matrix Int (2/r) N_i N_j dS of boundary face f: fills dofs (3 for P1, 6 for
// P2: vertices, then edges) and the matching top-left block of Me; returns 3 or 6.
int robin_face_matrix(const TetMesh& mesh, const FeSpace& space, Eigen::Index f, int dofs[6],
                      Eigen::Matrix<double, 6, 6>& Me);

// Load vector f_i = Int Br . grad N_i (T*mm^2) with per-cell Br (3 x n_tets, T).
Eigen::VectorXd assemble_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::Matrix3Xd& br_cell);

// Dofs on the outer boundary (vertices and, for P2, edges of boundary faces), sorted.
std::vector<int> boundary_dofs(const TetMesh& mesh, const FeSpace& space);

// psi = 0 on the given dofs: rows and columns replaced by the identity, rhs by 0.
void apply_zero_dirichlet(SparseMatrix& K, Eigen::VectorXd& f, const std::vector<int>& dofs);

}  // namespace magenc::fem
