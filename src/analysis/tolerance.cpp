#include "analysis/tolerance.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>
#include <sstream>

#include "core/errors.hpp"
#include "core/units.hpp"

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

std::vector<KeySpec> mount_box_keys(const ToleranceBox& d, bool magnet_tilt, const std::string& what) {
  const std::string h = what + " half-width of ";
  std::vector<KeySpec> k = {
      real_key("tol.sx_mm", d.sx_mm, 0, 10, "mm", h + "sx"),
      real_key("tol.sy_mm", d.sy_mm, 0, 10, "mm", h + "sy"),
      real_key("tol.dx_mm", d.dx_mm, 0, 10, "mm", h + "dx"),
      real_key("tol.dy_mm", d.dy_mm, 0, 10, "mm", h + "dy"),
      real_key("tol.dz_mm", d.dz_mm, 0, 10, "mm", h + "dz"),
      real_key("tol.tilt_x_deg", d.tilt_x_deg, 0, 10, "deg", h + "the sensor tilt about x"),
      real_key("tol.tilt_y_deg", d.tilt_y_deg, 0, 10, "deg", h + "the sensor tilt about y"),
  };
  if (magnet_tilt) k.push_back(real_key("tol.magnet_tilt_deg", d.magnet_tilt_deg, 0, 10, "deg", h + "each magnet lean component"));
  return k;
}

ToleranceBox mount_box_from_config(const Config& cfg, bool magnet_tilt) {
  ToleranceBox b{};
  b.sx_mm = cfg.real("tol.sx_mm");
  b.sy_mm = cfg.real("tol.sy_mm");
  b.dx_mm = cfg.real("tol.dx_mm");
  b.dy_mm = cfg.real("tol.dy_mm");
  b.dz_mm = cfg.real("tol.dz_mm");
  b.tilt_x_deg = cfg.real("tol.tilt_x_deg");
  b.tilt_y_deg = cfg.real("tol.tilt_y_deg");
  if (magnet_tilt) b.magnet_tilt_deg = cfg.real("tol.magnet_tilt_deg");
  b.validate("tol.");
  return b;
}

void ToleranceBox::validate(const std::string& prefix) const {
  const std::pair<const char*, double> items[] = {
      {"sx_mm", sx_mm}, {"sy_mm", sy_mm}, {"dx_mm", dx_mm}, {"dy_mm", dy_mm}, {"dz_mm", dz_mm}};
  for (const auto& [name, v] : items)
    if (!(std::isfinite(v) && v >= 0 && v <= 10))
      throw InputError(prefix + name + " = " + num(v) + " is out of range: allowed [0, 10] mm");
  const std::pair<const char*, double> tilts[] = {
      {"tilt_x_deg", tilt_x_deg}, {"tilt_y_deg", tilt_y_deg}, {"magnet_tilt_deg", magnet_tilt_deg}};
  for (const auto& [name, v] : tilts)
    if (!(std::isfinite(v) && v >= 0 && v <= 10))
      throw InputError(prefix + name + " = " + num(v) + " is out of range: allowed [0, 10] deg");
  struct Item {
    const char* name;
    double v, hi;
    const char* unit;
  };
  const Item more[] = {{"offset_cos_mT", offset_cos_mT, 100, " mT"},
                       {"offset_sin_mT", offset_sin_mT, 100, " mT"},
                       {"gain_mismatch", gain_mismatch, 0.5, ""},
                       {"phase_error_deg", phase_error_deg, 45, " deg"},
                       {"magnetization_elevation_deg", magnetization_elevation_deg, 45, " deg"}};
  for (const auto& it : more)
    if (!(std::isfinite(it.v) && it.v >= 0 && it.v <= it.hi))
      throw InputError(prefix + it.name + " = " + num(it.v) + " is out of range: allowed [0, " + num(it.hi) + "]" + it.unit);
  for (const auto& [name, v] : {std::pair<const char*, double>{"temperature_min_C", temperature_min_C},
                                std::pair<const char*, double>{"temperature_max_C", temperature_max_C}})
    if (!(std::isfinite(v) && v >= -273.15 && v <= 1000))
      throw InputError(prefix + name + " = " + num(v) + " is out of range: allowed [-273.15, 1000] C");
  if (temperature_min_C > temperature_max_C)
    throw InputError(prefix + "temperature_min_C = " + num(temperature_min_C) + " exceeds " + prefix +
                     "temperature_max_C = " + num(temperature_max_C) + ": allowed min <= max");
  if (!(std::isfinite(stray_mT) && stray_mT >= 0 && stray_mT <= 1e4))
    throw InputError(prefix + "stray_mT = " + num(stray_mT) + " is out of range: allowed [0, 10000] mT");
}

namespace {
constexpr int kAxes = 14;  // sx, sy, dx, dy, dz, tilt_x, tilt_y, lean x, lean y, oc, os, g, delta, elevation

// Mount from the first nine box coordinates (sx, sy, dx, dy, dz, tilt_x, tilt_y, lean x, lean y).
Mount mount_of(const double* v) {
  Mount m;
  m.sx_mm = v[0];
  m.sy_mm = v[1];
  m.dx_mm = v[2];
  m.dy_mm = v[3];
  m.dz_mm = v[4];
  m.tilt_x_deg = v[5];
  m.tilt_y_deg = v[6];
  m.magnet_tilt_deg = std::hypot(v[7], v[8]);
  m.magnet_tilt_azimuth_deg = m.magnet_tilt_deg > 0 ? std::atan2(v[8], v[7]) * 180.0 / M_PI : 0.0;
  return m;
}

// The whole case from the fourteen box coordinates.
ToleranceCase case_of(const double* v) {
  ToleranceCase c;
  c.mount = mount_of(v);
  c.chain.offset_cos_mT = v[9];
  c.chain.offset_sin_mT = v[10];
  c.chain.gain_mismatch = v[11];
  c.chain.phase_error_deg = v[12];
  c.elevation_deg = v[13];
  return c;
}
}  // namespace

std::vector<ToleranceCase> ToleranceBox::case_corners() const {
  const double half[kAxes] = {sx_mm,         sy_mm,         dx_mm,         dy_mm,           dz_mm,
                              tilt_x_deg,    tilt_y_deg,    magnet_tilt_deg, magnet_tilt_deg, offset_cos_mT,
                              offset_sin_mT, gain_mismatch, phase_error_deg, magnetization_elevation_deg};
  std::vector<ToleranceCase> out;
  for (int c = 0; c < (1 << kAxes); ++c) {
    double v[kAxes];
    bool duplicate = false;
    for (int b = 0; b < kAxes && !duplicate; ++b) {
      const bool minus = (c >> b) & 1;
      if (minus && half[b] == 0) duplicate = true;  // same as the '+' corner
      v[b] = minus ? -half[b] : half[b];
    }
    if (duplicate) continue;
    out.push_back(case_of(v));
  }
  return out;
}

std::vector<Mount> ToleranceBox::corners() const {
  ToleranceBox mounting = *this;
  mounting.offset_cos_mT = mounting.offset_sin_mT = mounting.gain_mismatch = mounting.phase_error_deg = 0;
  mounting.magnetization_elevation_deg = 0;
  std::vector<Mount> out;
  for (const auto& c : mounting.case_corners()) out.push_back(c.mount);
  return out;
}

ToleranceCase ToleranceBox::case_sample(std::uint64_t seed, std::uint64_t index) const {
  // One independent stream per sample: state from (seed, index), then the draws at fixed places (five
  // offsets, four tilt components, four chain components, the elevation), up to the last group the box
  // has: a box without tilts, chain and elevation draws five numbers, exactly as before those existed.
  std::uint64_t state = splitmix64(splitmix64(seed) ^ (index * 0xD1B54A32D192ED03ull + 0x632BE59BD9B4E019ull));
  auto next = [&] {
    state = splitmix64(state);
    return 2.0 * unit_uniform(state) - 1.0;  // [-1, 1)
  };
  const int draws = has_environment() ? 18 : has_elevation() ? 14 : has_chain() ? 13 : has_tilts() ? 9 : 5;
  const double half[kAxes] = {sx_mm,         sy_mm,         dx_mm,         dy_mm,           dz_mm,
                              tilt_x_deg,    tilt_y_deg,    magnet_tilt_deg, magnet_tilt_deg, offset_cos_mT,
                              offset_sin_mT, gain_mismatch, phase_error_deg, magnetization_elevation_deg};
  double v[kAxes] = {};
  for (int b = 0; b < std::min(draws, kAxes); ++b) {
    const double u = next();
    v[b] = half[b] * u;
  }
  ToleranceCase c = case_of(v);
  if (has_environment()) {
    const double u_t = next(), u_b = next(), z = next(), u_phi = next();  // each in [-1, 1)
    c.env = env_coefficients;
    c.env.temperature_C = temperature_min_C + 0.5 * (u_t + 1.0) * (temperature_max_C - temperature_min_C);
    const double b_mT = 0.5 * (u_b + 1.0) * stray_mT, rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = kPi * (u_phi + 1.0);  // z uniform in [-1, 1) and phi uniform: uniform on the sphere
    c.env.stray = StrayField{};
    c.env.stray.uniform_mT = b_mT * Eigen::Vector3d(rho * std::cos(phi), rho * std::sin(phi), z);
  }
  return c;
}

const std::vector<std::string>& ToleranceBox::groups() {
  static const std::vector<std::string> g = {"static",      "dynamic",      "air gap",
                                             "sensor tilt", "magnet tilt",  "signal chain",
                                             "magnetization elevation"};
  return g;
}

ToleranceBox ToleranceBox::only(const std::string& group) const {
  ToleranceBox b;
  b.sx_mm = b.sy_mm = b.dx_mm = b.dy_mm = b.dz_mm = 0;
  if (group == "static") b.sx_mm = sx_mm, b.sy_mm = sy_mm;
  else if (group == "dynamic") b.dx_mm = dx_mm, b.dy_mm = dy_mm;
  else if (group == "air gap") b.dz_mm = dz_mm;
  else if (group == "sensor tilt") b.tilt_x_deg = tilt_x_deg, b.tilt_y_deg = tilt_y_deg;
  else if (group == "magnet tilt") b.magnet_tilt_deg = magnet_tilt_deg;
  else if (group == "signal chain")
    b.offset_cos_mT = offset_cos_mT, b.offset_sin_mT = offset_sin_mT, b.gain_mismatch = gain_mismatch,
    b.phase_error_deg = phase_error_deg;
  else if (group == "magnetization elevation") b.magnetization_elevation_deg = magnetization_elevation_deg;
  else
    throw InputError("tolerance group '" + group +
                     "': allowed static, dynamic, air gap, sensor tilt, magnet tilt, signal chain, magnetization elevation");
  return b;
}

double ToleranceBox::max_inplane_mm() const { return std::hypot(sx_mm, sy_mm) + std::hypot(dx_mm, dy_mm); }

namespace {
template <class Case, class F>
Eigen::MatrixXd evaluate_cases_impl(const std::vector<Case>& cases, int n_out, const F& f) {
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
}  // namespace

Eigen::MatrixXd evaluate_cases(const std::vector<Mount>& cases, int n_out, const CaseFunction& f) {
  return evaluate_cases_impl(cases, n_out, f);
}

Eigen::MatrixXd evaluate_cases(const std::vector<ToleranceCase>& cases, int n_out, const ToleranceCaseFunction& f) {
  return evaluate_cases_impl(cases, n_out, f);
}

std::vector<Mount> monte_carlo_samples(const ToleranceBox& box, long n, std::uint64_t seed) {
  if (n < 1) throw InputError("Monte Carlo sample count = " + std::to_string(n) + " is out of range: allowed >= 1");
  std::vector<Mount> s(static_cast<std::size_t>(n));
  for (long i = 0; i < n; ++i) s[static_cast<std::size_t>(i)] = box.sample(seed, static_cast<std::uint64_t>(i));
  return s;
}

std::vector<ToleranceCase> monte_carlo_cases(const ToleranceBox& box, long n, std::uint64_t seed) {
  if (n < 1) throw InputError("Monte Carlo sample count = " + std::to_string(n) + " is out of range: allowed >= 1");
  std::vector<ToleranceCase> s(static_cast<std::size_t>(n));
  for (long i = 0; i < n; ++i) s[static_cast<std::size_t>(i)] = box.case_sample(seed, static_cast<std::uint64_t>(i));
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

bool clearly_larger(double candidate, double current) {
  return candidate > current + kWorstCaseTieRelative * std::abs(current);
}

WorstCase worst_case(const Eigen::MatrixXd& values, int col) {
  if (values.rows() == 0) throw InputError("worst case of no cases");
  WorstCase w;
  w.value = values(0, col);
  for (Eigen::Index i = 1; i < values.rows(); ++i)
    if (clearly_larger(values(i, col), w.value)) {
      w.value = values(i, col);
      w.row = static_cast<std::size_t>(i);
    }
  return w;
}

std::string corner_text(const Mount& m) {
  auto sgn = [](double v) { return v > 0 ? "+" : (v < 0 ? "-" : "0"); };
  std::string t = std::string("sx") + sgn(m.sx_mm) + " sy" + sgn(m.sy_mm) + " dx" + sgn(m.dx_mm) + " dy" + sgn(m.dy_mm) +
                  " dz" + sgn(m.dz_mm);
  if (m.sensor_tilted()) t += std::string(" tx") + sgn(m.tilt_x_deg) + " ty" + sgn(m.tilt_y_deg);
  if (m.magnet_tilted()) {
    const double psi = m.magnet_tilt_azimuth_deg * M_PI / 180.0;
    const double gx = m.magnet_tilt_deg * std::cos(psi), gy = m.magnet_tilt_deg * std::sin(psi);
    auto sgn_lean = [&](double v) { return std::abs(v) < 1e-12 * m.magnet_tilt_deg ? "0" : sgn(v); };
    t += std::string(" gx") + sgn_lean(gx) + " gy" + sgn_lean(gy);
  }
  return t;
}

std::string corner_text(const ToleranceCase& c) {
  auto sgn = [](double v) { return v > 0 ? "+" : (v < 0 ? "-" : "0"); };
  std::string t = corner_text(c.mount);
  if (!c.chain.ideal())
    t += std::string(" oc") + sgn(c.chain.offset_cos_mT) + " os" + sgn(c.chain.offset_sin_mT) + " g" +
         sgn(c.chain.gain_mismatch) + " ph" + sgn(c.chain.phase_error_deg);
  if (c.elevation_deg != 0) t += std::string(" el") + sgn(c.elevation_deg);
  return t;
}

}  // namespace magenc
