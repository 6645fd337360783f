// FEM verification ladder, part 1: exactness and matrix properties.
//  - P1 and P2 reproduce a linear potential exactly (patch test), P2 a quadratic one.
//  - K * const = 0 without the Robin term; K symmetric; x^T K x >= 0.
//  - the assembled matrix is bitwise independent of the thread count.
#include <Eigen/SparseCholesky>
#include <catch2/catch.hpp>
#include <random>

#include "field_solver/fe/assembly.hpp"
#include "field_solver/fe/fe_solution.hpp"
#include "fem_test_util.hpp"

using namespace magenc::fem;

namespace {

const TetMesh& small_mesh() {
  static const TetMesh mesh = [] {
    DomainSpec d = test::coarse_domain(1.2, 1.2, 16);
    d.mesh.outer_radius_mm = 15.0;
    d.mesh.h_air_mm = 6.0;
    d.zone.half_width_mm = 2.5;
    return mesh_domain(d);
  }();
  return mesh;
}

// Solves K psi = 0 with psi = g on the outer boundary; returns psi.
Eigen::VectorXd solve_with_boundary_values(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& g) {
  SparseMatrix K = assemble_stiffness(mesh, space, Eigen::VectorXd::Ones(mesh.num_tets()), false, 2);
  const std::vector<int> bd = boundary_dofs(mesh, space);
  Eigen::VectorXd gb = Eigen::VectorXd::Zero(space.num_dofs());
  for (int d : bd) gb[d] = g[d];
  Eigen::VectorXd f = -(K * gb);
  apply_zero_dirichlet(K, f, bd);
  for (int d : bd) f[d] = g[d];
  Eigen::SparseMatrix<double> Kc = K;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kc);
  REQUIRE(ldlt.info() == Eigen::Success);
  return ldlt.solve(f);
}

}  // namespace

TEST_CASE("patch test: P1 and P2 reproduce a linear potential exactly", "[field_solver][closed-form]") {
  const int order = GENERATE(1, 2);
  CAPTURE(order);
  const TetMesh& mesh = small_mesh();
  FeSpace space(mesh, order);
  const Eigen::Vector3d a(0.3, -1.1, 0.7);
  Eigen::VectorXd g(space.num_dofs());
  for (int i = 0; i < space.num_dofs(); ++i) g[i] = 0.25 + a.dot(space.dof_points().col(i));
  const Eigen::VectorXd psi = solve_with_boundary_values(mesh, space, g);
  // Round-off only: the discrete solution equals the linear function.
  CHECK((psi - g).cwiseAbs().maxCoeff() < 1e-9 * g.cwiseAbs().maxCoeff());
  // Its gradient is exact in every cell (B = -grad psi with mu_r = 1, Br = 0).
  FeSolution sol;
  sol.order = order;
  sol.points_mm = space.dof_points();
  sol.cell_dofs = space.cell_dofs();
  sol.psi_Tmm = psi;
  sol.region = mesh.region;
  sol.mu_r = Eigen::VectorXd::Ones(mesh.num_tets());
  sol.br_T = Eigen::Matrix3Xd::Zero(3, mesh.num_tets());
  double worst = 0;
  for (int c = 0; c < mesh.num_tets(); c += 7)
    worst = std::max(worst, (sol.B_in_cell(c, Eigen::Vector4d(0.1, 0.2, 0.3, 0.4)) + a).norm());
  CHECK(worst < 1e-8);
}

TEST_CASE("patch test: P2 reproduces a harmonic quadratic potential exactly", "[field_solver][closed-form]") {
  const TetMesh& mesh = small_mesh();
  FeSpace space(mesh, 2);
  Eigen::VectorXd g(space.num_dofs());
  for (int i = 0; i < space.num_dofs(); ++i) {
    const Eigen::Vector3d p = space.dof_points().col(i);
    g[i] = p.x() * p.x() - p.y() * p.y() + 0.5 * p.x() * p.z();  // Laplacian 0
  }
  const Eigen::VectorXd psi = solve_with_boundary_values(mesh, space, g);
  CHECK((psi - g).cwiseAbs().maxCoeff() < 1e-9 * g.cwiseAbs().maxCoeff());
}

TEST_CASE("stiffness: K*1 = 0 without Robin, symmetric, positive semi-definite", "[field_solver][closed-form]") {
  const int order = GENERATE(1, 2);
  CAPTURE(order);
  const TetMesh& mesh = small_mesh();
  FeSpace space(mesh, order);
  Eigen::VectorXd mu(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) mu[t] = mesh.region[t] == kRegionMagnet ? 1.05 : 1.0;
  const SparseMatrix K = assemble_stiffness(mesh, space, mu, false, 2);
  const double scale = K.diagonal().cwiseAbs().maxCoeff();
  CHECK((K * Eigen::VectorXd::Ones(space.num_dofs())).cwiseAbs().maxCoeff() < 1e-12 * scale);
  const SparseMatrix Kt = SparseMatrix(K.transpose());
  CHECK((K - Kt).norm() <= 1e-14 * K.norm());
  std::mt19937 rng(42);
  std::normal_distribution<double> nd;
  for (int k = 0; k < 5; ++k) {
    Eigen::VectorXd x(space.num_dofs());
    for (auto& v : x) v = nd(rng);
    CHECK(x.dot(K * x) > 0);
  }
  // With the Robin term, constants are no longer in the kernel: the energy of 1
  // equals Int_Gamma 2/r dS = 8 pi R_out on the sphere (faceted: slightly less).
  const SparseMatrix Kr = assemble_stiffness(mesh, space, mu, true, 2);
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(space.num_dofs());
  const double e1 = one.dot(Kr * one);
  CHECK(e1 == Approx(8.0 * 3.141592653589793 * 15.0).epsilon(0.02));
}

TEST_CASE("assembly is bitwise independent of the thread count", "[field_solver][determinism]") {
  const int order = GENERATE(1, 2);
  CAPTURE(order);
  const TetMesh& mesh = small_mesh();
  FeSpace space(mesh, order);
  const Eigen::VectorXd mu = Eigen::VectorXd::LinSpaced(mesh.num_tets(), 1.0, 2.0);
  const SparseMatrix K1 = assemble_stiffness(mesh, space, mu, true, 1);
  for (int threads : {2, 3, 4}) {
    CAPTURE(threads);
    const SparseMatrix Kn = assemble_stiffness(mesh, space, mu, true, threads);
    REQUIRE(Kn.nonZeros() == K1.nonZeros());
    bool same = true;
    for (Eigen::Index i = 0; i < K1.nonZeros(); ++i)
      same = same && K1.valuePtr()[i] == Kn.valuePtr()[i] && K1.innerIndexPtr()[i] == Kn.innerIndexPtr()[i];
    CHECK(same);
  }
}

TEST_CASE("FieldEvaluator: a point outside the mesh is one line naming it in num() format", "[field_solver][bad-input]") {
  const TetMesh& mesh = small_mesh();
  FeSpace space(mesh, 1);
  FeSolution sol;
  sol.order = 1;
  sol.points_mm = space.dof_points();
  sol.cell_dofs = space.cell_dofs();
  sol.psi_Tmm = Eigen::VectorXd::Zero(space.num_dofs());
  sol.region = mesh.region;
  sol.mu_r = Eigen::VectorXd::Ones(mesh.num_tets());
  sol.br_T = Eigen::Matrix3Xd::Zero(3, mesh.num_tets());
  const FieldEvaluator ev(std::move(sol));
  Eigen::Matrix3Xd p(3, 3);
  p.col(0) = Eigen::Vector3d(0, 0, test::kPlaneZ);  // inside
  p.col(1) = Eigen::Vector3d(100, 0.5, -2.25);      // outside (outer radius 15 mm): the first reported
  p.col(2) = Eigen::Vector3d(-40, 0, 0);            // outside too
  REQUIRE(ev.B_T(Eigen::Vector3d(p.col(0))).has_value());
  CHECK_THROWS_WITH(ev.B_T(p), "point (100, 0.5, -2.25) mm lies outside the FE mesh");
}
