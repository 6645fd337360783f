// Linear-solver backends (fem.solver, linear_solver.hpp):
//  - eigen-pcg, petsc-gamg and petsc-hypre solve the coarse mesh
//    (meshes/coarse.toml, P1 and P2) to the same potential within what the
//    CG tolerance allows;
//  - the multigrid iteration count stays low and does not grow when the
//    zone's edge length is halved, while Jacobi-PCG's grows.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/cli.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "field_solver/solve/linear_solver.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"
#include "solver_fixtures.hpp"

using namespace magenc::fem;

namespace {

FemSettings coarse_settings(const std::vector<std::string>& sets) {
  return magenc::fem::test::coarse_settings(sets, "fem.potential=total");  // the system the measured numbers below are of
}

struct Solved {
  Eigen::VectorXd psi;
  long iterations;
  double residual;
  long solved_dofs;
};

Solved solve(const std::string& backend, const std::vector<std::string>& sets) {
  FemSettings s = coarse_settings(sets);
  s.solver.solver = linear_solver_from_string(backend);
  MagnetostaticSolver solver(s.domain, s.solver);
  solver.run();
  return {solver.solution().psi_Tmm, solver.stats().iterations, solver.stats().residual, solver.stats().solved_dofs};
}

}  // namespace

TEST_CASE("fem.solver: auto resolves to a backend this build has, and bad names are refused", "[field_solver][bad-input]") {
  CHECK(to_string(resolve_linear_solver(LinearSolverKind::Auto)) == (petsc_available() ? "petsc-hypre" : "eigen-pcg"));
  CHECK(resolve_linear_solver(LinearSolverKind::EigenPcg) == LinearSolverKind::EigenPcg);
  CHECK_THROWS(coarse_settings({"fem.solver=amg"}));
  // Names and values correspond one to one; an unknown name names the key.
  for (const std::string& n : linear_solver_names()) CHECK(to_string(linear_solver_from_string(n)) == n);
  for (const std::string& n : preconditioner_names()) CHECK(to_string(preconditioner_from_string(n)) == n);
  for (const std::string& n : potential_names()) CHECK(to_string(potential_from_string(n)) == n);
  CHECK_THROWS_WITH(linear_solver_from_string("amg"), Catch::Contains("fem.solver = amg"));
  CHECK_THROWS_WITH(preconditioner_from_string("ilu"), Catch::Contains("fem.preconditioner = ilu"));
  CHECK_THROWS_WITH(potential_from_string("half"), Catch::Contains("fem.potential = half"));
}

TEST_CASE("PETSc multigrid and Eigen PCG give the same potential on the coarse mesh", "[field_solver][cross-check]") {
  if (!petsc_available()) {
    WARN("built without PETSc: only eigen-pcg");
    return;
  }
  const int order = GENERATE(1, 2);
  const std::string backend = GENERATE(std::string("petsc-gamg"), std::string("petsc-hypre"));
  CAPTURE(order, backend);
  const std::vector<std::string> sets = {"fem.order=" + std::to_string(order), "fem.tolerance=1e-10"};
  const Solved e = solve("eigen-pcg", sets), p = solve(backend, sets);
  CAPTURE(e.iterations, p.iterations, e.residual, p.residual);
  REQUIRE(e.psi.size() == p.psi.size());
  CHECK(p.residual < 1e-10);
  // Both stop at |f - K psi| < 1e-10 |f|; the potential error is then bounded
  // by cond(K) * 1e-10; measured 0.9e-11..1.4e-11 relative (P1, P2; GAMG,
  // BoomerAMG). 1e-8 keeps a margin of ~700 and still catches any wrong
  // system (a sign, a missing boundary row or a scrambled gather is O(1)).
  const double diff = (e.psi - p.psi).norm() / e.psi.norm();
  INFO("relative psi difference " << diff);
  CHECK(diff < 1e-8);
  CHECK(p.iterations < e.iterations);
}

TEST_CASE("multigrid iteration count stays low when the mesh is refined", "[field_solver][convergence][slow]") {
  if (!petsc_available()) {
    WARN("built without PETSc: only eigen-pcg");
    return;
  }
  // P2 on coarse.toml's mesh (zone edge 0.8 mm) and on a mesh with zone
  // edge 0.4 mm and magnet edge 0.5 mm (~4x the solved dofs).
  const std::vector<std::string> coarse = {"fem.order=2"};
  const std::vector<std::string> fine = {"fem.order=2", "mesh.h_zone_mm=0.4", "mesh.h_magnet_mm=0.5"};
  const Solved g1 = solve("petsc-gamg", coarse), g2 = solve("petsc-gamg", fine);
  const Solved j1 = solve("eigen-pcg", coarse), j2 = solve("eigen-pcg", fine);
  CAPTURE(g1.solved_dofs, g2.solved_dofs, g1.iterations, g2.iterations, j1.iterations, j2.iterations);
  REQUIRE(g2.solved_dofs > 3 * g1.solved_dofs);
  // Tens of iterations, and not growing with the mesh (up to 25 % + 5 for the
  // unstructured, non-nested meshes); Jacobi-PCG grows ~ 1/h.
  CHECK(g1.iterations < 60);
  CHECK(g2.iterations < 60);
  CHECK(g2.iterations <= 1.25 * g1.iterations + 5);
  CHECK(j2.iterations > 1.3 * j1.iterations);
}
