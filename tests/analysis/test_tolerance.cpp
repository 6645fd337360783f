// Tolerance box, seeded Monte Carlo, percentiles and the corner worst case
// (src/analysis/tolerance.hpp).
#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>

#include "core/errors.hpp"
#include "analysis/tolerance.hpp"

using namespace magenc;

namespace {
// A cheap deterministic "error" of a mount with two outputs.
void toy(std::size_t, const Mount& m, double* out) {
  out[0] = std::abs(m.sx_mm + 2 * m.sy_mm - 3 * m.dx_mm + 0.5 * m.dy_mm + m.dz_mm);
  out[1] = m.sx_mm * m.sx_mm + std::sin(10 * m.dz_mm);
}
Eigen::MatrixXd run_mc(const ToleranceBox& b, long n, std::uint64_t seed, int threads) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  Eigen::MatrixXd v = evaluate_cases(monte_carlo_samples(b, n, seed), 2, toy);
  omp_set_num_threads(saved);
  return v;
}
}  // namespace

TEST_CASE("Monte Carlo: same seed gives identical results for any thread count", "[analysis][determinism]") {
  ToleranceBox b;
  const Eigen::MatrixXd one = run_mc(b, 5000, 42, 1);
  const Eigen::MatrixXd two = run_mc(b, 5000, 42, 2);
  const Eigen::MatrixXd four = run_mc(b, 5000, 42, 4);
  CHECK((one.array() == two.array()).all());
  CHECK((one.array() == four.array()).all());
  const SampleStats s1 = sample_stats(one.col(0)), s4 = sample_stats(four.col(0));
  CHECK(s1.p99 == s4.p99);
  CHECK(s1.mean == s4.mean);
  // A different seed gives different samples and (slightly) different statistics.
  const Eigen::MatrixXd other = run_mc(b, 5000, 43, 2);
  CHECK((one.array() != other.array()).count() > 4900);
  CHECK(sample_stats(other.col(0)).p99 != s1.p99);
  // Sample i does not depend on how many samples are drawn.
  const auto few = monte_carlo_samples(b, 10, 42), many = monte_carlo_samples(b, 1000, 42);
  for (int i = 0; i < 10; ++i) CHECK(few[i].dz_mm == many[i].dz_mm);
}

TEST_CASE("Monte Carlo samples are uniform in the box", "[analysis]") {
  ToleranceBox b{0.1, 0.2, 0.05, 0.0, 0.3};
  const auto s = monte_carlo_samples(b, 200000, 7);
  double mean[5] = {}, m2[5] = {}, lo[5] = {1e9, 1e9, 1e9, 1e9, 1e9}, hi[5] = {-1e9, -1e9, -1e9, -1e9, -1e9};
  const double half[5] = {0.1, 0.2, 0.05, 0.0, 0.3};
  for (const auto& m : s) {
    const double v[5] = {m.sx_mm, m.sy_mm, m.dx_mm, m.dy_mm, m.dz_mm};
    for (int k = 0; k < 5; ++k) {
      mean[k] += v[k] / s.size();
      m2[k] += v[k] * v[k] / s.size();
      lo[k] = std::min(lo[k], v[k]);
      hi[k] = std::max(hi[k], v[k]);
    }
  }
  for (int k = 0; k < 5; ++k) {
    CAPTURE(k);
    CHECK(lo[k] >= -half[k]);
    CHECK(hi[k] <= half[k]);
    CHECK(std::abs(mean[k]) <= 0.01 * half[k] + 1e-15);
    // Variance of U(-h, h) is h^2/3.
    CHECK(m2[k] == Approx(half[k] * half[k] / 3).epsilon(0.01).margin(1e-15));
  }
}

TEST_CASE("percentiles follow the type-7 definition", "[analysis][closed-form]") {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // 1..100, unsorted
  CHECK(percentile(v, 0) == 1.0);
  CHECK(percentile(v, 100) == 100.0);
  CHECK(percentile(v, 50) == Approx(50.5));
  CHECK(percentile(v, 99) == Approx(99.01));
  CHECK(percentile(v, 95) == Approx(95.05));
  CHECK(percentile({3.0}, 99) == 3.0);
  CHECK_THROWS_AS(percentile({}, 50), InputError);
  CHECK_THROWS_AS(percentile(v, 101), InputError);
}

TEST_CASE("worst case: round-off ties go to the first row, real differences win", "[analysis]") {
  Eigen::MatrixXd v(3, 1);
  v << 1.0, 1.0 + 1e-13, 0.5; // rows 0 and 1 tie within round-off
  WorstCase w = worst_case(v, 0);
  CHECK(w.row == 0);
  CHECK(w.value == 1.0);
  v(1, 0) = 1.0 + 1e-6; // a real difference
  w = worst_case(v, 0);
  CHECK(w.row == 1);
  CHECK(w.value == 1.0 + 1e-6);
  CHECK(clearly_larger(2.0, 1.0));
  CHECK_FALSE(clearly_larger(1.0 + 1e-12, 1.0));
  CHECK_FALSE(clearly_larger(-1.0, -1.0 + 1e-13));
}

TEST_CASE("worst case over the corners: a case with a known answer", "[analysis][closed-form]") {
  // f = |sx + 2 sy - 3 dx + 0.5 dy + dz| is largest where every term has the
  // sign of its coefficient (or all opposite): value = sum |c_i| h_i.
  ToleranceBox b{0.1, 0.2, 0.05, 0.4, 0.3};
  const auto corners = b.corners();
  REQUIRE(corners.size() == 32);
  const Eigen::MatrixXd v = evaluate_cases(corners, 2, toy);
  const WorstCase w = worst_case(v, 0);
  CHECK(w.value == Approx(0.1 + 2 * 0.2 + 3 * 0.05 + 0.5 * 0.4 + 0.3));
  const Mount& m = corners[w.row];
  // First of the two tied corners in corner order: sx at '+' -> (+, +, -, +, +).
  CHECK(m.sx_mm > 0);
  CHECK(m.sy_mm > 0);
  CHECK(m.dx_mm < 0);
  CHECK(m.dy_mm > 0);
  CHECK(m.dz_mm > 0);
  CHECK(corner_text(m) == "sx+ sy+ dx- dy+ dz+");
  // Every MC sample lies inside the box, so none beats this (linear |.|) worst corner.
  const Eigen::MatrixXd mc = evaluate_cases(monte_carlo_samples(b, 20000, 3), 2, toy);
  CHECK(mc.col(0).maxCoeff() <= w.value);
  CHECK(mc.col(0).maxCoeff() > 0.8 * w.value);
}

TEST_CASE("corners drop duplicates of zero half-widths", "[analysis]") {
  ToleranceBox b{0.1, 0.0, 0.1, 0.0, 0.0};
  const auto c = b.corners();
  CHECK(c.size() == 4);
  CHECK(b.max_inplane_mm() == Approx(0.2));
}

TEST_CASE("tolerance box rejects bad half-widths", "[analysis][bad-input]") {
  ToleranceBox b;
  b.dz_mm = -0.1;
  CHECK_THROWS_WITH(b.validate("radius.tol_"), Catch::Contains("radius.tol_dz_mm") && Catch::Contains("[0, 10] mm"));
  b.dz_mm = std::nan("");
  CHECK_THROWS_AS(b.validate(), InputError);
  CHECK_THROWS_AS(monte_carlo_samples(ToleranceBox{}, 0, 1), InputError);
}

TEST_CASE("tilts in the box: the five offsets draw as before, corners, groups", "[analysis][regression]") {
  ToleranceBox old_box;  // five offsets only (tilt half-widths 0 by default)
  ToleranceBox tilted = old_box;
  tilted.tilt_x_deg = 0.5;
  tilted.tilt_y_deg = 0.25;
  tilted.magnet_tilt_deg = 0.5;
  CHECK_FALSE(old_box.has_tilts());
  CHECK(old_box.corners().size() == 32);
  CHECK(tilted.corners().size() == 512);
  double max_tx = 0, max_g = 0;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    const Mount a = old_box.sample(5, i), b = tilted.sample(5, i);
    // Common random numbers: the offsets of sample i do not depend on the tilts being in the box.
    CHECK(a.sx_mm == b.sx_mm);
    CHECK(a.dy_mm == b.dy_mm);
    CHECK(a.dz_mm == b.dz_mm);
    CHECK_FALSE(a.tilted());
    max_tx = std::max(max_tx, std::abs(b.tilt_x_deg));
    max_g = std::max(max_g, b.magnet_tilt_deg);
    CHECK(std::abs(b.tilt_y_deg) <= 0.25);
    // Lean components within the box.
    CHECK(std::abs(b.magnet_tilt_deg * std::cos(b.magnet_tilt_azimuth_deg * M_PI / 180)) <= 0.5 + 1e-12);
    CHECK(std::abs(b.magnet_tilt_deg * std::sin(b.magnet_tilt_azimuth_deg * M_PI / 180)) <= 0.5 + 1e-12);
  }
  CHECK(max_tx > 0.49);
  CHECK(max_g > 0.6);  // corners of the lean box reach sqrt(2) * 0.5 = 0.707 deg
  // Groups: only that group's half-widths survive.
  const ToleranceBox st = tilted.only("sensor tilt");
  CHECK(st.tilt_x_deg == 0.5);
  CHECK(st.magnet_tilt_deg == 0);
  CHECK(st.max_inplane_mm() == 0);
  CHECK(st.dz_mm == 0);
  const ToleranceBox dyn = tilted.only("dynamic");
  CHECK(dyn.dx_mm == old_box.dx_mm);
  CHECK_FALSE(dyn.has_tilts());
  CHECK(dyn.sample(5, 3).dx_mm == old_box.sample(5, 3).dx_mm);
  CHECK_THROWS_AS(tilted.only("gravity"), InputError);
  tilted.magnet_tilt_deg = -1;
  CHECK_THROWS_AS(tilted.validate("radius.tol_"), InputError);
  // Corner text names the tilt signs.
  CHECK(corner_text(ToleranceBox{0.1, 0.1, 0.1, 0.1, 0.2, 0.5, 0.5, 0.5}.corners().back()) ==
        "sx- sy- dx- dy- dz- tx- ty- gx- gy-");
}

TEST_CASE("signal chain and elevation in the box: off by default and drawn after the tilts", "[analysis][contract]") {
  ToleranceBox five;  // five offsets only
  ToleranceBox tilted = five;
  tilted.tilt_x_deg = tilted.tilt_y_deg = tilted.magnet_tilt_deg = 0.5;
  CHECK_FALSE(tilted.has_chain());
  CHECK_FALSE(tilted.has_elevation());
  CHECK(tilted.case_corners().size() == 512);
  CHECK(five.case_corners().size() == 32);
  ToleranceBox chained = tilted;
  chained.offset_cos_mT = 0.5;
  chained.offset_sin_mT = 0.25;
  chained.gain_mismatch = 0.01;
  chained.phase_error_deg = 1.0;
  ToleranceBox elevated = chained;
  elevated.magnetization_elevation_deg = 2.0;
  CHECK(chained.has_chain());
  CHECK(elevated.has_elevation());
  CHECK(chained.case_corners().size() == 512 * 16);
  CHECK(elevated.case_corners().size() == 512 * 32);
  // The first corners keep the order and values of the box without the new axes.
  const auto old_c = tilted.case_corners(), new_c = elevated.case_corners();
  for (std::size_t i = 0; i < old_c.size(); ++i) {
    CHECK(corner_text(old_c[i]) + " oc+ os+ g+ ph+ el+" == corner_text(new_c[i]));
    CHECK(old_c[i].mount.magnet_tilt_azimuth_deg == new_c[i].mount.magnet_tilt_azimuth_deg);
  }
  CHECK(corner_text(new_c.back()) == "sx- sy- dx- dy- dz- tx- ty- gx- gy- oc- os- g- ph- el-");
  CHECK(chained.corners().size() == 512);  // the Mount corners ignore the chain and elevation axes
  const ToleranceBox chain_only = elevated.only("signal chain");
  const ToleranceBox elevation_only = elevated.only("magnetization elevation");
  ToleranceBox five_chain = five;  // a chain without tilts: the tilt draws still keep their places
  five_chain.offset_cos_mT = 0.5;
  five_chain.offset_sin_mT = 0.25;
  five_chain.gain_mismatch = 0.01;
  five_chain.phase_error_deg = 1.0;
  double max_oc = 0, max_g = 0, max_el = 0;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    const ToleranceCase t = tilted.case_sample(5, i), c = chained.case_sample(5, i), e = elevated.case_sample(5, i);
    // Common random numbers: the mount of sample i does not depend on the chain or elevation being in the box.
    CHECK(t.mount.sx_mm == e.mount.sx_mm);
    CHECK(t.mount.dz_mm == c.mount.dz_mm);
    CHECK(t.mount.tilt_y_deg == e.mount.tilt_y_deg);
    CHECK(t.mount.magnet_tilt_azimuth_deg == e.mount.magnet_tilt_azimuth_deg);
    CHECK(t.chain.ideal());
    CHECK(t.elevation_deg == 0);
    CHECK(c.elevation_deg == 0);
    // ... nor the chain on the elevation, nor on the other groups (budget: one group alone, same values).
    CHECK(c.chain.offset_cos_mT == e.chain.offset_cos_mT);
    CHECK(c.chain.phase_error_deg == e.chain.phase_error_deg);
    const ToleranceCase co = chain_only.case_sample(5, i), eo = elevation_only.case_sample(5, i);
    CHECK(co.chain.gain_mismatch == e.chain.gain_mismatch);
    CHECK(co.chain.offset_sin_mT == e.chain.offset_sin_mT);
    CHECK(eo.elevation_deg == e.elevation_deg);
    CHECK_FALSE(co.mount.tilted());
    CHECK(co.mount.sx_mm == 0);
    CHECK(eo.chain.ideal());
    const ToleranceCase fc = five_chain.case_sample(5, i);
    CHECK(fc.mount.sy_mm == five.sample(5, i).sy_mm);
    CHECK_FALSE(fc.mount.tilted());
    CHECK(fc.chain.offset_cos_mT == c.chain.offset_cos_mT);
    CHECK(std::abs(c.chain.offset_sin_mT) <= 0.25);
    CHECK(std::abs(c.chain.gain_mismatch) <= 0.01);
    CHECK(std::abs(c.chain.phase_error_deg) <= 1.0);
    CHECK(std::abs(e.elevation_deg) <= 2.0);
    max_oc = std::max(max_oc, std::abs(c.chain.offset_cos_mT));
    max_g = std::max(max_g, std::abs(c.chain.gain_mismatch));
    max_el = std::max(max_el, std::abs(e.elevation_deg));
  }
  CHECK(max_oc > 0.49);
  CHECK(max_g > 0.0099);
  CHECK(max_el > 1.98);
  CHECK(chain_only.offset_cos_mT == 0.5);
  CHECK_FALSE(chain_only.has_tilts());
  CHECK_FALSE(chain_only.has_elevation());
  CHECK(chain_only.dz_mm == 0);
  CHECK(elevation_only.magnetization_elevation_deg == 2.0);
  CHECK_FALSE(elevation_only.has_chain());
  CHECK_FALSE(tilted.only("signal chain").has_chain());
  CHECK(tilted.only("signal chain").empty());
  CHECK_FALSE(chain_only.empty());
  // Half-width ranges.
  ToleranceBox bad = chained;
  bad.gain_mismatch = 0.6;
  CHECK_THROWS_WITH(bad.validate("radius.tol_"), Catch::Contains("radius.tol_gain_mismatch"));
  bad = chained;
  bad.offset_cos_mT = -0.1;
  CHECK_THROWS_WITH(bad.validate("radius.tol_"), Catch::Contains("radius.tol_offset_cos_mT"));
  bad = chained;
  bad.magnetization_elevation_deg = std::nan("");
  CHECK_THROWS_WITH(bad.validate("radius.tol_"), Catch::Contains("radius.tol_magnetization_elevation_deg"));
  // evaluate_cases over whole cases.
  const auto cases = monte_carlo_cases(elevated, 100, 3);
  const Eigen::MatrixXd v = evaluate_cases(
      cases, 1, [](std::size_t, const ToleranceCase& c, double* o) { o[0] = c.chain.gain_mismatch + c.elevation_deg; });
  for (std::size_t i = 0; i < cases.size(); ++i) CHECK(v(Eigen::Index(i), 0) == cases[i].chain.gain_mismatch + cases[i].elevation_deg);
}
