#include "analysis/tolerance.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>
#include <sstream>

#include "core/errors.hpp"

namespace magenc {

namespace {

// Uniform double in [0, 1) from the top 53 bits.
double unit_uniform(std::uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }

}  // namespace

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

void ToleranceBox::validate(const std::string& prefix) const {
  const std::pair<const char*, double> items[] = {
      {"sx_mm", sx_mm}, {"sy_mm", sy_mm}, {"dx_mm", dx_mm}, {"dy_mm", dy_mm}, {"dz_mm", dz_mm}};
  for (const auto& [name, v] : items)
    if (!(std::isfinite(v) && v >= 0 && v <= 10))
      throw InputError(prefix + name + " = " + num(v) + " is out of range: allowed [0, 10] mm");
}

std::vector<Mount> ToleranceBox::corners() const {
  const double half[5] = {sx_mm, sy_mm, dx_mm, dy_mm, dz_mm};
  std::vector<Mount> out;
  for (int c = 0; c < 32; ++c) {
    double v[5];
    bool duplicate = false;
    for (int b = 0; b < 5; ++b) {
      const bool minus = (c >> b) & 1;
      if (minus && half[b] == 0) duplicate = true;  // same as the '+' corner
      v[b] = minus ? -half[b] : half[b];
    }
    if (duplicate) continue;
    Mount m;
    m.sx_mm = v[0];
    m.sy_mm = v[1];
    m.dx_mm = v[2];
    m.dy_mm = v[3];
    m.dz_mm = v[4];
    out.push_back(m);
  }
  return out;
}

Mount ToleranceBox::sample(std::uint64_t seed, std::uint64_t index) const {
  // One independent stream per sample: state from (seed, index), then five draws.
  std::uint64_t state = splitmix64(splitmix64(seed) ^ (index * 0xD1B54A32D192ED03ull + 0x632BE59BD9B4E019ull));
  auto next = [&] {
    state = splitmix64(state);
    return 2.0 * unit_uniform(state) - 1.0;  // [-1, 1)
  };
  Mount m;
  m.sx_mm = sx_mm * next();
  m.sy_mm = sy_mm * next();
  m.dx_mm = dx_mm * next();
  m.dy_mm = dy_mm * next();
  m.dz_mm = dz_mm * next();
  return m;
}

double ToleranceBox::max_inplane_mm() const { return std::hypot(sx_mm, sy_mm) + std::hypot(dx_mm, dy_mm); }

Eigen::MatrixXd evaluate_cases(const std::vector<Mount>& cases, int n_out, const CaseFunction& f) {
  if (n_out < 1) throw InputError("evaluate_cases: n_out must be >= 1");
  // Row-major scratch so that each case writes a contiguous block.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out(
      static_cast<Eigen::Index>(cases.size()), n_out);
  std::exception_ptr err;
  std::mutex mtx;
  const long n = static_cast<long>(cases.size());
#pragma omp parallel for schedule(dynamic, 16)
  for (long i = 0; i < n; ++i) {
    try {
      f(static_cast<std::size_t>(i), cases[static_cast<std::size_t>(i)], out.row(i).data());
    } catch (...) {
      std::lock_guard<std::mutex> lock(mtx);
      if (!err) err = std::current_exception();
    }
  }
  if (err) std::rethrow_exception(err);
  return Eigen::MatrixXd(out);
}

std::vector<Mount> monte_carlo_samples(const ToleranceBox& box, long n, std::uint64_t seed) {
  if (n < 1) throw InputError("Monte Carlo sample count = " + std::to_string(n) + " is out of range: allowed >= 1");
  std::vector<Mount> s(static_cast<std::size_t>(n));
  for (long i = 0; i < n; ++i) s[static_cast<std::size_t>(i)] = box.sample(seed, static_cast<std::uint64_t>(i));
  return s;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) throw InputError("percentile of no values");
  if (!(p >= 0 && p <= 100)) throw InputError("percentile p = " + num(p) + " is out of range: allowed [0, 100]");
  std::sort(values.begin(), values.end());
  const double pos = p / 100.0 * static_cast<double>(values.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  return values[lo] + frac * (values[hi] - values[lo]);
}

SampleStats sample_stats(const Eigen::Ref<const Eigen::VectorXd>& values) {
  std::vector<double> v(values.data(), values.data() + values.size());
  SampleStats s;
  s.n = static_cast<long>(v.size());
  if (v.empty()) throw InputError("statistics of no samples");
  s.mean = values.mean();
  s.p95 = percentile(v, 95.0);
  s.p99 = percentile(v, 99.0);
  s.max = values.maxCoeff();
  return s;
}

WorstCase worst_case(const Eigen::MatrixXd& values, int col) {
  if (values.rows() == 0) throw InputError("worst case of no cases");
  WorstCase w;
  w.value = values(0, col);
  for (Eigen::Index i = 1; i < values.rows(); ++i)
    if (values(i, col) > w.value) {
      w.value = values(i, col);
      w.row = static_cast<std::size_t>(i);
    }
  return w;
}

std::string corner_text(const Mount& m) {
  auto sgn = [](double v) { return v > 0 ? "+" : (v < 0 ? "-" : "0"); };
  return std::string("sx") + sgn(m.sx_mm) + " sy" + sgn(m.sy_mm) + " dx" + sgn(m.dx_mm) + " dy" + sgn(m.dy_mm) +
         " dz" + sgn(m.dz_mm);
}

}  // namespace magenc
