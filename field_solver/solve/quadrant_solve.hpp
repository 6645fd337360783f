// Quadrant solve (mesh.symmetric with fem.quadrant_solve): the mesh is the
// quadrant x, y >= 0 mirrored into all four quadrants, so the potential of
// each magnetization component has a parity across x = 0 and y = 0 and can be
// solved on the quadrant alone (1/4 of the unknowns), then mirrored:
//   component x: odd in x (psi = 0 on x = 0), even in y (natural condition);
//   component y: the reverse;
//   component z (magnetization elevation): even in both (natural on both).
// Same discrete solution as a solve of the whole mirrored mesh (to the CG
// tolerance). One linear solve per non-zero component; the stiffness matrix
// is shared.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "field_solver/fe/assembly.hpp"
#include "field_solver/fe/fe_space.hpp"
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

// One right-hand side of the potential system on a mesh (reduced_potential.hpp):
// the load f and, for the split potential only, the magnet's source potential
// phi_s (T*mm) at the interface dofs between the total and reduced regions,
// 0 at all other dofs (empty for the total and reduced potentials).
struct PotentialLoad {
  Eigen::VectorXd f;
  Eigen::VectorXd interface_phi_s;
};

// The load of one magnetization component br_T (T) on (mesh, space).
using LoadBuilder = std::function<PotentialLoad(const TetMesh& mesh, const FeSpace& space, const Eigen::Vector3d& br_T)>;
// Solves K x = f (K symmetric positive definite).
using LinearSolve = std::function<void(const SparseMatrix& K, const Eigen::VectorXd& f, Eigen::VectorXd& x)>;

class QuadrantSolve {
 public:
  // quadrant: the quadrant mesh the whole mesh mirrors; order: Lagrange order of the dofs.
  QuadrantSolve(TetMesh quadrant, int order);
  const TetMesh& mesh() const { return quad_; }
  long num_dofs() const { return space_->num_dofs(); }
  long nonzeros() const { return K_.nonZeros(); }
  const FeSpace& space() const { return *space_; }
  // The quadrant's dofs on the plane x_c = 0 (c = 0: x, 1: y; none for c = 2): psi = 0 there
  // for component c, whose potential is odd across that plane.
  std::vector<int> odd_plane_dofs(int c) const;
  // v (a quadrant dof vector of component c's parity) mirrored onto the whole mesh's dof points
  // (3 x n, mm): the sign flips across the plane x_c = 0 for c = 0, 1.
  Eigen::VectorXd mirror(const Eigen::Matrix3Xd& full_dof_points_mm, const Eigen::VectorXd& v, int c) const;
  // Stiffness on the quadrant (per-cell mu_r_cell of the quadrant's cells, Robin or psi = 0 on the
  // outer boundary) and one load per component of br_T above 1e-12 * br_scale_T.
  void assemble(const Eigen::VectorXd& mu_r_cell, const Eigen::Vector3d& br_T, double br_scale_T, bool robin,
                int threads, const LoadBuilder& load);
  // Solves every load with its symmetry condition and mirrors the solutions onto the whole
  // mesh's dof points (3 x n, mm), summed over the components. interface_phi_s (when not null and
  // the loads carry one) receives the mirrored sum of the loads' interface_phi_s, else it is left
  // empty. Releases the quadrant's matrix and loads.
  Eigen::VectorXd solve_and_mirror(const Eigen::Matrix3Xd& full_dof_points_mm, const LinearSolve& solve,
                                   Eigen::VectorXd* interface_phi_s);

 private:
  TetMesh quad_;
  std::unique_ptr<FeSpace> space_;
  SparseMatrix K_;
  std::vector<std::pair<int, PotentialLoad>> loads_;  // (magnetization component, its load)
};

}  // namespace magenc::fem
