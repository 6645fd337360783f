// Continuous Lagrange P1/P2 space on a TetMesh: degrees of freedom are the
// mesh vertices (ids 0..n_nodes-1), then for P2 one per edge (edge midpoints).
#pragma once
#include <Eigen/Core>
#include <unordered_map>

#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

class FeSpace {
 public:
  FeSpace(const TetMesh& mesh, int order);  // order 1 or 2

  int order() const { return order_; }
  int num_dofs() const { return num_dofs_; }
  int dofs_per_cell() const { return static_cast<int>(cell_dofs_.rows()); }
  // dofs_per_cell x n_tets global dof ids in local (VTK) order.
  const Eigen::MatrixXi& cell_dofs() const { return cell_dofs_; }
  // 3 x num_dofs coordinates of the dof nodes (mm): vertices, then edge midpoints.
  const Eigen::Matrix3Xd& dof_points() const { return dof_points_; }
  // Global dof of the edge (a, b) of mesh vertices (P2 only); -1 if no such edge.
  int edge_dof(int a, int b) const;

 private:
  int order_ = 1;
  int num_dofs_ = 0;
  Eigen::MatrixXi cell_dofs_;
  Eigen::Matrix3Xd dof_points_;
  std::unordered_map<long long, int> edge_dof_;  // key a*n+b (a < b) -> dof
  long long n_nodes_ = 0;
};

}  // namespace magenc::fem
