#include "probe/spectrum.hpp"

#include <Eigen/QR>
#include <cmath>
#include <complex>
#include <stdexcept>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

double wrap_deg(double a_deg) {
  double r = std::fmod(a_deg + 180.0, 360.0);  // (-360, 360)
  if (r < 0) r += 360.0;                        // [0, 360)
  r -= 180.0;                                   // [-180, 180)
  return r == -180.0 ? 180.0 : r;               // (-180, 180]
}

namespace {

// c_n = hypot(a_n, b_n), c_0 = a0: the one place amplitudes are formed from a Spectrum's coefficients.
void set_amplitudes(Spectrum& sp) {
  sp.c_deg[0] = sp.a0_deg;
  for (int n = 1; n <= kHarmonics; ++n) sp.c_deg[n] = std::hypot(sp.a_deg[n], sp.b_deg[n]);
}

}  // namespace

namespace {

// exp(i n theta_m), theta_m = 2 pi m / M, n = 1..8, by repeated multiplication (n <= 8 keeps the error
// ~1e-15): entry m * kHarmonics + n - 1. Built once per M and thread (a study's spectra share M), so the
// sums below see the same numbers as when each call formed them itself.
struct Twiddles {
  Eigen::Index M = 0;
  std::vector<double> re, im;
};

const Twiddles& twiddles(Eigen::Index M) {
  thread_local Twiddles t;
  if (t.M == M) return t;
  t.re.resize(static_cast<std::size_t>(M * kHarmonics));
  t.im.resize(t.re.size());
  for (Eigen::Index m = 0; m < M; ++m) {
    const double theta_rad = 2.0 * kPi * static_cast<double>(m) / static_cast<double>(M);
    const std::complex<double> z1(std::cos(theta_rad), std::sin(theta_rad));
    std::complex<double> zn = z1;
    for (int n = 1; n <= kHarmonics; ++n) {
      const auto k = static_cast<std::size_t>(m * kHarmonics + n - 1);
      t.re[k] = zn.real();
      t.im[k] = zn.imag();
      zn *= z1;
    }
  }
  t.M = M;
  return t;
}

}  // namespace

Spectrum spectrum_of(const Eigen::VectorXd& eps_deg) {
  const Eigen::Index M = eps_deg.size();
  if (M < 1) throw std::invalid_argument("spectrum_of: no samples");
  Spectrum sp;
  std::array<double, kHarmonics + 1> sum_c{}, sum_s{};
  double sum = 0, lo = eps_deg[0], hi = eps_deg[0];
  const Twiddles& tw = twiddles(M);
  for (Eigen::Index m = 0; m < M; ++m) {
    const double e = eps_deg[m];
    const double* re = tw.re.data() + m * kHarmonics;
    const double* im = tw.im.data() + m * kHarmonics;
    for (int n = 1; n <= kHarmonics; ++n) {
      sum_c[n] += e * re[n - 1];
      sum_s[n] += e * im[n - 1];
    }
    sum += e;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  sp.a0_deg = sum / static_cast<double>(M);
  sp.a_deg[0] = sp.a0_deg;
  for (int n = 1; n <= kHarmonics; ++n) {
    sp.a_deg[n] = 2.0 / static_cast<double>(M) * sum_c[n];
    sp.b_deg[n] = 2.0 / static_cast<double>(M) * sum_s[n];
  }
  set_amplitudes(sp);
  sp.pp_deg = hi - lo;
  return sp;
}

std::array<double, 4> electrical_harmonics_deg(const Eigen::VectorXd& eps_deg, int pole_pairs) {
  const Eigen::Index M = eps_deg.size();
  std::array<double, 4> out{};
  for (int k = 1; k <= 4; ++k) {
    const long n = static_cast<long>(k) * pole_pairs;
    if (2 * n > M) continue;
    double re = 0, im = 0;
    for (Eigen::Index m = 0; m < M; ++m) {
      // The phase n m / M reduced modulo 1 before the sine: exact for large orders.
      const double a = 2.0 * kPi * static_cast<double>((n * m) % M) / static_cast<double>(M);
      re += eps_deg[m] * std::cos(a);
      im += eps_deg[m] * std::sin(a);
    }
    out[static_cast<std::size_t>(k - 1)] = 2.0 / static_cast<double>(M) * std::hypot(re, im);
  }
  return out;
}

Spectrum spectrum_of(const Eigen::VectorXd& eps_deg, int pole_pairs) {
  Spectrum s = spectrum_of(eps_deg);
  if (pole_pairs > 0) {
    s.pole_pairs = pole_pairs;
    s.ce_deg = electrical_harmonics_deg(eps_deg, pole_pairs);
  }
  return s;
}

const std::vector<std::string>& electrical_columns() {
  static const std::vector<std::string> cols{"ce1_deg", "ce2_deg", "ce3_deg", "ce4_deg"};
  return cols;
}

double Spectrum::column(const std::string& name) const {
  if (name == "pp_deg") return pp_deg;
  if (pole_pairs > 0)
    for (std::size_t k = 0; k < ce_deg.size(); ++k)
      if (name == electrical_columns()[k]) return ce_deg[k];
  if (name == "a0_deg") return a0_deg;
  if (name.size() == 6 && name.substr(2) == "_deg" && name[1] >= '1' && name[1] <= '0' + kHarmonics) {
    const int n = name[1] - '0';
    if (name[0] == 'a') return a_deg[n];
    if (name[0] == 'b') return b_deg[n];
    if (name[0] == 'c') return c_deg[n];
  }
  throw std::invalid_argument("unknown spectra column '" + name + "'");
}

const std::vector<std::string>& spectrum_columns() {
  static const std::vector<std::string> cols = [] {
    std::vector<std::string> c{"a0_deg"};
    for (char k : {'a', 'b', 'c'})
      for (int n = 1; n <= kHarmonics; ++n) c.push_back(std::string(1, k) + std::to_string(n) + "_deg");
    c.push_back("pp_deg");
    return c;
  }();
  return cols;
}

Eigen::VectorXd harmonics_ls(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& values, int max_n) {
  const auto N = theta_deg.size();
  const int P = 1 + 2 * max_n;
  if (N < P || values.size() != N)
    throw InputError("harmonic fit needs at least " + std::to_string(P) + " samples: got " + std::to_string(N));
  Eigen::MatrixXd A(N, P);
  for (Eigen::Index i = 0; i < N; ++i) {
    const double t = deg_to_rad(theta_deg[i]);
    A(i, 0) = 1.0;
    for (int n = 1; n <= max_n; ++n) {
      A(i, 2 * n - 1) = std::cos(n * t);
      A(i, 2 * n) = std::sin(n * t);
    }
  }
  return A.colPivHouseholderQr().solve(values);
}

double harmonic_amplitude(const Eigen::VectorXd& h, int n) { return std::hypot(h[2 * n - 1], h[2 * n]); }

Spectrum spectrum_from_ls(const Eigen::VectorXd& h) {
  Spectrum s;
  s.a0_deg = h[0];
  for (int n = 1; n <= kHarmonics && 2 * n < h.size(); ++n) {
    s.a_deg[n] = h[2 * n - 1];
    s.b_deg[n] = h[2 * n];
  }
  set_amplitudes(s);
  return s;
}

}  // namespace magenc
