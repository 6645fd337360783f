// core/vector_math: the bulk atan2 and the channel angles against libm's, the power sums and series of unit complex numbers
// against cos/sin term by term.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/vector_math.hpp"

using namespace magenc;

TEST_CASE("atan2_rad agrees with std::atan2 within 4 ULP in every quadrant", "[core][cross-check]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  // 363 points (not a multiple of the vector width: the tail is exercised), the axes and the origin.
  std::vector<double> x, y;
  for (int i = 0; i < 357; ++i) {
    x.push_back(u(rng));
    y.push_back(i % 5 == 0 ? 1e-9 * u(rng) : u(rng));
  }
  for (const auto& p : {std::pair{1.0, 0.0}, {-1.0, 0.0}, {0.0, 1.0}, {0.0, -1.0}, {0.0, 0.0}, {3.0, -1e-300}}) {
    x.push_back(p.first);
    y.push_back(p.second);
  }
  std::vector<double> out(x.size());
  atan2_rad(y.data(), x.data(), out.data(), x.size());
  const double ulp = std::numeric_limits<double>::epsilon();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double ref = std::atan2(y[i], x[i]);
    INFO("x = " << x[i] << ", y = " << y[i] << ", ref = " << ref << ", got = " << out[i]);
    CHECK(std::abs(out[i] - ref) <= 4 * ulp * std::abs(ref));
  }
  // In place (out aliasing y).
  std::vector<double> yy = y;
  atan2_rad(yy.data(), x.data(), yy.data(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i) CHECK(yy[i] == out[i]);
}

TEST_CASE("unit_power_sums and unit_series agree with the cos/sin sums term by term", "[core][cross-check]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), weight(-3.0, 3.0);
  for (const std::size_t n : {std::size_t(1), std::size_t(7), std::size_t(360), std::size_t(1001)}) {
    const int M = 16, K = 8;
    std::vector<double> t(n), c(n), s(n), w(n);
    for (std::size_t i = 0; i < n; ++i) {
      t[i] = angle(rng);
      c[i] = std::cos(t[i]);
      s[i] = std::sin(t[i]);
      w[i] = weight(rng);
    }
    std::vector<double> C(M + 1), S(M + 1), WC(K + 1), WS(K + 1);
    unit_power_sums(c.data(), s.data(), w.data(), n, M, K, C.data(), S.data(), WC.data(), WS.data());
    for (int m = 0; m <= M; ++m) {
      double rc = 0, rs = 0, rwc = 0, rws = 0;
      for (std::size_t i = 0; i < n; ++i) {
        rc += std::cos(m * t[i]);
        rs += std::sin(m * t[i]);
        rwc += w[i] * std::cos(m * t[i]);
        rws += w[i] * std::sin(m * t[i]);
      }
      INFO("n = " << n << ", m = " << m);
      // Angle addition: the round-off of z^m grows like m ulp per term, n terms.
      const double tol = 1e-15 * (m + 1) * static_cast<double>(n);
      CHECK(std::abs(C[m] - rc) <= tol);
      CHECK(std::abs(S[m] - rs) <= tol);
      if (m <= K) {
        CHECK(std::abs(WC[m] - rwc) <= 3 * tol);
        CHECK(std::abs(WS[m] - rws) <= 3 * tol);
      }
    }
    std::vector<double> h(2 * K + 1), v(n);
    for (auto& x : h) x = weight(rng);
    unit_series(c.data(), s.data(), n, h.data(), K, v.data());
    for (std::size_t i = 0; i < n; ++i) {
      double r = h[0];
      for (int m = 1; m <= K; ++m) r += h[std::size_t(2 * m - 1)] * std::cos(m * t[i]) + h[std::size_t(2 * m)] * std::sin(m * t[i]);
      CHECK(std::abs(v[i] - r) <= 1e-13);
    }
  }
}

TEST_CASE("channel_angles: the angle of the channels less theta, and their unit vector", "[core][cross-check]") {
  // Channels around a rotating field with errors up to +-60 deg (some blocks of four with x <= 0: the atan2
  // branch), one pair of zero channels, and n not a multiple of 4.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const std::size_t n = 363;
  std::vector<double> C(n), S(n), ct(n), st(n), eps(n), cp(n), sp(n), eps2(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double th = 2 * M_PI * static_cast<double>(i) / 360.0;
    const double err = (i < 180 ? 0.02 : 1.05) * u(rng);  // rad: small, then beyond +-60 deg
    const double amp = 0.05 * (1.0 + 0.3 * u(rng));
    ct[i] = std::cos(th);
    st[i] = std::sin(th);
    C[i] = amp * std::cos(th + err);
    S[i] = amp * std::sin(th + err);
  }
  C[7] = S[7] = 0.0;
  for (std::size_t i = 200; i < 204; ++i) C[i] = -C[i];  // a block turned by about 180 deg
  channel_angles(C.data(), S.data(), ct.data(), st.data(), n, eps.data(), cp.data(), sp.data());
  channel_angles(C.data(), S.data(), ct.data(), st.data(), n, eps2.data(), nullptr, nullptr);
  const double ulp = std::numeric_limits<double>::epsilon();
  for (std::size_t i = 0; i < n; ++i) {
    const double x = C[i] * ct[i] + S[i] * st[i], y = S[i] * ct[i] - C[i] * st[i];
    const double ref = std::atan2(y, x);
    INFO("i = " << i << ", ref = " << ref << ", got = " << eps[i]);
    // atan (3.5 ULP) of y / x (0.5 ULP) where x > 0, SLEEF's atan2 (3.5 ULP) elsewhere.
    CHECK(std::abs(eps[i] - ref) <= 5 * ulp * std::abs(ref));
    CHECK(eps2[i] == eps[i]);
    const double r = std::hypot(C[i], S[i]);
    CHECK(std::abs(cp[i] - (r > 0 ? C[i] / r : 1.0)) <= 4 * ulp);
    CHECK(std::abs(sp[i] - (r > 0 ? S[i] / r : 0.0)) <= 4 * ulp);
  }
}
