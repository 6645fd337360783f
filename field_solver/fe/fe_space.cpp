#include "field_solver/fe/fe_space.hpp"

#include <algorithm>

#include "field_solver/fe/element.hpp"
#include "core/errors.hpp"

namespace magenc::fem {

FeSpace::FeSpace(const TetMesh& mesh, int order) : order_(order), n_nodes_(mesh.num_nodes()) {
  if (order != 1 && order != 2) throw InputError("fem.order = " + std::to_string(order) + " is out of range: allowed 1 or 2");
  const int nt = mesh.num_tets();
  cell_dofs_.resize(fem::dofs_per_cell(order), nt);
  cell_dofs_.topRows(4) = mesh.tets;
  num_dofs_ = mesh.num_nodes();
  std::vector<Eigen::Vector3d> mids;
  if (order == 2) {
    edge_dof_.reserve(static_cast<size_t>(nt) * 2);
    for (int t = 0; t < nt; ++t)
      for (int e = 0; e < 6; ++e) {
        int a = mesh.tets(kTetEdges[e][0], t), b = mesh.tets(kTetEdges[e][1], t);
        if (a > b) std::swap(a, b);
        auto [it, inserted] = edge_dof_.try_emplace(a * n_nodes_ + b, num_dofs_);
        if (inserted) {
          ++num_dofs_;
          mids.push_back(0.5 * (mesh.nodes.col(a) + mesh.nodes.col(b)));
        }
        cell_dofs_(4 + e, t) = it->second;
      }
  }
  dof_points_.resize(3, num_dofs_);
  dof_points_.leftCols(mesh.num_nodes()) = mesh.nodes;
  for (size_t i = 0; i < mids.size(); ++i) dof_points_.col(mesh.num_nodes() + static_cast<Eigen::Index>(i)) = mids[i];
}

int FeSpace::edge_dof(int a, int b) const {
  if (a > b) std::swap(a, b);
  auto it = edge_dof_.find(a * n_nodes_ + b);
  return it == edge_dof_.end() ? -1 : it->second;
}

}  // namespace magenc::fem
