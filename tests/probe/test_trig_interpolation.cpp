// Fixed-size transforms on FFTW plans (src/probe/trig_interpolation.*): the trigonometric interpolation
// against directly evaluated trigonometric polynomials, the complex DFTs against the naive sums, shared
// plans used from several threads at once.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/units.hpp"
#include "probe/trig_interpolation.hpp"

using namespace magenc;

namespace {

// p(theta) = a[0] + sum_{k=1..deg} a[k] cos(k theta) + b[k] sin(k theta), evaluated directly.
struct TrigPoly {
  std::vector<double> a, b;
  double operator()(double theta) const {
    double v = a[0];
    for (std::size_t k = 1; k < a.size(); ++k) v += a[k] * std::cos(double(k) * theta) + b[k] * std::sin(double(k) * theta);
    return v;
  }
};

TrigPoly random_poly(int degree, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  TrigPoly p;
  p.a.resize(std::size_t(degree) + 1);
  p.b.assign(std::size_t(degree) + 1, 0.0);
  for (int k = 0; k <= degree; ++k) {
    p.a[std::size_t(k)] = u(rng);
    if (k > 0) p.b[std::size_t(k)] = u(rng);
  }
  return p;
}

// max_m |interpolated - p(2 pi m / N)| / max_m |p(2 pi m / N)| for the samples p(2 pi j / M).
double interpolation_error(const TrigPoly& p, int M, int N) {
  std::vector<double> x(static_cast<std::size_t>(M)), y(static_cast<std::size_t>(N));
  for (int j = 0; j < M; ++j) x[std::size_t(j)] = p(2.0 * kPi * j / M);
  TrigInterpolation::of(M, N)(x.data(), y.data());
  double err = 0, scale = 0;
  for (int m = 0; m < N; ++m) {
    const double want = p(2.0 * kPi * m / N);
    err = std::max(err, std::abs(y[std::size_t(m)] - want));
    scale = std::max(scale, std::abs(want));
  }
  return err / scale;
}

using cd = std::complex<double>;

// sum_j x_j e^{sign 2 pi i j k / n}, the exponent reduced modulo n before the angle is formed.
std::vector<cd> naive_dft(const std::vector<cd>& x, int sign) {
  const int n = static_cast<int>(x.size());
  std::vector<cd> X(x.size());
  for (int k = 0; k < n; ++k) {
    cd s = 0;
    for (int j = 0; j < n; ++j) s += x[std::size_t(j)] * std::polar(1.0, sign * 2.0 * kPi * ((j * k) % n) / n);
    X[std::size_t(k)] = s;
  }
  return X;
}

double max_abs(const std::vector<cd>& v) {
  double m = 0;
  for (const cd& z : v) m = std::max(m, std::abs(z));
  return m;
}

double max_diff(const std::vector<cd>& a, const std::vector<cd>& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

}  // namespace

TEST_CASE("trigonometric interpolation reproduces polynomials of degree below M/2 on N nodes", "[probe][closed-form]") {
  // The Monte Carlo engine's sizes (24 -> 360, 24 -> 72), an odd M (no M/2 term) and M = N.
  const unsigned seed = GENERATE(1u, 2u, 3u, 4u, 5u);
  SECTION("M = 24, N = 360, degree 11") { CHECK(interpolation_error(random_poly(11, seed), 24, 360) <= 1e-13); }
  SECTION("M = 24, N = 72, degree 11") { CHECK(interpolation_error(random_poly(11, seed), 24, 72) <= 1e-13); }
  SECTION("M = 25, N = 75, degree 12") { CHECK(interpolation_error(random_poly(12, seed), 25, 75) <= 1e-13); }
  SECTION("M = N = 24, degree 11") { CHECK(interpolation_error(random_poly(11, seed), 24, 24) <= 1e-13); }
}

TEST_CASE("trigonometric interpolation keeps a cos(M/2 theta) term at half weight", "[probe][closed-form]") {
  // On the M nodes cos(M/2 theta) is (-1)^j: the interpolant splits it between +-M/2 and gives it back
  // exactly (a full weight on the M/2 term would double it). sin(M/2 theta) vanishes on the nodes.
  const unsigned seed = GENERATE(11u, 12u, 13u);
  TrigPoly p = random_poly(12, seed);
  p.b[12] = 0.0;
  CHECK(interpolation_error(p, 24, 360) <= 1e-13);
  TrigPoly nyquist;
  nyquist.a.assign(13, 0.0);
  nyquist.b.assign(13, 0.0);
  nyquist.a[12] = 1.0;
  CHECK(interpolation_error(nyquist, 24, 360) <= 1e-13);
}

TEST_CASE("the complex DFTs equal the naive sums, unscaled", "[probe][closed-form]") {
  const int n = GENERATE(24, 72, 7);
  std::mt19937 rng(static_cast<unsigned>(n));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<cd> x(static_cast<std::size_t>(n), 0.0), X(static_cast<std::size_t>(n)), back(static_cast<std::size_t>(n));
  for (cd& z : x) z = cd(u(rng), u(rng));
  const ComplexDft& dft = ComplexDft::of(n);
  REQUIRE(dft.n() == n);
  dft.forward(x.data(), X.data());
  const std::vector<cd> want = naive_dft(x, -1);
  CHECK(max_diff(X, want) <= 1e-13 * max_abs(want));
  dft.backward(x.data(), back.data());
  const std::vector<cd> want_back = naive_dft(x, +1);
  CHECK(max_diff(back, want_back) <= 1e-13 * max_abs(want_back));
  // backward(forward(x)) = n x; in place (in and out the same array).
  std::vector<cd> v = x;
  dft.forward(v.data(), v.data());
  CHECK(max_diff(v, X) == 0.0);
  dft.backward(v.data(), v.data());
  for (cd& z : v) z /= double(n);
  CHECK(max_diff(v, x) <= 1e-14 * max_abs(x));
}

TEST_CASE("shared transforms give identical numbers on concurrent threads", "[probe][determinism]") {
  // Threads that make the plans of new sizes at once (the planner is behind a mutex) and run them
  // (new-array execute) give bit for bit the numbers of one thread.
  const TrigPoly p = random_poly(11, 7);
  std::vector<double> x(24);
  for (int j = 0; j < 24; ++j) x[std::size_t(j)] = p(2.0 * kPi * j / 24);
  const int sizes[] = {48, 96, 120, 180};  // (sizes no other test case uses: planned here first)
  const int T = 4;
  std::vector<std::vector<double>> out(T);
  std::vector<std::thread> threads;
  for (int t = 0; t < T; ++t)
    threads.emplace_back([&, t] {
      for (int rep = 0; rep < 50; ++rep)
        for (int N : sizes) {
          std::vector<double> y(static_cast<std::size_t>(N));
          TrigInterpolation::of(24, N)(x.data(), y.data());
          if (rep == 0) out[std::size_t(t)].insert(out[std::size_t(t)].end(), y.begin(), y.end());
        }
    });
  for (auto& th : threads) th.join();
  std::vector<double> ref;
  for (int N : sizes) {
    std::vector<double> y(static_cast<std::size_t>(N));
    TrigInterpolation::of(24, N)(x.data(), y.data());
    ref.insert(ref.end(), y.begin(), y.end());
  }
  for (int t = 0; t < T; ++t) CHECK(out[std::size_t(t)] == ref);
}

TEST_CASE("transform sizes out of range are refused", "[probe]") {
  CHECK_THROWS_AS(TrigInterpolation::of(0, 360), std::invalid_argument);
  CHECK_THROWS_AS(TrigInterpolation::of(24, 12), std::invalid_argument);
  CHECK_THROWS_AS(ComplexDft::of(0), std::invalid_argument);
  CHECK(TrigInterpolation::of(24, 360).m() == 24);
  CHECK(TrigInterpolation::of(24, 360).n() == 360);
}
