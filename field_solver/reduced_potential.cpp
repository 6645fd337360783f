#include "reduced_potential.hpp"

#include <array>
#include <vector>

#include "element.hpp"
#include "fe_solution.hpp"

namespace magenc::fem {
namespace {

// Keast 5-point rule, exact for degree 3 (barycentric points, weights sum to 1).
struct TetRule5 {
  std::array<Eigen::Vector4d, 5> L;
  std::array<double, 5> w;
};
const TetRule5& tet_rule5() {
  static const TetRule5 r = [] {
    TetRule5 q;
    q.L[0] = Eigen::Vector4d::Constant(0.25);
    q.w[0] = -0.8;
    const double a = 0.5, b = 1.0 / 6.0;
    for (int k = 0; k < 4; ++k) {
      q.L[static_cast<size_t>(k + 1)] = Eigen::Vector4d::Constant(b);
      q.L[static_cast<size_t>(k + 1)][k] = a;
      q.w[static_cast<size_t>(k + 1)] = 0.45;
    }
    return q;
  }();
  return r;
}

}  // namespace

Eigen::VectorXd assemble_reaction_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                      const AnalyticField& source) {
  const int order = space.order();
  const int nd = space.dofs_per_cell();
  std::vector<int> cells;
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mu_r_cell[t] != 1.0) cells.push_back(t);
  Eigen::MatrixXd fe = Eigen::MatrixXd::Zero(10, static_cast<Eigen::Index>(cells.size()));
  const TetRule5& q = tet_rule5();
#pragma omp parallel for schedule(dynamic, 64)
  for (long k = 0; k < static_cast<long>(cells.size()); ++k) {
    const int t = cells[static_cast<size_t>(k)];
    const TetGeometry g = tet_geometry(mesh.nodes, mesh.tets.col(t));
    Eigen::Matrix<double, 3, 10> G;
    for (size_t i = 0; i < q.L.size(); ++i) {
      const Eigen::Vector4d& L = q.L[i];
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int v = 0; v < 4; ++v) x += L[v] * mesh.nodes.col(mesh.tets(v, t));
      const Eigen::Vector3d h = (mu_r_cell[t] - 1.0) * source_H_T(source, x);
      basis_gradients(order, g, L, G);
      fe.col(k).head(nd) += (q.w[i] * g.volume_mm3) * (G.leftCols(nd).transpose() * h);
    }
  }
  Eigen::VectorXd f = Eigen::VectorXd::Zero(space.num_dofs());
  for (size_t k = 0; k < cells.size(); ++k)
    for (int i = 0; i < nd; ++i) f[space.cell_dofs()(i, cells[k])] += fe(i, static_cast<Eigen::Index>(k));
  return f;
}

}  // namespace magenc::fem
