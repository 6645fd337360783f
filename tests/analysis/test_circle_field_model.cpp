// The local field models on the probe circle (src/analysis/circle_field_model.hpp): the model built
// from the exact field's rotational symmetry against direct fits, and the fast pipeline's Monte Carlo
// (src/analysis/fast_pipeline.hpp) independent of the thread count.
#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <random>

#include "analysis/circle_field_model.hpp"
#include "analysis/fast_pipeline.hpp"
#include "analysis/tolerance.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"

using namespace magenc;

namespace {
constexpr double kPlaneZ = 2.0 + 2.55;  // z_s of the default magnet
using Construction = CircleFieldModel::Construction;

// Largest |a - b| of the two models' B (all components when full_vector) over every node and
// `draws` random displacements within the reach (magnet frame, mm).
double max_model_diff_T(const CircleFieldModel& a, const CircleFieldModel& b, int draws, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> u(static_cast<std::size_t>(a.terms()));
  double d = 0;
  for (int i = 0; i < draws; ++i) {
    const double ex = unit(rng) * a.reach_xy_mm() / std::sqrt(2.0), ey = unit(rng) * a.reach_xy_mm() / std::sqrt(2.0),
                 ez = unit(rng) * a.reach_z_mm();
    a.monomials(ex, ey, ez, u.data());
    for (int j = 0; j < a.nodes(); ++j) {
      if (a.full_vector()) {
        double Ba[3], Bb[3];
        a.B_T(j, u.data(), Ba);
        b.B_T(j, u.data(), Bb);
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(Ba[c] - Bb[c]));
      } else {
        d = std::max(d, std::abs(a.bz_T(j, u.data()) - b.bz_T(j, u.data())));
      }
    }
  }
  return d;
}
}  // namespace

// B(Rz(a) p; M) = Rz(a) B(p; Rz(-a) M), B linear in M: node 0's fits, one per magnetization axis,
// give every node. The least-squares fit is linear and commutes with a rotation of its stencil, so the
// symmetry-built model must equal direct fits on stencils turned with the nodes up to round-off
// (1e-12 T against fields of ~0.1 T: about 1e4 ulp of the field, the re-expansion's conditioning), with
// 2 (3 with an axial part) x 125 field evaluations instead of N x 125. Against the axis-aligned stencils
// (the other construction) the models differ by the fit error only: bounded by 2x the larger fit residual.
TEST_CASE("circle field model: built from the rotational symmetry equals direct fits", "[analysis][physics]") {
  Magnet mag;
  const double azimuth = GENERATE(0.0, 30.0);
  const double elevation = GENERATE(0.0, 20.0);
  const bool full = GENERATE(false, true);
  mag.magnetization_deg = azimuth;
  mag.magnetization_elevation_deg = elevation;
  CAPTURE(azimuth, elevation, full);
  const AnalyticField field(mag);
  REQUIRE(field.axisymmetric_parts().has_value());
  const int N = 72;
  const double r0 = 1.7, reach_xy = 0.35, reach_z = 0.3;
  const CircleFieldModel sym(field, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::symmetry);
  const CircleFieldModel rot(field, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::rotated);
  const CircleFieldModel axis(field, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::axis_aligned);
  const CircleFieldModel automatic(field, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::automatic);
  CHECK(automatic.construction() == Construction::symmetry);
  // The default keeps direct fits (the radius study's numbers; circle_field_model.hpp says why).
  const CircleFieldModel by_default(field, r0, kPlaneZ, N, reach_xy, reach_z, 4, full);
  CHECK(by_default.construction() == Construction::axis_aligned);
  CHECK(sym.field_evaluations() == (elevation != 0.0 ? 3 : 2) * 125);
  CHECK(rot.field_evaluations() == N * 125);
  CHECK(axis.field_evaluations() == N * 125);

  const double d_rot = max_model_diff_T(sym, rot, 20, 7);
  CAPTURE(d_rot);
  CHECK(d_rot < 1e-12);
  for (int j = 0; j < N; ++j) CHECK(std::abs(sym.node_bz_T(j) - field.Bz_T(Vec3(r0 * std::cos(2 * kPi * j / N), r0 * std::sin(2 * kPi * j / N), kPlaneZ))) < 1e-14);
  CHECK(std::abs(sym.amplitude_T() - axis.amplitude_T()) < 1e-14);
  CHECK(std::abs(sym.fit_residual_T() - rot.fit_residual_T()) < 1e-12);

  const double d_axis = max_model_diff_T(sym, axis, 20, 8);
  const double resid = std::max(sym.fit_residual_T(), axis.fit_residual_T());
  CAPTURE(d_axis, resid);
  CHECK(d_axis <= 2 * resid);
  CHECK(d_axis > 1e-12);  // the two constructions are different fits (the test can tell them apart)

  // Both against the exact field at displaced points of a few nodes: within the fit residual's scale.
  std::vector<double> u(static_cast<std::size_t>(sym.terms()));
  double d_exact = 0;
  for (int j = 0; j < N; j += 9) {
    const double phi = 2 * kPi * j / N, ex = 0.1, ey = -0.15, ez = 0.2;
    sym.monomials(ex, ey, ez, u.data());
    const Vec3 p(r0 * std::cos(phi) + ex, r0 * std::sin(phi) + ey, kPlaneZ + ez);
    d_exact = std::max(d_exact, std::abs(sym.bz_T(j, u.data()) - field.Bz_T(p)));
  }
  CAPTURE(d_exact);
  CHECK(d_exact <= 2 * resid);
}

TEST_CASE("circle field model: the symmetry build needs a source that declares it", "[analysis][bad-input]") {
  const LinearField linear;
  CHECK_FALSE(linear.axisymmetric_parts().has_value());
  CHECK_THROWS_AS(CircleFieldModel(linear, 1.0, kPlaneZ, 36, 0.3, 0.2, 4, false, Construction::symmetry), InputError);
  const CircleFieldModel automatic(linear, 1.0, kPlaneZ, 36, 0.3, 0.2, 4, false, Construction::automatic);
  // Bz = k x is the first harmonic exactly: automatic takes the symmetrized build, with no asymmetry.
  CHECK(automatic.construction() == Construction::symmetrized);
  CHECK(automatic.field_evaluations() == CircleFieldModel::kSymmetrizedAzimuths * 125 + 36);
  CHECK(automatic.node_residual_max_T() < 1e-15);
}

// The Monte Carlo writes sample i's result to row i and reduces nothing across threads: the pp of every
// sample (tilted mounts through the full-vector model) is bitwise the same with 1 and 2 threads.
TEST_CASE("fast pipeline: Monte Carlo results identical with 1 and 2 threads", "[analysis][determinism]") {
  const AnalyticField field{Magnet{}};
  ToleranceBox box;
  box.tilt_x_deg = box.tilt_y_deg = box.magnet_tilt_deg = 0.5;
  const CircleFieldModel model(field, 2.0, kPlaneZ, 360, 0.35, 0.3, 4, true);
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two", "arrays"), ProbeArray::parse("ring:8", "arrays")};
  const FastPipeline fast(model, arrays);
  const auto cases = monte_carlo_cases(box, 400, 3);
  auto run = [&](int threads) {
    const int saved = omp_get_max_threads();
    omp_set_num_threads(threads);
    const Eigen::MatrixXd v = evaluate_cases(cases, 2, [&](std::size_t, const ToleranceCase& c, double* o) { fast.pp(c, o); });
    omp_set_num_threads(saved);
    return v;
  };
  const Eigen::MatrixXd one = run(1), two = run(2);
  CHECK((one.array() == two.array()).all());
  CHECK(one.col(0).maxCoeff() > 0.1);  // a real error, not zeros
}

TEST_CASE("fast pipeline: readings interpolated in theta equal the direct ones on symmetry-built models",
          "[analysis][cross-check]") {
  // Every probe reading of a symmetry-built model is a trigonometric polynomial of degree <= 11 in
  // theta: 24 of the 360 nodes determine it (degree <= 11, the 12th term at half weight). The check has
  // teeth: with 12 nodes (degree <= 5 resolved) eps differs by 6.5e-9 deg on these cases. Tilted, eccentric, tempered, stray-field, signal-chain and
  // elevation cases (the axial model), untilted and tilted paths, against every node evaluated.
  Magnet mag;
  Magnet md = mag, ma = mag;
  ma.magnetization_elevation_deg = 90;
  const AnalyticField dia(md), ax(ma);
  const double r0 = 2.1, L = mag.height_mm;
  const CircleFieldModel model(dia, r0, kPlaneZ, 360, 0.5, 0.4, 4, true, Construction::symmetry);
  const CircleFieldModel axial(ax, r0, kPlaneZ, 360, 0.5, 0.4, 4, true, Construction::symmetry);
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4"), ProbeArray::parse("ring:8")};
  const FastPipeline interp(model, arrays, L, &axial, 0.0);
  FastPipeline direct(model, arrays, L, &axial, 0.0);
  direct.evaluate_every_node();
  REQUIRE(interp.coarse_steps() == 24);
  REQUIRE(direct.coarse_steps() == 0);
  // Direct fits (axis_aligned) keep every node.
  const CircleFieldModel axis(dia, r0, kPlaneZ, 360, 0.5, 0.4, 4, true);
  CHECK(FastPipeline(axis, arrays, L).coarse_steps() == 0);
  ToleranceBox box;
  box.tilt_x_deg = box.tilt_y_deg = 1.0;
  box.magnet_tilt_deg = 1.0;
  box.temperature_min_C = -40;
  box.temperature_max_C = 125;
  box.stray_mT = 2.0;
  box.offset_cos_mT = box.offset_sin_mT = 1.0;
  box.gain_mismatch = 0.02;
  box.phase_error_deg = 1.0;
  box.magnetization_elevation_deg = 3.0;
  std::vector<ToleranceCase> cases = monte_carlo_cases(box, 12, 11);
  ToleranceBox flat = box;
  flat.tilt_x_deg = flat.tilt_y_deg = flat.magnet_tilt_deg = 0;
  for (const auto& c : monte_carlo_cases(flat, 12, 12)) cases.push_back(c);
  for (const auto& c : box.corners()) {
    ToleranceCase tc;
    tc.mount = c;
    cases.push_back(tc);
    if (cases.size() > 40) break;
  }
  int tilted = 0;
  for (const auto& c : cases) {
    tilted += c.mount.tilted();
    std::vector<Eigen::VectorXd> ei, ed;
    double fi_lo[3], fi_hi[3], fd_lo[3], fd_hi[3], pi[3], pd[3];
    interp.eps_field(c, ei, fi_lo, fi_hi);
    direct.eps_field(c, ed, fd_lo, fd_hi);
    interp.pp(c, pi);
    direct.pp(c, pd);
    // Without the field window (eps, pp): only the channels C, S of each array are interpolated.
    std::vector<Eigen::VectorXd> ci, cd;
    interp.eps(c, ci);
    direct.eps(c, cd);
    for (int a = 0; a < 3; ++a) {
      const double de = (ei[a] - ed[a]).cwiseAbs().maxCoeff();
      const double dc = (ci[a] - cd[a]).cwiseAbs().maxCoeff();
      CAPTURE(dc);
      CHECK(dc <= 1e-10);
      CAPTURE(a, c.mount.tilted(), de, fi_lo[a], fd_lo[a], fi_hi[a], fd_hi[a]);
      // The peak readings to 1e-12 relative; eps (atan2 of the channels) to 1e-10 deg.
      CHECK(std::abs(fi_lo[a] - fd_lo[a]) <= 1e-12 * fd_lo[a]);
      CHECK(std::abs(fi_hi[a] - fd_hi[a]) <= 1e-12 * fd_hi[a]);
      CHECK(de <= 1e-10);
      CHECK(std::abs(pi[a] - pd[a]) <= 1e-10);
    }
  }
  CHECK(tilted >= 12);
}

TEST_CASE("fast pipeline: eps_field_bounds brackets eps_field's window strictly and gives its eps", "[analysis][cross-check]") {
  // Symmetry-built models (the coarse path and its bounds) and direct fits (every node: the bounds are the
  // values); eccentric, tilted, tempered, stray-field and signal-chain cases.
  const AnalyticField field{Magnet{}};
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4"), ProbeArray::parse("ring:8")};
  ToleranceBox box;
  box.sx_mm = box.sy_mm = 0.15;
  box.dz_mm = 0.2;
  box.tilt_x_deg = box.tilt_y_deg = 1.0;
  box.temperature_min_C = -40;
  box.temperature_max_C = 125;
  box.stray_mT = 1.0;
  box.offset_cos_mT = 0.5;
  box.phase_error_deg = 1.0;
  using C = CircleFieldModel::Construction;
  for (const C build : {C::symmetry, C::axis_aligned}) {
    const CircleFieldModel model(field, 1.8, kPlaneZ, 360, 0.5, 0.4, 4, true, build);
    const FastPipeline fast(model, arrays);
    REQUIRE((fast.coarse_steps() > 0) == (build == C::symmetry));
    double widest = 0;
    for (const ToleranceCase& c : monte_carlo_cases(box, 40, 9)) {
      std::vector<Eigen::VectorXd> e1, e2;
      std::vector<UnitAngles> u1, u2;
      double fmin[3], fmax[3], b[4][3];
      fast.eps_field(c, e1, fmin, fmax, &u1);
      fast.eps_field_bounds(c, e2, b[0], b[1], b[2], b[3], &u2);
      for (int a = 0; a < 3; ++a) {
        CAPTURE(a, fmin[a], b[0][a], b[1][a], fmax[a], b[2][a], b[3][a]);
        CHECK((e1[std::size_t(a)] - e2[std::size_t(a)]).cwiseAbs().maxCoeff() <= 1e-12);
        CHECK((u1[std::size_t(a)].cos_psi - u2[std::size_t(a)].cos_psi).cwiseAbs().maxCoeff() <= 1e-14);
        if (build == C::symmetry) {
          CHECK(b[0][a] < fmin[a]);
          CHECK(fmin[a] < b[1][a]);
          CHECK(b[2][a] < fmax[a]);
          CHECK(fmax[a] < b[3][a]);
          widest = std::max(widest, (b[3][a] - b[2][a]) / fmax[a]);
        } else {
          CHECK(b[0][a] == fmin[a]);
          CHECK(b[1][a] == fmin[a]);
          CHECK(b[2][a] == fmax[a]);
          CHECK(b[3][a] == fmax[a]);
        }
      }
    }
    // The bounds are narrow (the curvature bound over 15 deg: about 1 % of the peak), or they would not save work.
    if (build == C::symmetry) CHECK(widest < 0.03);
  }
}

TEST_CASE("fast pipeline: pp from the bounded intervals equals pp over every node", "[analysis][cross-check]") {
  // pp_bounded evaluates the 360 nodes only in the intervals its curvature bound cannot exclude. Against
  // the same pipeline over every node and against max - min of eps (atan2): small and large errors
  // (r0 = 0.7 mm with `two` reaches tens of degrees, where the bound is weak and the full pass runs),
  // signal-chain offsets and phase errors, tilted and untilted paths.
  const AnalyticField field{Magnet{}};
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4"), ProbeArray::parse("ring:8")};
  long bounded = 0, calls = 0, fallbacks = 0;
  for (double r0 : {0.7, 1.5, 2.1, 3.2}) {
    const CircleFieldModel model(field, r0, kPlaneZ, 360, 0.5, 0.4, 4, true, Construction::symmetry);
    const FastPipeline fast(model, arrays);
    FastPipeline every(model, arrays);
    every.evaluate_pp_on_every_node();
    ToleranceBox box;
    box.sx_mm = box.sy_mm = box.dx_mm = box.dy_mm = 0.15;
    box.dz_mm = 0.3;
    box.tilt_x_deg = box.tilt_y_deg = box.magnet_tilt_deg = 1.0;
    box.offset_cos_mT = box.offset_sin_mT = 2.0;
    box.gain_mismatch = 0.03;
    box.phase_error_deg = 2.0;
    std::vector<ToleranceCase> cases = monte_carlo_cases(box, 60, 21);
    ToleranceBox flat = box;
    flat.tilt_x_deg = flat.tilt_y_deg = flat.magnet_tilt_deg = 0;
    for (const auto& c : monte_carlo_cases(flat, 60, 22)) cases.push_back(c);
    for (const auto& c : cases) {
      double pb[3], pe[3], pa[3];
      const long before = FastPipeline::bounded_pp_count();
      fast.pp(c, pb);
      const bool took = FastPipeline::bounded_pp_count() > before;
      bounded += took;
      fallbacks += !took;
      ++calls;
      every.pp(c, pe);
      fast.pp_atan2(c, pa);
      for (int a = 0; a < 3; ++a) {
        CAPTURE(r0, a, took, pb[a], pe[a], pa[a]);
        CHECK(std::abs(pb[a] - pe[a]) <= 1e-10);
        CHECK(std::abs(pb[a] - pa[a]) <= 1e-10);
      }
    }
  }
  CAPTURE(calls, bounded, fallbacks);
  CHECK(bounded >= calls / 2);  // the bounded route is the usual one
  CHECK(fallbacks > 0);         // and the large errors take the full pass
}

// At a speed the fast pipeline applies the same steady-state chain (probe/speed.hpp) to each array's
// channels: its eps equals angle_error()'s at speed to the surrogate's own static accuracy, its pp is
// max - min of that eps, and the psi it returns is theta + eps.
TEST_CASE("fast pipeline at a speed agrees with the direct pipeline", "[analysis][cross-check]") {
  const AnalyticField field{Magnet{}};
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, 0.3, 0.3, 4, false);
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two", "arrays"), ProbeArray::parse("diff4", "arrays")};
  FastPipeline fast(model, arrays);
  SpeedChain speed;
  speed.rpm = 6000;
  speed.delay_us = 96;
  speed.skew_us = 2;
  speed.filter_hz = 1000;
  speed.sample_hz = 7777;  // off the 360-node grid
  ToleranceCase c;
  c.mount.sx_mm = 0.04;
  c.mount.dx_mm = 0.07;
  c.mount.dz_mm = 0.1;
  std::vector<Eigen::VectorXd> still, moving;
  fast.eps(c, still);
  fast.set_speed(speed);
  std::vector<UnitAngles> psi;
  fast.eps(c, moving, &psi);
  double pp[2];
  fast.pp(c, pp);
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    ProbeSetup s;
    s.array = arrays[a];
    s.r0_mm = 2.4;
    s.plane_z_mm = kPlaneZ;
    s.steps = 360;
    const double static_diff = (angle_error(field, s, c.mount).eps_deg - still[a]).cwiseAbs().maxCoeff();
    s.speed = speed;
    const AngleErrorResult direct = angle_error(field, s, c.mount);
    const double moving_diff = (direct.eps_deg - moving[a]).cwiseAbs().maxCoeff();
    CAPTURE(a, static_diff, moving_diff);
    CHECK(moving_diff <= 2 * static_diff + 1e-9);
    CHECK((moving[a] - still[a]).cwiseAbs().maxCoeff() > 0.5);  // the speed acts
    CHECK(pp[a] == moving[a].maxCoeff() - moving[a].minCoeff());
    for (int m = 0; m < 360; m += 37) {
      const double out = deg_to_rad(360.0 * m / 360 + moving[a][m]);
      CHECK(psi[a].cos_psi[m] == Approx(std::cos(out)).margin(1e-12));
      CHECK(psi[a].sin_psi[m] == Approx(std::sin(out)).margin(1e-12));
    }
  }
}

namespace {
// The exact field with a pattern that breaks its rotational symmetry as a D_16 mesh does (an FE
// solution's artefact harmonics 16 k +- 1): Bz + rel 0.05 T cos(15 phi), Bx and By unchanged; declares
// no symmetry.
class PatternedField final : public FieldSource {
 public:
  PatternedField(const Magnet& m, double rel) : exact_(m), rel_(rel) {}
  std::string name() const override { return "patterned"; }
  Vec3 B_T(const Vec3& p) const override {
    Vec3 b = exact_.B_T(p);
    b.z() += rel_ * 0.05 * std::cos(15.0 * std::atan2(p.y(), p.x()));
    return b;
  }
  double Bz_T(const Vec3& p) const override { return B_T(p).z(); }
  using FieldSource::B_T;
  using FieldSource::Bz_T;

 private:
  AnalyticField exact_;
  double rel_;
};
}  // namespace

// The symmetrized build: node 0's turned stencil at 12 azimuths, projected onto cos, sin and the mean.
// The pattern's harmonic in the samples (15 = 3 mod 12) does not fold onto them, so
// the model's coefficients must equal the symmetry-built model of the exact field up to round-off
// (1e-12 T, as symmetry against rotated), and its node residual is the pattern at the nodes exactly.
// automatic takes it while the residual is within 1e-4 of the amplitude and direct fits beyond.
TEST_CASE("circle field model: the symmetrized build is the symmetric part plus the asymmetry at the nodes",
          "[analysis][physics]") {
  const Magnet mag;
  const AnalyticField exact(mag);
  const bool full = GENERATE(false, true);
  CAPTURE(full);
  const int N = 72;
  const double r0 = 1.7, reach_xy = 0.35, reach_z = 0.3, rel = 2e-5;
  const PatternedField field(mag, rel);
  const CircleFieldModel sym(exact, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::symmetry);
  const CircleFieldModel model(field, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::automatic);
  REQUIRE(model.construction() == Construction::symmetrized);
  CHECK(model.field_evaluations() == CircleFieldModel::kSymmetrizedAzimuths * 125 + N);
  REQUIRE(model.has_node_residual());
  CHECK_FALSE(sym.has_node_residual());
  const double d_sym = max_model_diff_T(model, sym, 20, 9);
  CAPTURE(d_sym);
  CHECK(d_sym < 1e-12);
  double worst = 0, largest = 0;
  for (int j = 0; j < N; ++j) {
    const double phi = 2 * kPi * j / N;
    const Vec3 p(r0 * std::cos(phi), r0 * std::sin(phi), kPlaneZ);
    CHECK(model.node_bz_T(j) == field.Bz_T(p));  // the field itself at the node (the same point)
    const double pattern = field.Bz_T(p) - exact.Bz_T(p);
    worst = std::max(worst, std::abs(model.node_residual_T(0, j) - pattern));
    largest = std::max(largest, std::abs(pattern));
    if (full) CHECK(std::abs(model.node_residual_T(1, j)) + std::abs(model.node_residual_T(2, j)) < 1e-12);
  }
  CAPTURE(worst, largest);
  CHECK(worst < 1e-12);
  CHECK(largest > 1e-8);  // the pattern is there to be kept
  CHECK(std::abs(model.amplitude_T() - sym.amplitude_T()) < 1e-3 * sym.amplitude_T());

  // A pattern of 1e-3 of 0.05 T: automatic falls back to direct fits.
  const PatternedField strong(mag, 1e-3);
  const CircleFieldModel fallback(strong, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::automatic);
  CHECK(fallback.construction() == Construction::axis_aligned);
  CHECK_FALSE(fallback.has_node_residual());
  // Asked for, the symmetrized build serves it all the same.
  CHECK(CircleFieldModel(strong, r0, kPlaneZ, N, reach_xy, reach_z, 4, full, Construction::symmetrized).construction() ==
        Construction::symmetrized);
}

// The pipeline on a symmetrized model against the direct pipeline on the patterned field itself, at
// random mounts (eccentric, tilted), 360 theta each. The model omits only how the pattern changes with
// the displacement: at most dB = max |pattern(node + e) - pattern(node)| over the reach (sampled here) per
// probe reading, so eps moves by at most sum_k (|w_cos,k| + |w_sin,k|) dB / |(C, S)| rad, and pp by twice
// that, on top of the local polynomials' own error, which the same pipeline on the exact field's symmetry
// model measures (its pp against the direct pipeline on the exact field). pp_bounded with the asymmetry
// added equals the pass over every node (1e-10 deg), and eps_field_bounds brackets eps_field's window.
TEST_CASE("fast pipeline: a symmetrized model reproduces the direct pipeline within the pattern's variation",
          "[analysis][cross-check]") {
  const Magnet mag;
  const AnalyticField exact(mag);
  const double rel = 2e-4, r0 = 2.1, L = mag.height_mm;  // rel: 10x a D_16 FE mesh's artefact, to see it
  const PatternedField field(mag, rel);
  ToleranceBox box;
  box.sx_mm = box.sy_mm = box.dx_mm = box.dy_mm = 0.1;
  box.dz_mm = 0.2;
  box.tilt_x_deg = box.tilt_y_deg = box.magnet_tilt_deg = 0.5;
  const CircleFieldModel model(field, r0, kPlaneZ, 360, 0.45, 0.3, 4, true, Construction::symmetrized);
  const CircleFieldModel sym(exact, r0, kPlaneZ, 360, 0.45, 0.3, 4, true, Construction::symmetry);
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4"), ProbeArray::parse("ring:8")};
  const FastPipeline fast(model, arrays, L), fast_exact(sym, arrays, L);
  FastPipeline every(model, arrays, L);
  every.evaluate_pp_on_every_node();
  REQUIRE(fast.coarse_steps() == 24);
  // dB: the pattern's largest change over the reach, sampled around a few nodes.
  double dB = 0;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int j = 0; j < 360; j += 7)
    for (int k = 0; k < 40; ++k) {
      const double phi = 2 * kPi * j / 360;
      const Vec3 p0(r0 * std::cos(phi), r0 * std::sin(phi), kPlaneZ);
      const Vec3 p = p0 + Vec3(unit(rng) * 0.45, unit(rng) * 0.45, unit(rng) * 0.3);
      dB = std::max(dB, std::abs((field.Bz_T(p) - exact.Bz_T(p)) - (field.Bz_T(p0) - exact.Bz_T(p0))));
    }
  std::vector<ToleranceCase> cases = monte_carlo_cases(box, 16, 31);
  ToleranceBox flat = box;
  flat.tilt_x_deg = flat.tilt_y_deg = flat.magnet_tilt_deg = 0;
  for (const auto& c : monte_carlo_cases(flat, 8, 32)) cases.push_back(c);
  long bounded = 0;
  for (const auto& c : cases) {
    double pf[3], pe[3], px[3], pv[3];
    const long before = FastPipeline::bounded_pp_count();
    fast.pp(c, pf);
    bounded += FastPipeline::bounded_pp_count() > before;
    every.pp(c, pv);
    fast_exact.pp(c, px);
    fast.pp_atan2(c, pe);
    std::vector<Eigen::VectorXd> e;
    double lo_lo[3], lo_hi[3], hi_lo[3], hi_hi[3], fmin[3], fmax[3];
    fast.eps_field_bounds(c, e, lo_lo, lo_hi, hi_lo, hi_hi);
    fast.eps_field(c, e, fmin, fmax);
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      ProbeSetup setup;
      setup.array = arrays[a];
      setup.r0_mm = r0;
      setup.plane_z_mm = kPlaneZ;
      setup.steps = 360;
      setup.magnet_height_mm = L;
      const double direct = error_spectrum(field, setup, c.mount).pp_deg;
      const double direct_exact = error_spectrum(exact, setup, c.mount).pp_deg;
      double wsum = 0;
      for (std::size_t k = 0; k < arrays[a].size(); ++k) wsum += std::abs(arrays[a].w_cos[k]) + std::abs(arrays[a].w_sin[k]);
      double C = 0, S = 0;  // |(C, S)| of the ideal mount at theta = 0 (half of it: a floor over the turn and the box)
      for (std::size_t k = 0; k < arrays[a].size(); ++k) {
        const double b = deg_to_rad(arrays[a].angle_deg[k]);
        const double bz = exact.Bz_T(Vec3(r0 * std::cos(b), r0 * std::sin(b), kPlaneZ));
        C += arrays[a].w_cos[k] * bz;
        S += arrays[a].w_sin[k] * bz;
      }
      const double amp = std::hypot(C, S);
      const double bound = std::abs(px[a] - direct_exact) + 2.0 * rad_to_deg(wsum * dB / (0.5 * amp));
      CAPTURE(a, c.mount.tilted(), pf[a], direct, px[a], direct_exact, bound, dB);
      CHECK(std::abs(pf[a] - direct) <= bound);
      CHECK(std::abs(pf[a] - pv[a]) <= 1e-10);
      CHECK(std::abs(pf[a] - pe[a]) <= 1e-10);
      CHECK(lo_lo[a] < fmin[a]);
      CHECK(fmin[a] < lo_hi[a]);
      CHECK(hi_lo[a] < fmax[a]);
      CHECK(fmax[a] < hi_hi[a]);
    }
  }
  CHECK(bounded >= static_cast<long>(cases.size()) / 2);
  // The pattern shows: the ideal mount's pp is that of the direct pipeline (the field at the nodes).
  double p0[3];
  fast.pp(ToleranceCase{Mount{}, SignalChain{}, 0.0}, p0);
  ProbeSetup setup;
  setup.array = arrays[0];
  setup.r0_mm = r0;
  setup.plane_z_mm = kPlaneZ;
  setup.steps = 360;
  setup.magnet_height_mm = L;
  const double ideal = error_spectrum(field, setup, Mount{}).pp_deg;
  CAPTURE(p0[0], ideal);
  CHECK(ideal > 1e-3);
  CHECK(std::abs(p0[0] - ideal) <= 1e-9);
}
