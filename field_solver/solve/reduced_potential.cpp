#include "field_solver/solve/reduced_potential.hpp"

#include <array>
#include <deque>
#include <vector>

#include "core/errors.hpp"
#include "field_solver/fe/element.hpp"
#include "field_solver/fe/fe_solution.hpp"

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

// f_i = Int w_t H_s . grad N_i over the cells with weight w_t != 0.
Eigen::VectorXd assemble_weighted_source_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& w_cell,
                                             const AnalyticField& source) {
  const int order = space.order();
  const int nd = space.dofs_per_cell();
  std::vector<int> cells;
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (w_cell[t] != 0.0) cells.push_back(t);
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
      const Eigen::Vector3d h = w_cell[t] * source_H_T(source, x);
      basis_gradients(order, g, L, G);
      fe.col(k).head(nd) += (q.w[i] * g.volume_mm3) * (G.leftCols(nd).transpose() * h);
    }
  }
  Eigen::VectorXd f = Eigen::VectorXd::Zero(space.num_dofs());
  for (size_t k = 0; k < cells.size(); ++k)
    for (int i = 0; i < nd; ++i) f[space.cell_dofs()(i, cells[k])] += fe(i, static_cast<Eigen::Index>(k));
  return f;
}

// Interface dofs: 1 where a dof belongs to a total and to a reduced cell.
std::vector<char> interface_dofs(const FeSpace& space, const std::vector<char>& total) {
  const Eigen::MatrixXi& cd = space.cell_dofs();
  std::vector<char> in_total(static_cast<size_t>(space.num_dofs()), 0), in_reduced(in_total);
  for (Eigen::Index c = 0; c < cd.cols(); ++c)
    for (Eigen::Index i = 0; i < cd.rows(); ++i) (total[static_cast<size_t>(c)] ? in_total : in_reduced)[static_cast<size_t>(cd(i, c))] = 1;
  for (size_t d = 0; d < in_total.size(); ++d) in_total[d] = in_total[d] && in_reduced[d];
  return in_total;
}

// -Int_a^b H_s . dl (T*mm) on the straight segment a -> b: 4-point Gauss-Legendre.
double source_potential_step(const AnalyticField& source, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  static const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  const Eigen::Vector3d mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double s = 0;
  for (int k = 0; k < 4; ++k) s += w[k] * source_H_T(source, mid + x[k] * half).dot(half);
  return -s;
}

}  // namespace

Eigen::VectorXd assemble_reaction_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                      const AnalyticField& source) {
  return assemble_weighted_source_rhs(mesh, space, (mu_r_cell.array() - 1.0).matrix(), source);
}

std::vector<char> total_potential_cells(const TetMesh& mesh, const DomainSpec& domain) {
  std::vector<char> total(static_cast<size_t>(mesh.num_tets()), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    total[static_cast<size_t>(t)] = mesh.region[t] == kRegionShaft || domain.permeable_part_region(mesh.region[t]);
  return total;
}

Eigen::VectorXd interface_source_potential(const FeSpace& space, const std::vector<char>& total,
                                           const AnalyticField& source, int odd_axis) {
  const std::vector<char> on_g = interface_dofs(space, total);
  const Eigen::Matrix3Xd& p = space.dof_points();
  const Eigen::MatrixXi& cd = space.cell_dofs();
  // Graph of interface dofs: two are adjacent when a total cell holds both (the segment lies in that cell).
  std::vector<std::vector<int>> adj(static_cast<size_t>(space.num_dofs()));
  for (Eigen::Index c = 0; c < cd.cols(); ++c) {
    if (!total[static_cast<size_t>(c)]) continue;
    for (Eigen::Index i = 0; i < cd.rows(); ++i)
      for (Eigen::Index j = 0; j < cd.rows(); ++j)
        if (i != j && on_g[static_cast<size_t>(cd(i, c))] && on_g[static_cast<size_t>(cd(j, c))])
          adj[static_cast<size_t>(cd(i, c))].push_back(cd(j, c));
  }
  Eigen::VectorXd phi = Eigen::VectorXd::Zero(space.num_dofs());
  std::vector<char> done(static_cast<size_t>(space.num_dofs()), 0);
  std::deque<int> queue;
  long n_g = 0;
  for (Eigen::Index d = 0; d < p.cols(); ++d) {
    if (!on_g[static_cast<size_t>(d)]) continue;
    ++n_g;
    const bool root = odd_axis >= 0 ? p(odd_axis, d) == 0.0 : queue.empty();
    if (root) {
      done[static_cast<size_t>(d)] = 1;  // phi_s = 0: on the odd plane, or the one free constant
      queue.push_back(static_cast<int>(d));
    }
  }
  if (n_g == 0) return phi;
  if (queue.empty()) throw ComputeError("split potential: no interface dof on the symmetry plane");
  long reached = static_cast<long>(queue.size());
  auto sweep = [&] {
    while (!queue.empty()) {
      const int a = queue.front();
      queue.pop_front();
      for (int b : adj[static_cast<size_t>(a)]) {
        if (done[static_cast<size_t>(b)]) continue;
        done[static_cast<size_t>(b)] = 1;
        phi[b] = phi[a] + source_potential_step(source, p.col(a), p.col(b));
        queue.push_back(b);
        ++reached;
      }
    }
  };
  sweep();
  // Without a symmetry plane every connected part of the total region has its
  // own free constant (several permeable parts): one root each.
  if (odd_axis < 0)
    for (Eigen::Index d = 0; d < p.cols(); ++d) {
      if (!on_g[static_cast<size_t>(d)] || done[static_cast<size_t>(d)]) continue;
      done[static_cast<size_t>(d)] = 1;
      queue.push_back(static_cast<int>(d));
      ++reached;
      sweep();
    }
  if (reached != n_g)
    throw ComputeError("split potential: the interface of the total region is not connected (" +
                       std::to_string(reached) + " of " + std::to_string(n_g) + " dofs reached)");
  return phi;
}

Eigen::VectorXd assemble_split_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                   const std::vector<char>& total, const AnalyticField& source,
                                   const Eigen::VectorXd& interface_phi_s) {
  // f_R + f_T: weights mu_r - 1 in R, -1 in T.
  Eigen::VectorXd w(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) w[t] = total[static_cast<size_t>(t)] ? -1.0 : mu_r_cell[t] - 1.0;
  Eigen::VectorXd f = assemble_weighted_source_rhs(mesh, space, w, source);
  // + K_R g over the reduced cells with a dof on the interface (g != 0 only there).
  const int order = space.order(), nd = space.dofs_per_cell();
  const Eigen::MatrixXi& cd = space.cell_dofs();
  Eigen::Matrix<double, 3, 10> G;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (total[static_cast<size_t>(t)]) continue;
    bool touches = false;
    for (int i = 0; i < nd; ++i) touches = touches || interface_phi_s[cd(i, t)] != 0.0;
    if (!touches) continue;
    const TetGeometry g = tet_geometry(mesh.nodes, mesh.tets.col(t));
    for (const Eigen::Vector4d& L : tet_quadrature_points()) {  // degree 2: exact for P2 x P2 gradients
      basis_gradients(order, g, L, G);
      Eigen::Vector3d grad_g = Eigen::Vector3d::Zero();
      for (int i = 0; i < nd; ++i) grad_g += interface_phi_s[cd(i, t)] * G.col(i);
      const double s = mu_r_cell[t] * kTetQuadratureWeight * g.volume_mm3;
      for (int i = 0; i < nd; ++i) f[cd(i, t)] += s * G.col(i).dot(grad_g);
    }
  }
  return f;
}

}  // namespace magenc::fem
