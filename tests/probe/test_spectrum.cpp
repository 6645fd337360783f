// Spectrum layer (src/probe/spectrum.*): wrap into (-180, 180], exact recovery of
// synthetic trigonometric signals, peak-to-peak, column names.
#include <catch2/catch.hpp>

#include <cmath>

#include "probe/spectrum.hpp"
#include "core/units.hpp"

using namespace magenc;

TEST_CASE("wrap_deg maps into -180 < a <= 180", "[probe][closed-form]") {
  CHECK(wrap_deg(0.0) == 0.0);
  CHECK(wrap_deg(180.0) == 180.0);
  CHECK(wrap_deg(-180.0) == 180.0);
  CHECK(wrap_deg(540.0) == 180.0);
  CHECK(wrap_deg(190.0) == Approx(-170.0).epsilon(1e-14));
  CHECK(wrap_deg(-190.0) == Approx(170.0).epsilon(1e-14));
  CHECK(wrap_deg(359.5) == Approx(-0.5).epsilon(1e-12));
  CHECK(wrap_deg(-720.25) == Approx(-0.25).epsilon(1e-12));
  CHECK(wrap_deg(1e6 + 0.5) == Approx(wrap_deg(std::fmod(1e6, 360.0) + 0.5)).epsilon(1e-12));
}

TEST_CASE("spectrum recovers a synthetic signal exactly", "[probe][closed-form]") {
  // eps = a0 + sum a_n cos + b_n sin for n = 1..8 with arbitrary coefficients:
  // the discrete sums are exact for M > 16, up to round-off (~1e-14 deg).
  const int M = GENERATE(17, 100, 3600);
  Spectrum want;
  want.a0_deg = 0.37;
  for (int n = 1; n <= kHarmonics; ++n) {
    want.a_deg[n] = 0.1 * n - 0.35;
    want.b_deg[n] = 0.05 * n * n - 0.8;
  }
  Eigen::VectorXd eps(M);
  for (int m = 0; m < M; ++m) {
    const double th = 2.0 * kPi * m / M;
    double e = want.a0_deg;
    for (int n = 1; n <= kHarmonics; ++n) e += want.a_deg[n] * std::cos(n * th) + want.b_deg[n] * std::sin(n * th);
    eps[m] = e;
  }
  const Spectrum got = spectrum_of(eps);
  CAPTURE(M);
  CHECK(got.a0_deg == Approx(want.a0_deg).margin(1e-12));
  CHECK(got.c_deg[0] == got.a0_deg);
  for (int n = 1; n <= kHarmonics; ++n) {
    CAPTURE(n);
    CHECK(got.a_deg[n] == Approx(want.a_deg[n]).margin(1e-12));
    CHECK(got.b_deg[n] == Approx(want.b_deg[n]).margin(1e-12));
    CHECK(got.c_deg[n] == Approx(std::hypot(want.a_deg[n], want.b_deg[n])).margin(1e-12));
  }
  CHECK(got.pp_deg == Approx(eps.maxCoeff() - eps.minCoeff()).margin(1e-15));
}

TEST_CASE("spectra of other sample counts and threads in between do not change a spectrum", "[probe][determinism]") {
  // spectrum_of keeps exp(i n theta) per sample count and thread: a spectrum must not depend on what the
  // thread computed before, nor on the thread.
  auto signal = [](int M) {
    Eigen::VectorXd eps(M);
    for (int m = 0; m < M; ++m) eps[m] = 0.3 * std::sin(3.0 * m + 0.1) + 0.01 * m / M;
    return eps;
  };
  const Eigen::VectorXd e360 = signal(360), e17 = signal(17);
  const Spectrum ref = spectrum_of(e360);
  const Spectrum ref17 = spectrum_of(e17);
  const Spectrum again = spectrum_of(e360);
  bool same = true;
#pragma omp parallel for reduction(&& : same)
  for (int i = 0; i < 64; ++i) {
    const Spectrum s = spectrum_of(i % 3 == 0 ? e17 : e360);
    const Spectrum& r = i % 3 == 0 ? ref17 : ref;
    same = same && s.a_deg == r.a_deg && s.b_deg == r.b_deg && s.a0_deg == r.a0_deg && s.pp_deg == r.pp_deg;
  }
  CHECK(same);
  CHECK(again.a_deg == ref.a_deg);
  CHECK(again.b_deg == ref.b_deg);
  // And the numbers are the DFT's (to round-off) for both counts.
  for (const Eigen::VectorXd* e : {&e360, &e17}) {
    const Spectrum s = spectrum_of(*e);
    const auto M = static_cast<double>(e->size());
    for (int n = 1; n <= kHarmonics; ++n) {
      double a = 0, b = 0;
      for (Eigen::Index m = 0; m < e->size(); ++m) {
        a += (*e)[m] * std::cos(2.0 * kPi * n * static_cast<double>(m) / M);
        b += (*e)[m] * std::sin(2.0 * kPi * n * static_cast<double>(m) / M);
      }
      CAPTURE(M, n);
      CHECK(s.a_deg[n] == Approx(2.0 / M * a).margin(1e-13));
      CHECK(s.b_deg[n] == Approx(2.0 / M * b).margin(1e-13));
    }
  }
}

TEST_CASE("wrapping a signal that crosses +-180 keeps its spectrum", "[probe][regression]") {
  // phi - theta for a true error eps = 0.4 sin(3 theta) - 0.2, computed from an
  // angle that runs over many turns: raw differences jump by multiples of 360,
  // wrap_deg must restore eps exactly.
  const int M = 720;
  Eigen::VectorXd wrapped(M);
  for (int m = 0; m < M; ++m) {
    const double th_deg = 360.0 * m / M;
    const double eps = 0.4 * std::sin(3 * deg_to_rad(th_deg)) - 0.2;
    const double phi_deg = rad_to_deg(std::atan2(std::sin(deg_to_rad(th_deg + eps)), std::cos(deg_to_rad(th_deg + eps))));
    wrapped[m] = wrap_deg(phi_deg - th_deg + 720.0 * (m % 3));  // add whole turns
  }
  const Spectrum s = spectrum_of(wrapped);
  CHECK(s.a0_deg == Approx(-0.2).margin(1e-12));
  CHECK(s.b_deg[3] == Approx(0.4).margin(1e-12));
  CHECK(s.a_deg[3] == Approx(0.0).margin(1e-12));
  CHECK(s.c_deg[1] < 1e-12);
  CHECK(s.pp_deg == Approx(0.8).margin(1e-12));
}

TEST_CASE("spectrum columns follow docs/interfaces.md", "[probe][contract]") {
  const auto& cols = spectrum_columns();
  REQUIRE(cols.size() == 1 + 3 * kHarmonics + 1);
  CHECK(cols.front() == "a0_deg");
  CHECK(cols[1] == "a1_deg");
  CHECK(cols[8] == "a8_deg");
  CHECK(cols[9] == "b1_deg");
  CHECK(cols[17] == "c1_deg");
  CHECK(cols.back() == "pp_deg");
  Spectrum s;
  s.b_deg[5] = 1.5;
  CHECK(s.column("b5_deg") == 1.5);
  CHECK_THROWS_AS(s.column("b9_deg"), std::invalid_argument);
  CHECK_THROWS_AS(s.column("d1_deg"), std::invalid_argument);
}
