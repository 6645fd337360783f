// Nonlinear (B-H) parts of the total-potential system: the secant permeability
// per cell, the residual and its exact Jacobian for Newton's method.
//
// In a cell t of a part with a B-H curve the permeability is taken at the
// cell's centroid gradient g_t = grad psi(centroid) (T; mu0 H = -g there,
// total potential): s = |g_t|, H = s / mu0, mu_t(s) = B(H) / (mu0 H) = B(s / mu0) / s.
// Residual (the system MagnetostaticSolver solves, f independent of psi):
//   R(psi) = K(mu(psi)) psi - f,  K(mu) = sum_t mu_t K_t^1 (+ Robin),
// with K_t^1 the cell's stiffness at mu_r = 1. Its exact derivative:
//   dR_i/dpsi_j = K(mu)_ij + sum_t a_t u_i v_j,  u = K_t^1 psi (element vector),
//   v_j = G_j . g_t (G_j = grad N_j at the centroid),  a_t = mu_t'(s) / s
//   = (dB/dH / mu0 - mu_t) / s^2,
// a rank-one term per nonlinear cell. For P1 u = V v (grad psi is constant):
// the Jacobian is symmetric, K_t^1 with the differential permeability along
// g and the secant across it. For P2 the gradient varies inside the cell while
// mu_t is taken at the centroid: u != V v and the Jacobian is not symmetric
// (its Newton steps are solved with BiCGSTAB, not CG).
#pragma once
#include <Eigen/Core>
#include <vector>

#include "field_solver/fe/assembly.hpp"
#include "field_solver/mesh/bh_curve.hpp"
#include "field_solver/fe/fe_space.hpp"
#include "field_solver/mesh/geometry.hpp"
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

// The B-H curve of every cell (nullptr: linear cell), from the parts' region ids.
std::vector<const BhCurve*> cell_bh_curves(const DomainSpec& domain, const TetMesh& mesh);

// Secant relative permeability per cell: mu_linear where the cell has no curve,
// else B(H) / (mu0 H) at the centroid gradient of psi, clamped to [1, 1e6].
Eigen::VectorXd secant_mu_r(const TetMesh& mesh, const FeSpace& space, const std::vector<const BhCurve*>& curves,
                            const Eigen::VectorXd& mu_linear, const Eigen::VectorXd& psi, int threads);

// The Jacobian dR/dpsi at psi: K_mu (the stiffness with secant_mu_r(psi), Robin
// included) plus the rank-one tangent terms of the nonlinear cells (none where
// the clamp of secant_mu_r is active). Same sparsity pattern as K_mu.
SparseMatrix nonlinear_jacobian(const TetMesh& mesh, const FeSpace& space, const std::vector<const BhCurve*>& curves,
                                const SparseMatrix& K_mu, const Eigen::VectorXd& psi);

}  // namespace magenc::fem
