// The radius scan's surrogate (src/analysis/radius_scan.hpp) against the direct
// probe-path pipeline (angle_error.hpp), and its recommendation logic.
#include <catch2/catch.hpp>

#include <cmath>

#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "core/errors.hpp"
#include "analysis/radius_scan.hpp"
#include "analysis/tolerance.hpp"

using namespace magenc;

namespace {
Magnet default_magnet() { return Magnet{}; }
constexpr double kPlaneZ = 2.0 + 2.55;  // z_s of the default magnet
}  // namespace

// Stated tolerance of the surrogate (default order 4) on the default box
// (|s|, |d| <= 0.1*sqrt2, |dz| <= 0.2 mm): peak-to-peak and every Fourier
// coefficient within 0.005 deg or 0.05 % of pp (whichever is larger) of the
// direct pipeline on the same theta grid; order 3 within 0.02 deg or 0.2 %.
// The measured discrepancy is reported by the study.
TEST_CASE("surrogate matches the direct pipeline on corners and random samples", "[radius][surrogate]") {
  const AnalyticField field(default_magnet());
  const double r0 = GENERATE(0.6, 2.4, 3.4);
  const int order = GENERATE(3, 4);
  CAPTURE(r0, order);
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4"),
                                          ProbeArray::parse("ring:8")};
  const ToleranceBox box;
  const CircleFieldModel model(field, r0, kPlaneZ, 360, box.max_inplane_mm(), box.dz_mm, order);
  const FastPipeline fast(model, arrays);
  std::vector<Mount> cases = box.corners();
  cases.resize(8);
  for (const auto& m : monte_carlo_samples(box, 4, 99)) cases.push_back(m);
  for (const auto& m : cases) {
    std::vector<Eigen::VectorXd> eps;
    fast.eps(m, eps);
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      ProbeSetup setup{arrays[a], r0, kPlaneZ, 360};
      const Spectrum direct = error_spectrum(field, setup, m);
      const Spectrum sur = spectrum_of(eps[a]);
      const double tol = order == 4 ? std::max(0.005, 0.0005 * direct.pp_deg) : std::max(0.02, 0.002 * direct.pp_deg);
      CAPTURE(arrays[a].name, m.sx_mm, m.sy_mm, m.dx_mm, m.dy_mm, m.dz_mm, direct.pp_deg, sur.pp_deg);
      CHECK(std::abs(sur.pp_deg - direct.pp_deg) <= tol);
      CHECK(std::abs(sur.a0_deg - direct.a0_deg) <= tol);
      for (int n = 1; n <= kHarmonics; ++n) {
        CAPTURE(n);
        CHECK(std::abs(sur.a_deg[n] - direct.a_deg[n]) <= tol);
        CHECK(std::abs(sur.b_deg[n] - direct.b_deg[n]) <= tol);
      }
    }
  }
}

TEST_CASE("surrogate: ideal mount has no error and the amplitude is the field's", "[radius][surrogate]") {
  const AnalyticField field(default_magnet());
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, 0.3, 0.2, 3);
  const FastPipeline fast(model, {ProbeArray::parse("two"), ProbeArray::parse("ring:8")});
  double pp[2];
  fast.pp(Mount{}, pp);
  CHECK(pp[0] < 1e-6);
  CHECK(pp[1] < 1e-6);
  // Bz = A cos(phi) on the circle (diametric magnet): amplitude = Bz at phi = 0.
  CHECK(model.amplitude_T() == Approx(field.Bz_T(Vec3(2.4, 0, kPlaneZ))).epsilon(1e-9));
}

TEST_CASE("surrogate rejects arrays whose probes miss the theta grid", "[radius][bad-input]") {
  const AnalyticField field(default_magnet());
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, 0.3, 0.2, 3);
  CHECK_THROWS_WITH(FastPipeline(model, {ProbeArray::parse("ring:7")}), Catch::Contains("radius.fast_steps"));
}

TEST_CASE("worst corner on the linear field: dy and dz cannot matter", "[radius][worst]") {
  // Bz = k x: dy moves probes along y (no field change) and dz scales nothing,
  // so the worst corner over a box with large dy/dz tolerances equals that of
  // the box without them (physics.md, linear model).
  const LinearField field;
  const ProbeArray two = ProbeArray::parse("two");
  auto worst = [&](const ToleranceBox& box) {
    const CircleFieldModel model(field, 2.4, kPlaneZ, 360, box.max_inplane_mm(), box.dz_mm, 3);
    const FastPipeline fast(model, {two});
    const auto corners = box.corners();
    const Eigen::MatrixXd v = evaluate_cases(corners, 1, [&](std::size_t, const Mount& m, double* o) { fast.pp(m, o); });
    return worst_case(v, 0).value;
  };
  const double w0 = worst(ToleranceBox{0.1, 0.1, 0.1, 0.0, 0.0});
  const double w1 = worst(ToleranceBox{0.1, 0.1, 0.1, 0.3, 0.3});
  CHECK(w1 == Approx(w0).epsilon(1e-9));
  // And the surrogate is exact for the linear field: compare with the direct pipeline.
  const Mount m{0.1, -0.1, 0.1, 0, 0};
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, 0.3, 0.1, 3);
  double pp;
  FastPipeline(model, {two}).pp(m, &pp);
  CHECK(pp == Approx(error_spectrum(field, ProbeSetup{two, 2.4, kPlaneZ, 360}, m).pp_deg).epsilon(1e-9));
}

TEST_CASE("find_peak and recommend", "[radius]") {
  std::vector<double> x, y;
  for (int i = 0; i <= 30; ++i) {
    x.push_back(0.1 * i);
    y.push_back(1.0 - (x.back() - 1.234) * (x.back() - 1.234));
  }
  const Peak p = find_peak(x, y);
  CHECK(p.x == Approx(1.234).epsilon(1e-9));
  CHECK_FALSE(p.at_edge);
  std::vector<RadiusRow> rows(5);
  const double tot[5] = {3.0, 2.0, 1.0, 1.04, 1.2};
  for (int i = 0; i < 5; ++i) {
    rows[i].r0_mm = 1 + 0.5 * i;
    rows[i].total_p99_pp_deg = tot[i];
    rows[i].mc.p99 = tot[i] - (i == 4 ? 0.5 : 0.0);
  }
  const Recommendation r = recommend(rows, 0.05);
  CHECK(r.r0_best_mm == 2.0);
  CHECK(r.total_p99_left_deg == 2.0);
  CHECK(r.total_p99_right_deg == 1.04);
  CHECK(r.band_lo_mm == 2.0);
  CHECK(r.band_hi_mm == 2.5);
  CHECK(r.r0_best_mount_only_mm == 3.0);
}

TEST_CASE("surrogate with tilts (full vector) matches the direct pipeline on tilted corners and samples",
          "[radius][surrogate][tilt]") {
  // The tolerance box of the radius study's defaults: offsets as before plus sensor tilt +-0.5 deg and a
  // magnet lean of +-0.5 deg per component. Same acceptance as the untilted order-4 test above.
  const AnalyticField field(default_magnet());
  const double r0 = GENERATE(1.0, 2.4, 3.4);
  CAPTURE(r0);
  RadiusScanOptions opt;
  opt.plane_z_mm = kPlaneZ;
  opt.box.tilt_x_deg = opt.box.tilt_y_deg = opt.box.magnet_tilt_deg = 0.5;
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4"),
                                          ProbeArray::parse("ring:8")};
  const auto [reach_xy, reach_z] = model_reach_mm(opt, r0);
  CHECK(reach_xy > opt.box.max_inplane_mm());  // the tilts widen the stencil
  const CircleFieldModel model(field, r0, kPlaneZ, 360, reach_xy, reach_z, 4, true);
  REQUIRE(model.full_vector());
  const FastPipeline fast(model, arrays, 4.0);
  std::vector<Mount> cases = opt.box.corners();
  REQUIRE(cases.size() == 512);
  cases.resize(6);
  cases.push_back(opt.box.corners()[511]);  // every component at its minus end
  for (const auto& m : monte_carlo_samples(opt.box, 5, 7)) cases.push_back(m);
  Mount only_tilt;
  only_tilt.tilt_x_deg = 0.5;
  cases.push_back(only_tilt);
  Mount only_magnet;
  only_magnet.magnet_tilt_deg = 0.5;
  only_magnet.magnet_tilt_azimuth_deg = 30;
  cases.push_back(only_magnet);
  for (const auto& m : cases) {
    REQUIRE(m.tilted());
    std::vector<Eigen::VectorXd> eps;
    fast.eps(m, eps);
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      ProbeSetup setup{arrays[a], r0, kPlaneZ, 360};
      setup.magnet_height_mm = 4.0;
      const Spectrum direct = error_spectrum(field, setup, m);
      const Spectrum sur = spectrum_of(eps[a]);
      const double tol = std::max(0.005, 0.0005 * direct.pp_deg);
      CAPTURE(arrays[a].name, corner_text(m), m.tilt_x_deg, m.tilt_y_deg, m.magnet_tilt_deg, direct.pp_deg, sur.pp_deg);
      CHECK(std::abs(sur.pp_deg - direct.pp_deg) <= tol);
      CHECK(std::abs(sur.a0_deg - direct.a0_deg) <= tol);
      for (int n = 1; n <= kHarmonics; ++n) {
        CAPTURE(n);
        CHECK(std::abs(sur.a_deg[n] - direct.a_deg[n]) <= tol);
        CHECK(std::abs(sur.b_deg[n] - direct.b_deg[n]) <= tol);
      }
    }
  }
  // A model without the full vector refuses a tilted mount.
  const CircleFieldModel bz_only(field, r0, kPlaneZ, 360, reach_xy, reach_z, 4);
  const FastPipeline fast_bz(bz_only, arrays);
  std::vector<Eigen::VectorXd> eps;
  CHECK_THROWS_AS(fast_bz.eps(only_tilt, eps), InputError);
  // A field with only Bz on a plane cannot make a full-vector model.
  CHECK_THROWS_AS(CircleFieldModel(LinearField(), r0, kPlaneZ, 360, reach_xy, reach_z, 4, true), InputError);
}
