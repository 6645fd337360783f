// Total/reduced split (fem.potential = split, reduced_potential.hpp): total
// potential in the shaft, reduced potential (correction to the magnet's exact
// field) elsewhere, tied on the shaft's surface by psi = phi + phi_s.
//  - no shaft: split and auto are the reduced potential, the FE field is the
//    exact field (correction 0);
//  - shaft with mu_r = 1: the split field is the exact field up to the
//    interpolation error of psi = phi_s inside the shaft, far below the total
//    potential's error on the same mesh;
//  - phi_s on the interface (integrated along mesh edges) agrees with an
//    independent fine line integral of H_s;
//  - shaft with mu_r = 1000: split and total agree on the same mesh to within
//    the total potential's own discretization error, and the two converge to
//    one field under refinement; the quadrant solve equals the whole-mesh one;
//  - mesh.vtu keeps the split (fem:DIR gives the same B, in the shaft too).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <string>

#include "core/cli.hpp"
#include "core/errors.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "fields/analytic_field.hpp"
#include "field_solver/fe/fe_solution.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"
#include "field_solver/solve/reduced_potential.hpp"
#include "solver_fixtures.hpp"
#include "field_solver/field_io/validation.hpp"
#include "field_solver/field_io/vtk_io.hpp"

using namespace magenc::fem;
using magenc::GridData;

using namespace magenc::fem::test;  // coarse_settings, plane, with, solved, diff (solver_fixtures.hpp)

namespace {

const std::vector<std::string> kShaft = {"shaft.enabled=true", "shaft.radius_mm=3", "shaft.length_mm=8",
                                         "shaft.gap_mm=1"};

}  // namespace

TEST_CASE("split potential without a shaft is the reduced potential: the exact field", "[field_solver][physics][cross-check]") {
  for (const std::string pot : {"split", "auto"}) {
    const auto s = solved({"magnet.mu_r=1"}, pot);
    CHECK(s->options().potential == (pot == "auto" ? Potential::Reduced : Potential::Split));
    CHECK(s->stats().iterations == 0);
    CHECK_FALSE(s->solution().split());
    const magenc::AnalyticField exact(s->domain().magnet);
    const BzErrorStats e = bz_error_on_grid(s->evaluator(), exact, plane(coarse_settings({})));
    CAPTURE(pot, e.max_rel());
    CHECK(e.max_rel() < 1e-12);
  }
}

TEST_CASE("split potential with a mu_r = 1 shaft: the correction is only the shaft's interpolation error", "[field_solver][physics]") {
  const auto sets = with(kShaft, {"magnet.mu_r=1", "shaft.mu_r=1"});
  const auto split = solved(sets, "auto");
  REQUIRE(split->options().potential == Potential::Split);
  REQUIRE(split->solution().split());
  const auto total = solved(sets, "total");
  const magenc::AnalyticField exact(split->domain().magnet);
  const GridData g = plane(coarse_settings({}));
  const BzErrorStats es = bz_error_on_grid(split->evaluator(), exact, g);
  const BzErrorStats et = bz_error_on_grid(total->evaluator(), exact, g);
  CAPTURE(es.rms_rel(), es.max_rel(), et.rms_rel(), et.max_rel());
  // Measured RMS / max of Bz relative to its peak: split 6.8e-7 / 1.1e-6, total 8.0e-3 / 1.7e-2.
  CHECK(es.rms_rel() < 1e-4);
  CHECK(es.rms_rel() < et.rms_rel() / 100);
  // Just above the shaft's face and inside it: B is still the exact field.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1.0, 0.5, -2.9), Eigen::Vector3d(0.5, -1.0, -5.0)}) {
    const Eigen::Vector3d b = *split->evaluator().B_T(p), e = exact.B_T(p);
    CAPTURE(p.transpose(), b.transpose(), e.transpose());
    // Measured relative errors 1.7e-3 above the face, 1.2e-2 inside (P2 psi on the 1 mm shaft mesh).
    CHECK((b - e).norm() < 0.05 * e.norm());
  }
}

TEST_CASE("split potential: phi_s on the interface is the line integral of H_s", "[field_solver][cross-check]") {
  const auto s = solved(with(kShaft, {"shaft.mu_r=1000"}), "split");
  const FeSolution& sol = s->solution();
  REQUIRE(sol.split());
  // Two interface dofs far apart: the top face centre region and the bottom rim.
  int a = -1, b = -1;
  for (Eigen::Index d = 0; d < sol.points_mm.cols(); ++d) {
    if (sol.interface_phi_s_Tmm[d] == 0.0) continue;
    const Eigen::Vector3d p = sol.points_mm.col(d);
    if (a < 0 || p.z() > sol.points_mm(2, a)) a = static_cast<int>(d);
    if (b < 0 || p.z() < sol.points_mm(2, b) - 1e-9 || (std::abs(p.z() - sol.points_mm(2, b)) < 1e-9 && p.x() > sol.points_mm(0, b)))
      b = static_cast<int>(d);
  }
  REQUIRE(a >= 0);
  REQUIRE(b >= 0);
  const magenc::AnalyticField src(s->domain().magnet);
  const Eigen::Vector3d pa = sol.points_mm.col(a), pb = sol.points_mm.col(b);
  // Midpoint rule, 4000 steps, along the straight segment (inside the convex shaft).
  double line = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) line -= source_H_T(src, pa + (k + 0.5) / n * (pb - pa)).dot((pb - pa) / n);
  const double mesh_path = sol.interface_phi_s_Tmm[b] - sol.interface_phi_s_Tmm[a];
  CAPTURE(pa.transpose(), pb.transpose(), line, mesh_path);
  CHECK(std::abs(line) > 1e-3);  // a real potential difference (T*mm)
  CHECK(mesh_path == Approx(line).epsilon(1e-6));
}

TEST_CASE("split potential with a mu_r = 1000 shaft agrees with the total potential", "[field_solver][cross-check]") {
  const auto sets = with(kShaft, {"shaft.mu_r=1000", "magnet.mu_r=1.05"});
  const std::vector<std::string> fine = {"mesh.h_zone_mm=0.5", "mesh.h_magnet_mm=0.6"};
  const auto split = solved(sets, "split"), total = solved(sets, "total");
  const auto split_f = solved(with(sets, fine), "split"), total_f = solved(with(sets, fine), "total");
  const GridData g = plane(coarse_settings({}));
  const auto [d_c, dm_c] = diff(split->evaluator(), total->evaluator(), g);
  const auto [d_f, dm_f] = diff(split_f->evaluator(), total_f->evaluator(), g);
  const auto [t_c, tm_c] = diff(total->evaluator(), total_f->evaluator(), g);
  const auto [s_c, sm_c] = diff(split->evaluator(), split_f->evaluator(), g);
  CAPTURE(d_c, dm_c, d_f, dm_f, t_c, tm_c, s_c, sm_c);
  // Measured (P2, coarse.toml; fine: zone 0.5, magnet/shaft 0.6 mm), RMS / max relative to peak |B|:
  // split - total 9.0e-3 / 1.7e-2 coarse, 3.2e-3 / 7.5e-3 fine; total coarse - fine 9.4e-3 / 1.9e-2;
  // split coarse - fine 5.2e-4 / 7.9e-4. The two differ by the total potential's own discretization
  // error (the split's is ~18x smaller), and that difference shrinks under refinement.
  CHECK(d_c < 1.5 * t_c);
  CHECK(dm_c < 1.5 * tm_c);
  CHECK(d_f < d_c / 2);
  CHECK(s_c < t_c / 5);
  // The shaft's reaction is real: the split field is not the magnet's free-space field.
  const magenc::AnalyticField exact(split->domain().magnet);
  CHECK(bz_error_on_grid(split->evaluator(), exact, g).rms_rel() > 1e-2);
}

TEST_CASE("split potential: quadrant solve equals the whole-mesh solve, and mesh.vtu keeps the split", "[field_solver][cross-check][contract]") {
  // All three magnetization components: x and y odd across their planes (phi_s = 0 there), z even.
  // The two solves agree to the CG tolerance: 1e-10 (not the default 1e-8).
  const auto sets = with(kShaft, {"shaft.mu_r=1000", "magnet.mu_r=1.05", "magnet.magnetization_deg=30",
                                  "magnet.magnetization_elevation_deg=20", "fem.tolerance=1e-10"});
  const auto quad = solved(sets, "split");
  const auto whole = solved(with(sets, {"fem.quadrant_solve=false"}), "split");
  CHECK(quad->stats().solves == 3);
  const std::filesystem::path f =
      std::filesystem::temp_directory_path() / ("magenc_split_" + std::to_string(::getpid()) + ".vtu");
  write_solution_vtu(f, quad->solution(), quad->B_cell());
  const FieldEvaluator back(read_solution_vtu(f));
  std::filesystem::remove(f);
  REQUIRE(back.solution().split());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.3, 0.2, 4.55), Eigen::Vector3d(-2.0, 1.0, 4.3),
                                  Eigen::Vector3d(1.0, -0.5, 0.0),     // in the magnet
                                  Eigen::Vector3d(-0.7, 1.1, -2.95),   // just above the shaft
                                  Eigen::Vector3d(0.5, -1.2, -6.0)}) {  // in the shaft
    const Eigen::Vector3d a = *quad->evaluator().B_T(p), w = *whole->evaluator().B_T(p), b = *back.B_T(p);
    CAPTURE(p.transpose(), a.transpose(), w.transpose());
    CHECK((a - w).norm() < 1e-6 * a.norm() + 1e-9);
    CHECK((a - b).norm() < 1e-12);
  }
}

TEST_CASE("split potential: a mesh.vtu with half of the split is refused", "[field_solver][bad-input]") {
  const auto s = solved(with(kShaft, {"shaft.mu_r=1000"}), "split");
  FeSolution broken = s->solution();
  broken.interface_phi_s_Tmm.resize(3);  // no longer one value per point
  const std::filesystem::path f =
      std::filesystem::temp_directory_path() / ("magenc_split_bad_" + std::to_string(::getpid()) + ".vtu");
  write_solution_vtu(f, broken, s->B_cell());
  CHECK_THROWS_AS(read_solution_vtu(f), magenc::InputError);
  std::filesystem::remove(f);
}
