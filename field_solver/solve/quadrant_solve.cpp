#include "field_solver/solve/quadrant_solve.hpp"

#include <cmath>

#include "field_solver/mesh/symmetric_mesh.hpp"

namespace magenc::fem {

QuadrantSolve::QuadrantSolve(TetMesh quadrant, int order)
    : quad_(std::move(quadrant)), space_(std::make_unique<FeSpace>(quad_, order)) {}

void QuadrantSolve::assemble(const Eigen::VectorXd& mu_r_cell, const Eigen::Vector3d& br_T, double br_scale_T,
                             bool robin, int threads, const LoadBuilder& load) {
  // Eigen 3.4's SparseMatrix has no move assignment: K_ = f() would copy the matrix.
  SparseMatrix K = assemble_stiffness(quad_, *space_, mu_r_cell, robin, threads);
  K_.swap(K);
  loads_.clear();
  for (int c = 0; c < 3; ++c) {
    if (std::abs(br_T[c]) < 1e-12 * br_scale_T) continue;
    Eigen::Vector3d br = Eigen::Vector3d::Zero();
    br[c] = br_T[c];
    loads_.emplace_back(c, load(quad_, *space_, br));
  }
  if (!robin) {
    const std::vector<int> outer = boundary_dofs(quad_, *space_);
    for (auto& [c, l] : loads_) apply_zero_dirichlet(K_, l.f, outer);
  }
}

Eigen::VectorXd QuadrantSolve::solve_and_mirror(const Eigen::Matrix3Xd& fp, const LinearSolve& solve,
                                                Eigen::VectorXd* interface_phi_s) {
  // Component c (x or y) is odd across the plane x_c = 0 and even across the other; the axial
  // component (c = 2) is unchanged by both reflections x -> -x, y -> -y, which map the magnet and
  // every region onto themselves: even in x and y, mirrored without a sign.
  const Eigen::Matrix3Xd& qp = space_->dof_points();
  const std::vector<int> image = mirror_dof_map(fp, qp);
  Eigen::VectorXd psi = Eigen::VectorXd::Zero(fp.cols());
  const bool offsets = interface_phi_s && !loads_.empty() && loads_.front().second.interface_phi_s.size() > 0;
  if (interface_phi_s) *interface_phi_s = offsets ? Eigen::VectorXd::Zero(fp.cols()) : Eigen::VectorXd();
  for (size_t k = 0; k < loads_.size(); ++k) {
    auto& [c, l] = loads_[k];
    std::vector<int> plane;
    if (c < 2)
      for (Eigen::Index i = 0; i < qp.cols(); ++i)
        if (qp(c, i) == 0.0) plane.push_back(static_cast<int>(i));
    SparseMatrix Kc;
    if (k + 1 < loads_.size()) Kc = K_;  // the last solve may overwrite K_
    SparseMatrix& K = k + 1 < loads_.size() ? Kc : K_;
    apply_zero_dirichlet(K, l.f, plane);
    Eigen::VectorXd psi_q;
    solve(K, l.f, psi_q);
    for (Eigen::Index i = 0; i < fp.cols(); ++i) {
      const double sign = c < 2 && fp(c, i) < 0 ? -1.0 : 1.0;
      psi[i] += sign * psi_q[image[static_cast<size_t>(i)]];
      if (offsets) (*interface_phi_s)[i] += sign * l.interface_phi_s[image[static_cast<size_t>(i)]];
    }
  }
  loads_.clear();
  SparseMatrix().swap(K_);  // frees it (assigning an empty matrix keeps the allocation)
  return psi;
}

std::vector<int> QuadrantSolve::odd_plane_dofs(int c) const {
  std::vector<int> plane;
  const Eigen::Matrix3Xd& qp = space_->dof_points();
  if (c < 2)
    for (Eigen::Index i = 0; i < qp.cols(); ++i)
      if (qp(c, i) == 0.0) plane.push_back(static_cast<int>(i));
  return plane;
}

Eigen::VectorXd QuadrantSolve::mirror(const Eigen::Matrix3Xd& fp, const Eigen::VectorXd& v, int c) const {
  const std::vector<int> image = mirror_dof_map(fp, space_->dof_points());
  Eigen::VectorXd w(fp.cols());
  for (Eigen::Index i = 0; i < fp.cols(); ++i)
    w[i] = (c < 2 && fp(c, i) < 0 ? -1.0 : 1.0) * v[image[static_cast<size_t>(i)]];
  return w;
}

}  // namespace magenc::fem
