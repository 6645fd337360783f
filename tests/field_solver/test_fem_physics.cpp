// FEM verification ladder, part 2: physics against closed forms.
//  - mu_r = 1: Bz on the sensing plane vs the exact AnalyticField on coarse
//    meshes, with error bounds and an observed convergence rate (P1, P2).
//  - uniformly magnetized sphere with mu_r != 1: uniform B inside
//    B_in = 2 Br/(mu_r + 2), dipole m = Br a^3/(mu_r + 2) outside (scaled units).
//  - a high-mu_r shaft under the magnet pulls flux: B turns normal to its face,
//    and Bz on the sensing plane drops slightly.
#include <catch2/catch.hpp>
#include <cmath>

#include "fields/analytic_field.hpp"
#include "fem_test_util.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"
#include "field_solver/field_io/validation.hpp"

using namespace magenc::fem;

namespace {

SolverOptions quiet(int order) {
  SolverOptions o;
  o.order = order;
  o.potential = Potential::Total;  // the formulation whose discretization error these tests measure
  o.progress_every = 0;
  o.tolerance = 1e-10;
  return o;
}

struct Run {
  long dofs;
  double rms_rel, max_rel;      // raw FE gradient
  double rms_rec, max_rec;      // recovered (node-averaged) gradient
};

Run run_cylinder(double h_zone, int order) {
  SolverOptions o = quiet(order);
  o.recovery = false;  // theoretical rates are those of the raw FE gradient
  MagnetostaticSolver s(test::coarse_domain(h_zone), o);
  s.run();
  magenc::AnalyticField exact(s.domain().magnet);
  // Plane grid over the probe region (|x|, |y| <= 3 mm) at z_s.
  const magenc::GridData g = magenc::GridData::from_range({-3, -3, test::kPlaneZ}, {3, 3, test::kPlaneZ}, {0.2, 0.2, 1});
  const BzErrorStats e = bz_error_on_grid(s.evaluator(), exact, g);
  FeSolution rec = s.solution();
  rec.recover_gradient();
  const FieldEvaluator ev(std::move(rec));
  const BzErrorStats r = bz_error_on_grid(ev, exact, g);
  return {s.stats().dofs, e.rms_rel(), e.max_rel(), r.rms_rel(), r.max_rel()};
}

}  // namespace

TEST_CASE("mu_r = 1: Bz on the sensing plane converges to the exact field", "[field_solver][physics][convergence]") {
  // Two coarse meshes per order (zone edge 0.8 and 0.5 mm). Bounds are ~1.5x
  // the errors measured when this test was written (P1: RMS 6.4e-2 at 0.8 mm;
  // P2: RMS 2.0e-3 at 0.5 mm) so that a real regression fails. Observed rates in
  // the zone's edge length h (measured 1.9 for P1, 3.5 for P2: pre-asymptotic,
  // the 1.1 mm thick zone is barely resolved at 0.8 mm); asserted >= the
  // theoretical B rates 1 (P1) and 2 (P2) minus 0.3, since unstructured TetGen
  // meshes are not nested refinements.
  const int order = GENERATE(1, 2);
  CAPTURE(order);
  const Run a = run_cylinder(0.8, order), b = run_cylinder(0.5, order);
  // Only the zone is refined, so the rate is taken in its edge length h.
  const double rate_h = std::log(a.rms_rel / b.rms_rel) / std::log(0.8 / 0.5);
  CAPTURE(a.dofs, a.rms_rel, a.max_rel, b.dofs, b.rms_rel, b.max_rel, rate_h, b.rms_rec, b.max_rec);
  if (order == 1) {
    CHECK(b.rms_rel < 0.085);
    CHECK(rate_h > 0.7);
  } else {
    CHECK(b.rms_rel < 3e-3);
    CHECK(b.max_rel < 3e-2);
    CHECK(rate_h > 1.7);
  }
  CHECK(b.rms_rel < a.rms_rel);
  // Gradient recovery (solve_field's default) must not make things worse
  // (measured: P1 RMS 5.7e-2 -> 2.0e-2; P2 max error roughly halved).
  CHECK(b.rms_rec < b.rms_rel);
  CHECK(b.max_rec < b.max_rel);
}

TEST_CASE("uniformly magnetized sphere with mu_r != 1 matches its closed form", "[field_solver][physics][closed-form]") {
  // Sphere radius a = 2 mm, Br = 1.2 T along x. Closed form (scaled units):
  //   inside  B = 2 Br/(mu_r + 2) x^ (uniform),
  //   outside psi = m.r/r^3 with m = Br a^3/(mu_r + 2) x^ (T*mm^2).
  // The outside field is a pure dipole, for which the Robin condition is exact,
  // so a 15 mm truncation sphere suffices. Tolerances: absolute 1 % inside
  // (measured 0.2-0.4 %), 2 % on psi outside (measured 0.9-1.1 %, coarse air
  // mesh, h_air 3 mm); the mu_r = 4 / mu_r = 1 ratios (same mesh, exact value
  // 1/2 for both) to 0.5 % (measured 0.2 %): a wrong mu_r handling (ignored:
  // ratio 1; H_in = -M0/(mu_r+1): 0.6) fails clearly.
  auto solve = [](double mu_r) {
    DomainSpec d;
    d.shape = MagnetShape::Sphere;
    d.magnet.radius_mm = 2.0;
    d.magnet.br_T = 1.2;
    d.magnet.mu_r = mu_r;
    d.zone.enabled = false;
    d.mesh.sphere_subdivisions = 3;
    d.mesh.h_magnet_mm = 0.5;
    d.mesh.h_air_mm = 3.0;
    d.mesh.outer_radius_mm = 15.0;
    d.mesh.symmetry_order = 2;            // the mesh this test was measured on
    d.mesh.mesher.min_dihedral_deg = 10;
    auto s = std::make_unique<MagnetostaticSolver>(d, quiet(2));
    s->run();
    return s;
  };
  const auto s1 = solve(1.0), s4 = solve(4.0);
  const double a = 2.0, br = 1.2;
  const std::vector<Eigen::Vector3d> inside = {{0, 0, 0}, {0.7, 0.2, -0.3}, {-0.5, 0.6, 0.4}, {0.1, -0.8, 0.5}};
  const std::vector<Eigen::Vector3d> outside = {{4, 0, 0}, {-3, 1, 1}, {3, 2, 2}, {-2, 3, -3}};
  for (const auto* s : {s1.get(), s4.get()}) {
    const double mu_r = s->domain().magnet.mu_r;
    CAPTURE(mu_r);
    const double b_in = 2.0 * br / (mu_r + 2.0);
    for (const auto& p : inside) {
      const Eigen::Vector3d B = *s->evaluator().B_T(p);
      CAPTURE(p.transpose(), B.transpose(), b_in);
      CHECK((B - Eigen::Vector3d(b_in, 0, 0)).norm() < 0.01 * b_in);
    }
    const Eigen::Vector3d m(br * a * a * a / (mu_r + 2.0), 0, 0);
    for (const auto& p : outside) {
      const double r = p.norm(), psi_exact = m.dot(p) / (r * r * r);
      const double psi = *s->evaluator().psi_Tmm(p);
      CAPTURE(p.transpose(), psi, psi_exact);
      CHECK(std::abs(psi - psi_exact) < 0.02 * std::abs(psi_exact));
    }
  }
  for (const auto& p : outside) {
    const double ratio = *s4->evaluator().psi_Tmm(p) / *s1->evaluator().psi_Tmm(p);
    CAPTURE(p.transpose(), ratio);
    CHECK(ratio == Approx(0.5).epsilon(0.005));
  }
  const double ratio_in = s4->evaluator().B_T(Eigen::Vector3d(0.2, 0.1, 0))->x() / s1->evaluator().B_T(Eigen::Vector3d(0.2, 0.1, 0))->x();
  CHECK(ratio_in == Approx(0.5).epsilon(0.005));
}

TEST_CASE("a high-mu_r shaft under the magnet pulls flux towards it", "[field_solver][physics]") {
  auto solve = [](bool shaft, double shaft_mu) {
    // Magnet/shaft edge 0.7 mm: at 1.0 mm the field near the face was not resolved
    // (tangential fraction at the 2nd point 0.26 -> 0.38 -> 0.50 at h 1.0, 0.7, 0.5 mm).
    DomainSpec d = test::coarse_domain(0.8, 0.7);
    d.shaft.enabled = shaft;
    d.shaft.radius_mm = 3.0;
    d.shaft.length_mm = 8.0;
    d.shaft.gap_mm = 1.0;
    d.shaft.mu_r = shaft_mu;
    auto s = std::make_unique<MagnetostaticSolver>(d, quiet(2));
    s->run();
    return s;
  };
  const auto unit = solve(true, 1.0), steel = solve(true, 1000.0);
  // Just above the shaft's top face (z = -3): at a mu_r >> 1 surface the
  // tangential H vanishes, so B turns normal to the face (flux is pulled into
  // the steel). Compared with a mu_r = 1 shaft, whose mesh is identical.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1.0, 0.5, -2.95), Eigen::Vector3d(-1.5, 0.3, -2.95), Eigen::Vector3d(0.2, -1.2, -2.95)}) {
    const Eigen::Vector3d bu = *unit->evaluator().B_T(p), bs = *steel->evaluator().B_T(p);
    const double tan_unit = bu.head<2>().norm() / bu.norm(), tan_steel = bs.head<2>().norm() / bs.norm();
    CAPTURE(p.transpose(), bu.transpose(), bs.transpose(), tan_unit, tan_steel);
    // Measured tangential fractions (h 0.7 mm): steel 0.03-0.25, mu_r = 1 shaft 0.38-0.99.
    CHECK(tan_steel < 0.35 * tan_unit);
  }
  // The steel is magnetized by the magnet's return field (along -x under the
  // magnet), so it acts like an opposing dipole below: on the sensing plane Bz
  // drops a little (measured -3 % at r0 = 2.4 mm); a big change would mean a
  // wrong coupling.
  const Eigen::Vector3d probe(2.4, 0, test::kPlaneZ);
  const double bz_unit = unit->evaluator().B_T(probe)->z(), bz_steel = steel->evaluator().B_T(probe)->z();
  CAPTURE(bz_unit, bz_steel);
  CHECK(bz_steel < bz_unit);
  CHECK(bz_steel > 0.9 * bz_unit);
}
