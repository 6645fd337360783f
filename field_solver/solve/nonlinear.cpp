#include "field_solver/solve/nonlinear.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "field_solver/fe/element.hpp"

namespace magenc::fem {
namespace {

constexpr double kMuMin = 1.0, kMuMax = 1e6;  // secant_mu_r's clamp

// Centroid gradient basis G (3 x nd) and g = grad psi there, cell t.
Eigen::Vector3d centroid_gradient(const TetMesh& mesh, const FeSpace& space, int t, const Eigen::VectorXd& psi,
                                  Eigen::Matrix<double, 3, 10>& G) {
  basis_gradients(space.order(), tet_geometry(mesh.nodes, mesh.tets.col(t)), Eigen::Vector4d::Constant(0.25), G);
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (int k = 0; k < space.dofs_per_cell(); ++k) g += psi[space.cell_dofs()(k, t)] * G.col(k);
  return g;
}

// mu_t(s) = B(s / mu0) / s, unclamped (s = |g| in T).
double secant(const BhCurve& c, double s) { return c.mu_r(s / kMu0_T_m_per_A); }

}  // namespace

std::vector<const BhCurve*> cell_bh_curves(const DomainSpec& domain, const TetMesh& mesh) {
  std::vector<const BhCurve*> c(static_cast<size_t>(mesh.num_tets()), nullptr);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int i = mesh.region[t] - kRegionPartFirst;
    if (i >= 0 && i < static_cast<int>(domain.parts.size())) c[static_cast<size_t>(t)] = domain.parts[static_cast<size_t>(i)].bh.get();
  }
  return c;
}

Eigen::VectorXd secant_mu_r(const TetMesh& mesh, const FeSpace& space, const std::vector<const BhCurve*>& curves,
                            const Eigen::VectorXd& mu_linear, const Eigen::VectorXd& psi, int threads) {
  Eigen::VectorXd mu = mu_linear;
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const BhCurve* c = curves[static_cast<size_t>(t)];
    if (!c) continue;
    Eigen::Matrix<double, 3, 10> G;
    mu[t] = std::clamp(secant(*c, centroid_gradient(mesh, space, t, psi, G).norm()), kMuMin, kMuMax);
  }
  return mu;
}

SparseMatrix nonlinear_jacobian(const TetMesh& mesh, const FeSpace& space, const std::vector<const BhCurve*>& curves,
                                const SparseMatrix& K_mu, const Eigen::VectorXd& psi) {
  SparseMatrix J = K_mu;
  const int nd = space.dofs_per_cell();
  const Eigen::MatrixXi& cd = space.cell_dofs();
  Eigen::Matrix<double, 3, 10> G;
  Eigen::Matrix<double, 10, 10> K1;
  Eigen::Matrix<double, 10, 1> pe, u, v;
  // Serial, cells in order: J is reproducible and independent of the thread count.
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const BhCurve* c = curves[static_cast<size_t>(t)];
    if (!c) continue;
    const Eigen::Vector3d g = centroid_gradient(mesh, space, t, psi, G);
    const double s = g.norm();
    if (s == 0.0) continue;  // v = 0: no tangent term
    const double mu = secant(*c, s);
    if (mu <= kMuMin || mu >= kMuMax) continue;  // clamped: mu does not vary with psi here
    const double a = (c->dB_dH(s / kMu0_T_m_per_A) / kMu0_T_m_per_A - mu) / (s * s);
    cell_stiffness(mesh, space.order(), t, 1.0, K1);
    for (int k = 0; k < nd; ++k) pe[k] = psi[cd(k, t)];
    u.head(nd) = K1.topLeftCorner(nd, nd) * pe.head(nd);
    v.head(nd) = G.leftCols(nd).transpose() * g;
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) {
        double* e = &J.coeffRef(cd(i, t), cd(j, t));  // in the pattern: (i, j) share cell t
        *e += a * u[i] * v[j];
      }
  }
  return J;
}

}  // namespace magenc::fem
