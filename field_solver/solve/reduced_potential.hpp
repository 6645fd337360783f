// Reduced scalar potential (fem.potential = reduced): the field of the magnet
// in free space, H_s = B_exact - Br_s (AnalyticField, exact), is known; the
// FEM solves only for the reaction of the permeable parts,
//   H = H_s - grad phi,  B = mu_r H + Br_s,
//   Int mu_r grad phi . grad v + Int_Gamma (2/r) phi v = Int (mu_r - 1) H_s . grad v,
// (from div B = 0 and div(H_s + Br_s) = 0). The load lives only in cells with
// mu_r != 1 (magnet with its recoil permeability, shaft), so with mu_r = 1
// everywhere phi = 0 and the FE field is the exact field. The dipole Robin
// condition applies to phi (the reaction decays like a dipole too).
//
// Not alone for very permeable parts (shaft mu_r ~ 1000): there H ~ 0 while
// H_s is not, so grad phi ~ H_s cancels and the FE error of grad phi is
// multiplied by mu_r. The total/reduced split (fem.potential = split) keeps
// the reduced phi outside the permeable region T (the shaft) and the total
// potential psi inside it, H = -grad psi in T:
//
//   Interface G = boundary of T (the shaft is closed, away from the magnet and
//   the truncation sphere). The magnet's field has a scalar potential outside
//   the magnet, H_s = -grad phi_s (surface charges), so the total potential of
//   the region R outside T is phi + phi_s, and continuity of tangential H is
//   psi = phi + phi_s on G. Nodal dof transform: one continuous FE function u
//   with u = psi in T and on G, u = phi at the dofs of R off G; in the cells of
//   R, phi_h = u - g, g = phi_s at the dofs on G (0 elsewhere).
//   Weak form of div B = 0 with v continuous (the variations of psi and phi
//   agree on G), B = mu_r(-grad psi) in T, mu_r(H_s - grad phi) + Br_s in R:
//     Int_T mu_r grad psi.grad v + Int_R mu_r grad phi.grad v + Robin(phi)
//       = Int_R (mu_r H_s + Br_s).grad v - Int_sphere v B_s.n
//       = Int_R (mu_r - 1) H_s.grad v + Int_G v H_s.n_R        (div B_s = 0 in R)
//       = Int_R (mu_r - 1) H_s.grad v - Int_T H_s.grad v        (div H_s = 0 in T)
//   (n_R: the normal out of R on G). With phi_h = u - g:
//     K u = f_R + f_T + K_R g,  K the usual stiffness (both regions),
//     f_R_i = Int_R (mu_r - 1) H_s.grad N_i,  f_T_i = -Int_T H_s.grad N_i,
//     (K_R g)_i = Int_R mu_r grad g_h.grad N_i  (only R cells touching G).
//   phi_s is needed on G only, up to one constant (a constant added to g on a
//   connected G adds the same constant to psi in T and leaves phi and B
//   unchanged): it is integrated along mesh edges inside T from a root dof,
//   phi_s(b) = phi_s(a) - Int_a^b H_s.dl (4-point Gauss-Legendre; H_s is
//   smooth in T, which does not contain the magnet). A potential odd across a
//   symmetry plane (quadrant solve) is 0 on that plane: its dofs are the roots.
//   With mu_r = 1 in T the solution is phi ~ 0 (only the interpolation error
//   of psi = phi_s in T remains); no T: the reduced potential exactly.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "field_solver/fe/fe_space.hpp"
#include "fields/analytic_field.hpp"
#include "field_solver/mesh/geometry.hpp"
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

// f_i = Int (mu_r - 1) H_s . grad N_i (T*mm^2) over the cells with mu_r != 1
// (5-point degree-3 tet rule; cells in parallel, summed in cell order).
Eigen::VectorXd assemble_reaction_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                      const AnalyticField& source);

// Split potential: 1 for the cells that carry the total potential (the shaft's and
// those of the permeable [[parts]]: mu_r != 1 or a B-H curve, whatever the curve's start
// value), 0 elsewhere. A B-H part must be total from the start: its mu_r changes while
// the nonlinear iteration runs, and a reduced cell's load assumes a fixed mu_r.
std::vector<char> total_potential_cells(const TetMesh& mesh, const DomainSpec& domain);

// phi_s (T*mm) at the interface dofs (dofs of both a total and a reduced cell), 0 elsewhere; up to
// a constant, or 0 on the plane x_odd_axis = 0 when the potential is odd across it (0 or 1; -1: none).
// ComputeError when the interface is not connected through the total cells.
Eigen::VectorXd interface_source_potential(const FeSpace& space, const std::vector<char>& total,
                                           const AnalyticField& source, int odd_axis);

// The load of the split potential: f_R + f_T + K_R g (see above); g = interface_phi_s.
Eigen::VectorXd assemble_split_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                   const std::vector<char>& total, const AnalyticField& source,
                                   const Eigen::VectorXd& interface_phi_s);

}  // namespace magenc::fem
