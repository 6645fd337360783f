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

// The surrogate's spectrum against the direct pipeline's: pp, a0 and every a_n, b_n within tol (deg).
void check_spectra_agree(const Spectrum& sur, const Spectrum& direct, double tol) {
  CHECK(std::abs(sur.pp_deg - direct.pp_deg) <= tol);
  CHECK(std::abs(sur.a0_deg - direct.a0_deg) <= tol);
  for (int n = 1; n <= kHarmonics; ++n) {
    CAPTURE(n);
    CHECK(std::abs(sur.a_deg[n] - direct.a_deg[n]) <= tol);
    CHECK(std::abs(sur.b_deg[n] - direct.b_deg[n]) <= tol);
  }
}
}  // namespace

// Stated tolerance of the surrogate (default order 4) on the default box
// (|s|, |d| <= 0.1*sqrt2, |dz| <= 0.2 mm): peak-to-peak and every Fourier
// coefficient within 0.005 deg or 0.05 % of pp (whichever is larger) of the
// direct pipeline on the same theta grid; order 3 within 0.02 deg or 0.2 %.
// The measured discrepancy is reported by the study.
TEST_CASE("surrogate matches the direct pipeline on corners and random samples", "[analysis][cross-check]") {
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
      ProbeSetup setup{arrays[a], r0, kPlaneZ, 360, {}};
      const Spectrum direct = error_spectrum(field, setup, m);
      const Spectrum sur = spectrum_of(eps[a]);
      const double tol = order == 4 ? std::max(0.005, 0.0005 * direct.pp_deg) : std::max(0.02, 0.002 * direct.pp_deg);
      CAPTURE(arrays[a].name, m.sx_mm, m.sy_mm, m.dx_mm, m.dy_mm, m.dz_mm, direct.pp_deg, sur.pp_deg);
      check_spectra_agree(sur, direct, tol);
    }
  }
}

TEST_CASE("surrogate: ideal mount has no error and the amplitude is the field's", "[analysis][physics]") {
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

TEST_CASE("surrogate rejects arrays whose probes miss the theta grid", "[analysis][bad-input]") {
  const AnalyticField field(default_magnet());
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, 0.3, 0.2, 3);
  CHECK_THROWS_WITH(FastPipeline(model, {ProbeArray::parse("ring:7")}), Catch::Contains("radius.fast_steps"));
}

TEST_CASE("worst corner on the linear field: dy and dz cannot matter", "[analysis][physics]") {
  // Bz = k x: dy moves probes along y (no field change) and dz scales nothing,
  // so the worst corner over a box with large dy/dz tolerances equals that of
  // the box without them (docs/physics.md, linear model).
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
  CHECK(pp == Approx(error_spectrum(field, ProbeSetup{two, 2.4, kPlaneZ, 360, {}}, m).pp_deg).epsilon(1e-9));
}

TEST_CASE("find_peak and recommend", "[analysis][closed-form]") {
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
          "[analysis][cross-check]") {
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
      ProbeSetup setup{arrays[a], r0, kPlaneZ, 360, {}};
      setup.magnet_height_mm = 4.0;
      const Spectrum direct = error_spectrum(field, setup, m);
      const Spectrum sur = spectrum_of(eps[a]);
      const double tol = std::max(0.005, 0.0005 * direct.pp_deg);
      CAPTURE(arrays[a].name, corner_text(m), m.tilt_x_deg, m.tilt_y_deg, m.magnet_tilt_deg, direct.pp_deg, sur.pp_deg);
      check_spectra_agree(sur, direct, tol);
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

namespace {
// A one-radius scan of the default magnet at r0 = 2.4 mm (cheap: 360 direct steps, few samples).
RadiusScanOptions one_radius_options(const std::vector<std::string>& arrays) {
  RadiusScanOptions opt;
  for (const auto& a : arrays) opt.arrays.push_back(ProbeArray::parse(a));
  opt.r0_mm = {2.4};
  opt.plane_z_mm = kPlaneZ;
  opt.direct_steps = 360;
  opt.samples = 2000;
  opt.seed = 11;
  opt.validate_radii = 1;
  opt.validate_samples = 2;
  opt.box = ToleranceBox{0, 0, 0, 0, 0};
  return opt;
}
const BudgetRow* budget_row(const RadiusScanResult& r, const std::string& array, const std::string& group) {
  for (const auto& b : r.budget)
    if (b.array == array && b.group == group) return &b;
  return nullptr;
}
}  // namespace

TEST_CASE("surrogate with a signal chain: closed forms and the direct pipeline", "[analysis][closed-form]") {
  // docs/physics.md "Beyond the five offsets": a channel offset oc gives a 1st harmonic of oc/amplitude rad, a gain
  // mismatch g a 2nd harmonic of g/2 rad, a phase error delta a0 = c2 = delta/2 (small-signal forms: their
  // relative error is of the order of the perturbation itself, ~1 % here, so 3 % is the check). The channel
  // amplitude is A for `two` (u_c = B_0) and 2A for `diff4` (u_c = B_0 - B_180).
  const AnalyticField field(default_magnet());
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4")};
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, 0.3, 0.2, 4);
  const FastPipeline fast(model, arrays);
  const double A = model.amplitude_T();
  const double rad = 180.0 / M_PI;
  auto spectra = [&](const ToleranceCase& c) {
    std::vector<Eigen::VectorXd> eps;
    fast.eps(c, eps);
    std::vector<Spectrum> s;
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      s.push_back(spectrum_of(eps[a]));
      // The surrogate against the direct pipeline with the same chain: at the nodes (ideal mount) the
      // surrogate reads the exact field, so they agree to round-off; displaced, within the surrogate's tolerance.
      ProbeSetup setup{arrays[a], 2.4, kPlaneZ, 360, {}};
      setup.chain = c.chain;
      const Spectrum direct = error_spectrum(field, setup, c.mount);
      const double tol = c.mount.sx_mm == 0 && c.mount.dx_mm == 0 ? 1e-9 : std::max(0.005, 0.0005 * direct.pp_deg);
      CAPTURE(arrays[a].name, c.chain.offset_cos_mT, c.chain.gain_mismatch, c.chain.phase_error_deg, c.mount.sx_mm);
      check_spectra_agree(s.back(), direct, tol);
    }
    return s;
  };
  ToleranceCase oc;
  oc.chain.offset_cos_mT = 0.5;
  auto s = spectra(oc);
  CHECK(s[0].c_deg[1] == Approx(0.5e-3 / A * rad).epsilon(0.03));
  CHECK(s[1].c_deg[1] == Approx(0.5e-3 / (2 * A) * rad).epsilon(0.03));
  CHECK(s[0].c_deg[1] == Approx(0.627).margin(0.002));  // docs/physics.md reference value
  ToleranceCase os;
  os.chain.offset_sin_mT = -0.5;
  s = spectra(os);
  CHECK(s[0].c_deg[1] == Approx(0.5e-3 / A * rad).epsilon(0.03));
  ToleranceCase gain;
  gain.chain.gain_mismatch = 0.01;
  s = spectra(gain);
  for (const auto& sp : s) {
    CHECK(sp.c_deg[2] == Approx(0.01 / 2 * rad).epsilon(0.03));
    CHECK(sp.c_deg[1] < 1e-9);
  }
  CHECK(s[0].c_deg[2] == Approx(0.285).margin(0.002));
  ToleranceCase phase;
  phase.chain.phase_error_deg = 1.0;
  s = spectra(phase);
  for (const auto& sp : s) {
    CHECK(sp.a0_deg == Approx(0.5).epsilon(0.03));
    CHECK(sp.c_deg[2] == Approx(0.5).epsilon(0.03));
  }
  // A chain on a displaced mount (the surrogate's local models and the chain together).
  ToleranceCase both = phase;
  both.chain.offset_cos_mT = 0.3;
  both.chain.gain_mismatch = -0.02;
  both.mount.sx_mm = 0.1;
  both.mount.dx_mm = -0.08;
  both.mount.dz_mm = 0.1;
  spectra(both);
  // An all-zero chain is exactly the chain-off path (bit for bit), untilted and tilted.
  ToleranceCase zero;
  zero.mount = both.mount;
  std::vector<Eigen::VectorXd> e_case, e_mount;
  fast.eps(zero, e_case);
  fast.eps(zero.mount, e_mount);
  for (std::size_t a = 0; a < arrays.size(); ++a) CHECK((e_case[a].array() == e_mount[a].array()).all());
  const CircleFieldModel full(field, 2.4, kPlaneZ, 360, 0.3, 0.2, 4, true);
  const FastPipeline fast_full(full, arrays);
  zero.mount.tilt_x_deg = 0.5;
  zero.mount.magnet_tilt_deg = 0.3;
  fast_full.eps(zero, e_case);
  fast_full.eps(zero.mount, e_mount);
  for (std::size_t a = 0; a < arrays.size(); ++a) CHECK((e_case[a].array() == e_mount[a].array()).all());
  // A tilted mount with a chain against the direct pipeline.
  ToleranceCase tilted_chain = zero;
  tilted_chain.chain = both.chain;
  fast_full.eps(tilted_chain, e_case);
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    ProbeSetup setup{arrays[a], 2.4, kPlaneZ, 360, {}};
    setup.chain = tilted_chain.chain;
    const Spectrum direct = error_spectrum(field, setup, tilted_chain.mount);
    CHECK(spectrum_of(e_case[a]).pp_deg == Approx(direct.pp_deg).margin(std::max(0.005, 0.0005 * direct.pp_deg)));
  }
  // No axial model: an elevation deviation is refused.
  ToleranceCase el;
  el.elevation_deg = 1;
  CHECK_THROWS_AS(fast.eps(el, e_case), InputError);
}

TEST_CASE("radius scan with the signal chain in the box: closed forms and the budget", "[analysis][closed-form]") {
  const AnalyticField field(default_magnet());
  const double rad = 180.0 / M_PI;
  // Chain-only boxes: the corners and the Monte Carlo p99 of the peak-to-peak error follow the closed forms
  // (pp of a pure 1st harmonic c1 is 2 c1, of a pure 2nd harmonic 2 c2; the phase error's eps = delta/2 (1 - cos 2theta)
  // has pp = delta). MC p99 of a uniform half-width h: 0.99 h.
  auto scan = [&](const RadiusScanOptions& opt) {
    RadiusScanResult r;
    run_radius_scan(field, "analytic", opt, r);
    REQUIRE(r.rows.size() == opt.arrays.size());
    for (const auto& v : r.validation) {
      if (v.label.rfind("worst corner", 0) != 0 && v.label.rfind("mc sample", 0) != 0) continue;  // spectra cases
      CAPTURE(v.label, v.array);
      CHECK(v.max_coef_diff_deg < 1e-6);  // no displacement: the surrogate reads the exact field
    }
    return r;
  };
  {
    RadiusScanOptions opt = one_radius_options({"two", "diff4"});
    opt.box.offset_cos_mT = 0.5;
    const RadiusScanResult r = scan(opt);
    const double A = r.rows[0].bz_amplitude_T;
    CHECK(r.rows[0].worst_pp_deg == Approx(2 * 0.5e-3 / A * rad).epsilon(0.03));
    CHECK(r.rows[1].worst_pp_deg == Approx(2 * 0.5e-3 / (2 * A) * rad).epsilon(0.03));
    CHECK(r.rows[0].mc.p99 == Approx(0.99 * 2 * 0.5e-3 / A * rad).epsilon(0.03));
    CHECK_THAT(r.rows[0].worst_corner, Catch::Matches("sx0 sy0 dx0 dy0 dz0 oc[+-] os0 g0 ph0"));
    REQUIRE(r.budget.size() == 2);
    CHECK(r.budget[0].group == "signal chain");
    CHECK(r.budget[0].share == 1.0);
  }
  {
    RadiusScanOptions opt = one_radius_options({"two"});
    opt.box.gain_mismatch = 0.01;
    const RadiusScanResult r = scan(opt);
    CHECK(r.rows[0].worst_pp_deg == Approx(0.01 * rad).epsilon(0.03));
    CHECK(r.rows[0].mc.p99 == Approx(0.99 * 0.01 * rad).epsilon(0.03));
  }
  {
    RadiusScanOptions opt = one_radius_options({"two"});
    opt.box.phase_error_deg = 1.0;
    const RadiusScanResult r = scan(opt);
    CHECK(r.rows[0].worst_pp_deg == Approx(1.0).epsilon(0.03));
  }
  // The default radius box (offsets and tilts) with and without a chain: the chain gets its own budget row,
  // the other groups' p99 alone are the same numbers (common random numbers), the whole-box p99 and hence
  // every share change.
  RadiusScanOptions off = one_radius_options({"two", "ring:8"});
  off.box = ToleranceBox{};
  off.box.tilt_x_deg = off.box.tilt_y_deg = off.box.magnet_tilt_deg = 0.5;
  off.validate_radii = 0;
  RadiusScanOptions zero = off;  // an all-zero chain: exactly chain off
  zero.box.offset_cos_mT = zero.box.offset_sin_mT = zero.box.gain_mismatch = zero.box.phase_error_deg = 0.0;
  RadiusScanOptions on = off;
  on.box.offset_cos_mT = on.box.offset_sin_mT = 0.5;
  on.box.gain_mismatch = 0.01;
  on.box.phase_error_deg = 1.0;
  RadiusScanResult r_off, r_zero, r_on;
  run_radius_scan(field, "analytic", off, r_off);
  run_radius_scan(field, "analytic", zero, r_zero);
  run_radius_scan(field, "analytic", on, r_on);
  REQUIRE(r_off.rows.size() == r_zero.rows.size());
  for (std::size_t i = 0; i < r_off.rows.size(); ++i) {
    CHECK(r_off.rows[i].worst_pp_deg == r_zero.rows[i].worst_pp_deg);
    CHECK(r_off.rows[i].worst_corner == r_zero.rows[i].worst_corner);
    CHECK(r_off.rows[i].mc.p99 == r_zero.rows[i].mc.p99);
    CHECK(r_off.rows[i].mc.mean == r_zero.rows[i].mc.mean);
  }
  REQUIRE(r_off.budget.size() == r_zero.budget.size());
  for (std::size_t i = 0; i < r_off.budget.size(); ++i) CHECK(r_off.budget[i].share == r_zero.budget[i].share);
  for (const std::string array : {"two", "ring:8"}) {
    CAPTURE(array);
    CHECK(budget_row(r_off, array, "signal chain") == nullptr);
    const BudgetRow* chain = budget_row(r_on, array, "signal chain");
    REQUIRE(chain != nullptr);
    CHECK(chain->p99_only_deg > 0.3);
    for (const std::string group : {"static", "dynamic", "air gap", "sensor tilt", "magnet tilt"}) {
      CAPTURE(group);
      const BudgetRow* a = budget_row(r_off, array, group);
      const BudgetRow* b = budget_row(r_on, array, group);
      REQUIRE(a != nullptr);
      REQUIRE(b != nullptr);
      CHECK(a->p99_only_deg == b->p99_only_deg);
      CHECK(b->p99_all_deg > a->p99_all_deg);
      CHECK(b->share < a->share);
    }
  }
  for (std::size_t i = 0; i < r_off.rows.size(); ++i) CHECK(r_on.rows[i].mc.p99 > r_off.rows[i].mc.p99);
}

TEST_CASE("radius scan with the magnetization elevation in the box", "[analysis][physics]") {
  // docs/physics.md reference: elevation 5 deg, `two`, r0 2.4 mm: c1 = 7.70 deg; `diff4` and `ring:N` see nothing
  // with an ideal mount (the axial part is symmetric about the axis).
  const AnalyticField field(default_magnet());
  Magnet md = default_magnet(), ma = default_magnet();
  ma.magnetization_elevation_deg = 90;
  const AnalyticField diametric(md), axial(ma);
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4")};
  const CircleFieldModel m_d(diametric, 2.4, kPlaneZ, 360, 0.3, 0.2, 4), m_a(axial, 2.4, kPlaneZ, 360, 0.3, 0.2, 4);
  const FastPipeline fast(m_d, arrays, 4.0, &m_a, 0.0);
  ToleranceCase c;
  c.elevation_deg = 5;
  std::vector<Eigen::VectorXd> eps;
  fast.eps(c, eps);
  CHECK(spectrum_of(eps[0]).c_deg[1] == Approx(7.70).margin(0.01));
  CHECK(spectrum_of(eps[1]).pp_deg < 1e-6);
  // Nominal 2 deg + deviation 3 deg is the 5 deg magnet; displaced mounts against the direct pipeline on it.
  Magnet m5 = default_magnet();
  m5.magnetization_elevation_deg = 5;
  const AnalyticField field5(m5);
  const FastPipeline fast2(m_d, arrays, 4.0, &m_a, 2.0);
  ToleranceCase d;
  d.elevation_deg = 3;
  d.mount.sx_mm = 0.1;
  d.mount.dy_mm = -0.1;
  d.mount.dz_mm = 0.15;
  fast2.eps(d, eps);
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    const Spectrum direct = error_spectrum(field5, ProbeSetup{arrays[a], 2.4, kPlaneZ, 360, {}}, d.mount);
    const Spectrum sur = spectrum_of(eps[a]);
    const double tol = std::max(0.005, 0.0005 * direct.pp_deg);
    CHECK(std::abs(sur.pp_deg - direct.pp_deg) <= tol);
    for (int n = 1; n <= kHarmonics; ++n) CHECK(std::abs(sur.c_deg[n] - direct.c_deg[n]) <= tol);
  }
  // The scan: an elevation-only box; validation rows compare with the exact field at each case's elevation.
  RadiusScanOptions opt = one_radius_options({"two", "diff4"});
  opt.box.magnetization_elevation_deg = 5;
  RadiusScanResult r;
  run_radius_scan(field, "analytic", opt, r);
  REQUIRE(r.rows.size() == 2);
  CHECK(r.rows[0].worst_pp_deg > 14.0);  // c1 = 7.7 deg: pp about 2 c1
  CHECK(r.rows[1].worst_pp_deg < 1e-6);
  CHECK(r.rows[0].bz_amplitude_T == Approx(m_d.amplitude_T()).epsilon(1e-12));
  bool saw_elevated = false;
  for (const auto& v : r.validation) {
    if (v.label.rfind("worst corner", 0) != 0 && v.label.rfind("mc sample", 0) != 0) continue;  // spectra cases
    CAPTURE(v.label, v.array);
    CHECK(v.max_coef_diff_deg < 1e-6);  // no displacement: cos(al) diametric + sin(al) axial at the nodes is exact
    saw_elevated = true;
  }
  CHECK(saw_elevated);
  REQUIRE(budget_row(r, "two", "magnetization elevation") != nullptr);
  // Fields with one fixed magnetization refuse the axis (one line naming the key); so does nominal + half-width > 90.
  CHECK_THROWS_WITH(check_field_serves_box(LinearField(), "linear", opt),
                    Catch::Contains("radius.tol_magnetization_elevation_deg") && Catch::Contains("'linear'"));
  RadiusScanResult r2;
  CHECK_THROWS_AS(run_radius_scan(LinearField(), "linear", opt, r2), InputError);
  CHECK(r2.rows.empty());
  opt.elevation_deg = 88;
  CHECK_THROWS_WITH(check_field_serves_box(field, "analytic", opt), Catch::Contains("allowed <= 2"));
  opt.box.magnetization_elevation_deg = 0;
  CHECK_NOTHROW(check_field_serves_box(LinearField(), "linear", opt));
}

TEST_CASE("radius fields: two sources of one kind are refused, one of each kind passes", "[analysis][bad-input]") {
  const auto analytic = std::make_shared<AnalyticField>(Magnet{});
  const auto linear = std::make_shared<LinearField>();
  const std::vector<std::pair<std::string, FieldSourcePtr>> mixed = {{"analytic", analytic}, {"linear", linear}};
  CHECK_NOTHROW(check_distinct_field_kinds(mixed));
  const std::vector<std::pair<std::string, FieldSourcePtr>> twice = {
      {"analytic", analytic}, {"linear", linear}, {"analytic", std::make_shared<AnalyticField>(Magnet{})}};
  CHECK_THROWS_WITH(check_distinct_field_kinds(twice),
                    Catch::Contains("'analytic' and 'analytic' are both analytic fields") && Catch::Contains("allowed one"));
}

TEST_CASE("tolerance box environment: off by default, draws in range, mounts unchanged", "[analysis][determinism]") {
  ToleranceBox off;
  off.tilt_x_deg = 0.5;
  REQUIRE_FALSE(off.has_environment());
  ToleranceBox on = off;
  on.temperature_min_C = -40;
  on.temperature_max_C = 150;
  on.stray_mT = 2.0;
  on.env_coefficients.offset_cos_tc_uT_per_K = 3;
  REQUIRE(on.has_environment());
  on.validate();
  double z_mean = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const ToleranceCase a = off.case_sample(7, static_cast<std::uint64_t>(i));
    const ToleranceCase b = on.case_sample(7, static_cast<std::uint64_t>(i));
    CHECK(a.env.neutral());  // off: the case's environment is the neutral default
    // Common random numbers: the environment's draws come after the others, the mounts are identical.
    CHECK(a.mount.sx_mm == b.mount.sx_mm);
    CHECK(a.mount.tilt_x_deg == b.mount.tilt_x_deg);
    CHECK(a.mount.dz_mm == b.mount.dz_mm);
    CHECK(b.env.temperature_C >= -40);
    CHECK(b.env.temperature_C < 150);
    CHECK(b.env.stray.uniform_mT.norm() <= 2.0 + 1e-12);
    CHECK(b.env.offset_cos_tc_uT_per_K == 3);
    if (b.env.stray.uniform_mT.norm() > 0) z_mean += b.env.stray.uniform_mT.normalized().z();
  }
  CHECK(std::abs(z_mean / n) < 0.05);  // uniform on the sphere: mean z 0 (sd 1/sqrt(3 n) = 0.013)
  ToleranceBox bad = on;
  bad.temperature_min_C = 200;
  CHECK_THROWS_AS(bad.validate("radius.tol_"), InputError);
  bad = on;
  bad.stray_mT = -1;
  CHECK_THROWS_WITH(bad.validate("radius.tol_"), Catch::Contains("radius.tol_stray_mT"));
}

TEST_CASE("surrogate with a temperature and a stray field: the direct pipeline", "[analysis][cross-check]") {
  // A case's environment in the surrogate against angle_error() with the same Environment: Br(T) scaling,
  // a homogeneous stray field read by each probe (tilted die included), offset and air-gap drift.
  const AnalyticField field(default_magnet());
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4")};
  ToleranceBox box;
  box.tilt_x_deg = 0.5;
  box.temperature_min_C = -40;
  box.temperature_max_C = 150;
  box.stray_mT = 1.5;
  box.env_coefficients.offset_cos_tc_uT_per_K = 2;
  box.env_coefficients.dz_tc_um_per_K = 0.5;
  // The surrogate's reach must cover the air-gap drift (0.5 um/K x 130 K = 0.065 mm on top of dz).
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, box.max_inplane_mm() + 0.05, box.dz_mm + 0.1, 4, true);
  const FastPipeline fast(model, arrays);
  for (const ToleranceCase& c : monte_carlo_cases(box, 6, 3)) {
    std::vector<Eigen::VectorXd> eps;
    fast.eps(c, eps);
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      ProbeSetup setup{arrays[a], 2.4, kPlaneZ, 360, {}};
      setup.env = c.env;
      const Spectrum direct = error_spectrum(field, setup, c.mount);
      const Spectrum sur = spectrum_of(eps[a]);
      CAPTURE(arrays[a].name, c.env.temperature_C, c.env.stray.uniform_mT.transpose(), direct.pp_deg, sur.pp_deg);
      check_spectra_agree(sur, direct, std::max(0.005, 0.0005 * direct.pp_deg));
    }
  }
}

TEST_CASE("FastPipeline::eps_field gives the numbers of eps and pp_field, and the angles as unit vectors", "[analysis][cross-check]") {
  const AnalyticField field(default_magnet());
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("ring:8")};
  ToleranceBox box;
  box.temperature_min_C = -40;
  box.temperature_max_C = 125;
  box.stray_mT = 0.5;
  const CircleFieldModel model(field, 2.4, kPlaneZ, 360, box.max_inplane_mm(), box.dz_mm + 0.1, 4);
  const FastPipeline fast(model, arrays);
  for (const ToleranceCase& c : monte_carlo_cases(box, 6, 5)) {
    std::vector<Eigen::VectorXd> e1, e2;
    double fmin[2], fmax[2], pp[2], fmin2[2], fmax2[2];
    fast.eps_field(c, e1, fmin, fmax);
    fast.eps(c, e2);
    fast.pp_field(c, pp, fmin2, fmax2);
    // The sensor's angles as unit vectors: cos and sin of theta + eps, with eps unchanged by asking.
    std::vector<Eigen::VectorXd> e3, e4;
    std::vector<UnitAngles> u3, u4;
    double f3[2], g3[2];
    fast.eps_field(c, e3, f3, g3, &u3);
    fast.eps(c, e4, &u4);
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      CHECK(e3[a] == e1[a]);
      CHECK(e4[a] == e2[a]);
      CHECK(u3[a].cos_psi == u4[a].cos_psi);
      CHECK(u3[a].sin_psi == u4[a].sin_psi);
      for (int m = 0; m < 360; ++m) {
        const double psi = (m + e1[a][m]) * M_PI / 180.0;  // theta_m = m deg
        CHECK(std::abs(u3[a].cos_psi[m] - std::cos(psi)) < 1e-13);
        CHECK(std::abs(u3[a].sin_psi[m] - std::sin(psi)) < 1e-13);
      }
    }
    for (std::size_t a = 0; a < arrays.size(); ++a) {
      CHECK(e1[a] == e2[a]);
      CHECK(std::abs(pp[a] - (e1[a].maxCoeff() - e1[a].minCoeff())) < 1e-12);
      CHECK(fmin[a] == fmin2[a]);
      CHECK(fmax[a] == fmax2[a]);
      CHECK(fmin[a] > 0);
    }
  }
}

TEST_CASE("FastPipeline::pp without atan2 equals the max - min of eps to round-off", "[analysis][cross-check]") {
  // Eccentric, tilted, tempered, stray-field and signal-chain cases, and wrapped ones (|eps| >= 90 deg:
  // the pipeline falls back to atan2), all against pp_atan2 (max - min of eps).
  const AnalyticField field(default_magnet());
  const std::vector<ProbeArray> arrays = {ProbeArray::parse("two"), ProbeArray::parse("diff4"), ProbeArray::parse("ring:8")};
  ToleranceBox box;
  box.tilt_x_deg = box.tilt_y_deg = 1.0;
  box.magnet_tilt_deg = 1.0;
  box.temperature_min_C = -40;
  box.temperature_max_C = 125;
  box.stray_mT = 2.0;
  box.offset_cos_mT = box.offset_sin_mT = 2.0;
  box.gain_mismatch = 0.05;
  box.phase_error_deg = 2.0;
  const double r0 = 2.4;
  const CircleFieldModel model(field, r0, kPlaneZ, 360, 0.5, 0.4, 4, true);
  const FastPipeline fast(model, arrays, 4.0);
  std::vector<ToleranceCase> cases = monte_carlo_cases(box, 20, 3);
  ToleranceBox flat = box;  // untilted samples (the other path)
  flat.tilt_x_deg = flat.tilt_y_deg = flat.magnet_tilt_deg = 0;
  for (const auto& c : monte_carlo_cases(flat, 20, 4)) cases.push_back(c);
  // Wrapped: a cos-channel offset larger than the amplitude turns eps through +-180 deg.
  ToleranceCase w;
  w.chain.offset_cos_mT = 1e3 * 3 * model.amplitude_T();
  cases.push_back(w);
  w.mount.tilt_x_deg = 0.5;
  cases.push_back(w);
  int wrapped = 0;
  for (const auto& c : cases) {
    double p1[3], p2[3];
    fast.pp(c, p1);
    fast.pp_atan2(c, p2);
    std::vector<Eigen::VectorXd> e;
    fast.eps(c, e);
    if (e[0].cwiseAbs().maxCoeff() >= 90) ++wrapped;
    for (int a = 0; a < 3; ++a) {
      CAPTURE(a, c.mount.tilt_x_deg, c.chain.offset_cos_mT, p1[a], p2[a]);
      CHECK(std::abs(p1[a] - p2[a]) <= 1e-12 * std::max(1.0, p2[a]));
    }
  }
  CHECK(wrapped >= 2);
  double pm[3], pa[3];
  fast.pp(Mount{0.1, -0.05, 0.05, 0.02, 0.1}, pm);
  ToleranceCase tc;
  tc.mount = Mount{0.1, -0.05, 0.05, 0.02, 0.1};
  fast.pp_atan2(tc, pa);
  for (int a = 0; a < 3; ++a) CHECK(std::abs(pm[a] - pa[a]) <= 1e-12);
}

TEST_CASE("radius.surrogate_build = symmetry needs the exact field", "[analysis][bad-input]") {
  RadiusScanOptions opt;
  opt.arrays = {ProbeArray::parse("two")};
  opt.r0_mm = {2.0};
  opt.samples = 10;
  opt.validate_radii = 0;
  opt.surrogate_build = CircleFieldModel::Construction::symmetry;
  RadiusScanResult r;
  CHECK_THROWS_WITH(run_radius_scan(LinearField(), "linear", opt, r),
                    Catch::Contains("radius.surrogate_build") && Catch::Contains("allowed axis_aligned"));
}
