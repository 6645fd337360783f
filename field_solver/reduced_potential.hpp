// Reduced scalar potential (fem.potential = reduced): the field of the magnet
// in free space, H_s = B_exact - Br_s (AnalyticField, exact), is known; the
// FEM solves only for the reaction of the permeable parts,
//   H = H_s - grad phi,  B = mu_r H + Br_s,
//   Int mu_r grad phi . grad v + Int_Gamma (2/r) phi v = Int (mu_r - 1) H_s . grad v,
// (from div B = 0 and div(H_s + Br_s) = 0). The load lives only in cells with
// mu_r != 1 (magnet with its recoil permeability, shaft), so with mu_r = 1
// everywhere phi = 0 and the FE field is the exact field. The dipole Robin
// condition applies to phi (the reaction decays like a dipole too).
// Not suited to very permeable parts (shaft mu_r ~ 1000): there H ~ 0 while
// H_s is not, so grad phi ~ H_s cancels (total/reduced split: not implemented;
// use fem.potential = total with a shaft).
#pragma once
#include <Eigen/Core>

#include "fe_space.hpp"
#include "fields/analytic_field.hpp"
#include "mesh.hpp"

namespace magenc::fem {

// f_i = Int (mu_r - 1) H_s . grad N_i (T*mm^2) over the cells with mu_r != 1
// (5-point degree-3 tet rule; cells in parallel, summed in cell order).
Eigen::VectorXd assemble_reaction_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                      const AnalyticField& source);

}  // namespace magenc::fem
