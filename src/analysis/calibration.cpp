#include "analysis/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SVD>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/units.hpp"
#include "core/vector_math.hpp"
#include "probe/mounting.hpp"

namespace magenc {

namespace {

// Angle folded into [0, 360).
double fold_deg(double a) {
  double f = std::fmod(a, 360.0);
  if (f < 0) f += 360.0;
  return f >= 360.0 ? 0.0 : f;
}

// A positive integer after "name:" within [lo, hi]; InputError naming `what` otherwise.
int parse_order(const std::string& text, std::size_t colon, int lo, int hi, const std::string& what,
                const std::string& allowed) {
  const std::string digits = text.substr(colon + 1);
  bool ok = !digits.empty() && digits.size() <= 9 &&
            std::all_of(digits.begin(), digits.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
  const long v = ok ? std::stol(digits) : 0;
  if (!ok || v < lo || v > hi)
    throw InputError(what + " = '" + text + "' is not a valid calibration method: allowed " + allowed);
  return static_cast<int>(v);
}

}  // namespace

CalibrationMethod CalibrationMethod::parse(const std::string& text, const std::string& what) {
  const std::string allowed = "none, harmonics:N (N in [1, " + std::to_string(kMaxHarmonics) + "]), lut:K (K in [4, " +
                              std::to_string(kMaxLut) + "]), ogp";
  CalibrationMethod m;
  if (text == "none") return m;
  if (text == "ogp") {
    m.kind = CalibrationKind::Ogp;
    return m;
  }
  const auto colon = text.find(':');
  const std::string head = colon == std::string::npos ? text : text.substr(0, colon);
  if (colon != std::string::npos && head == "harmonics") {
    m.kind = CalibrationKind::Harmonics;
    m.order = parse_order(text, colon, 1, kMaxHarmonics, what, allowed);
    return m;
  }
  if (colon != std::string::npos && head == "lut") {
    m.kind = CalibrationKind::Lut;
    m.order = parse_order(text, colon, 4, kMaxLut, what, allowed);
    return m;
  }
  throw InputError(what + " = '" + text + "' is not a valid calibration method: allowed " + allowed);
}

std::string CalibrationMethod::name() const {
  switch (kind) {
    case CalibrationKind::None: return "none";
    case CalibrationKind::Harmonics: return "harmonics:" + std::to_string(order);
    case CalibrationKind::Lut: return "lut:" + std::to_string(order);
    case CalibrationKind::Ogp: return "ogp";
  }
  return "none";
}

double ChannelEllipse::angle_deg(double u_c, double u_s) const {
  const double d = deg_to_rad(phase_deg);
  const double x = u_c - offset_cos;
  const double y = (u_s - offset_sin) / gain_ratio;  // = A sin(psi + delta) = A (sin psi cos d + cos psi sin d)
  return rad_to_deg(std::atan2((y - x * std::sin(d)) / std::cos(d), x));
}

namespace {

// The channels must follow the fitted ellipse: corrected to a circle (offsets, gain ratio, phase), their
// radius may spread by at most kOgpMaxRadiusSpread of its mean (RMS). Channels with harmonics (a real
// sensor's few %) pass; noise, or channels of another turn count, give a conic that is no description.
constexpr double kOgpMaxRadiusSpread = 0.25;

void check_ellipse_fit(const ChannelEllipse& el, const Eigen::VectorXd& u_cos, const Eigen::VectorXd& u_sin) {
  const double d = deg_to_rad(el.phase_deg);
  Eigen::ArrayXd r(u_cos.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const double x = u_cos[i] - el.offset_cos, y = (u_sin[i] - el.offset_sin) / el.gain_ratio;
    r[i] = std::hypot(x, (y - x * std::sin(d)) / std::cos(d));
  }
  const double mean = r.mean(), spread = std::sqrt((r - mean).square().mean()) / mean;
  if (!(std::isfinite(spread) && spread <= kOgpMaxRadiusSpread))
    throw InputError("ogp calibration: the channels leave the fitted ellipse by " + fmt_sig(100 * spread, 3) +
                     " % RMS of its radius: allowed at most " + fmt_sig(100 * kOgpMaxRadiusSpread, 3) +
                     " % (channels that turn once per electrical turn on an ellipse)");
}

}  // namespace

ChannelEllipse fit_channel_ellipse(const Eigen::VectorXd& u_cos, const Eigen::VectorXd& u_sin) {
  const auto n = u_cos.size();
  if (n < 6 || u_sin.size() != n)
    throw InputError("ogp calibration needs at least 6 channel samples: got " + std::to_string(n));
  // Centred and scaled coordinates (one scale for both channels: the gain ratio and phase do not change).
  const double mc = u_cos.mean(), ms = u_sin.mean();
  const double s = std::sqrt(((u_cos.array() - mc).square() + (u_sin.array() - ms).square()).mean());
  if (!(s > 0) || !std::isfinite(s))
    throw InputError("ogp calibration: the channels do not move (all samples at one point): allowed channels that "
                     "turn once per electrical turn");
  Eigen::MatrixXd D(n, 6);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = (u_cos[i] - mc) / s, y = (u_sin[i] - ms) / s;
    D.row(i) << x * x, x * y, y * y, x, y, 1.0;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(D, Eigen::ComputeThinV);
  const Eigen::VectorXd p = svd.matrixV().col(5);
  double a = p[0], b = p[1], c = p[2];
  const double d = p[3], e = p[4];
  const double disc = 4 * a * c - b * b;
  if (!(disc > 1e-12 * (a * a + b * b + c * c)))
    throw InputError("ogp calibration: the channels do not lie on an ellipse (4ac - b^2 = " + fmt_sig(disc, 3) +
                     "): allowed channels that turn once per electrical turn");
  // Centre: gradient zero.
  const double x0 = (b * e - 2 * c * d) / disc;
  const double y0 = (b * d - 2 * a * e) / disc;
  if (a < 0) {
    a = -a;
    b = -b;
    c = -c;
  }
  ChannelEllipse el;
  el.offset_cos = mc + s * x0;
  el.offset_sin = ms + s * y0;
  el.gain_ratio = std::sqrt(a / c);
  el.phase_deg = rad_to_deg(std::asin(std::clamp(-b / (2 * std::sqrt(a * c)), -1.0, 1.0)));
  check_ellipse_fit(el, u_cos, u_sin);
  return el;
}

double Correction::e_deg(double psi_deg) const {
  switch (method.kind) {
    case CalibrationKind::Harmonics: {
      const double t = deg_to_rad(psi_deg);
      double v = harmonics_deg[0];
      for (int k = 1; k <= method.order; ++k)
        v += harmonics_deg[2 * k - 1] * std::cos(k * t) + harmonics_deg[2 * k] * std::sin(k * t);
      return v;
    }
    case CalibrationKind::Lut: {
      const auto K = lut_deg.size();
      const double x = fold_deg(psi_deg) * static_cast<double>(K) / 360.0;
      auto k = static_cast<Eigen::Index>(std::floor(x));
      if (k >= K) k = K - 1;
      const double w = x - static_cast<double>(k);
      return (1 - w) * lut_deg[k] + w * lut_deg[(k + 1) % K];
    }
    case CalibrationKind::None:
    case CalibrationKind::Ogp:
      return 0.0;
  }
  return 0.0;
}

Correction correct_pairs(const CalibrationMethod& method, const Eigen::VectorXd& phi_deg,
                         const Eigen::VectorXd& eps_deg, int turns) {
  if (phi_deg.size() != eps_deg.size())
    throw InputError("calibration pairs: " + std::to_string(phi_deg.size()) + " angles but " +
                     std::to_string(eps_deg.size()) + " errors");
  Correction c;
  c.method = method;
  c.turns = turns;
  const auto n = phi_deg.size();
  const Eigen::VectorXd psi = turns * phi_deg;
  const Eigen::VectorXd e = turns * eps_deg;
  switch (method.kind) {
    case CalibrationKind::None: return c;
    case CalibrationKind::Ogp:
      throw InputError("calibration method ogp needs the raw channels (theta_deg,u_cos,u_sin), not an error curve: "
                       "allowed harmonics:N or lut:K for error curves");
    case CalibrationKind::Harmonics:
      if (n < 2 * method.order + 1)
        throw InputError("calibration method " + method.name() + " needs at least " +
                         std::to_string(2 * method.order + 1) + " samples: got " + std::to_string(n));
      c.harmonics_deg = harmonics_ls(psi, e, method.order);
      return c;
    case CalibrationKind::Lut: {
      if (n < 2) throw InputError("calibration method " + method.name() + " needs at least 2 samples: got " +
                                  std::to_string(n));
      std::vector<std::pair<double, double>> pr(static_cast<std::size_t>(n));
      for (Eigen::Index i = 0; i < n; ++i) pr[static_cast<std::size_t>(i)] = {fold_deg(psi[i]), e[i]};
      std::sort(pr.begin(), pr.end());
      const std::size_t m = pr.size();
      const int K = method.order;
      c.lut_deg.resize(K);
      std::size_t j = 0;  // first pair with angle >= psi_k
      for (int k = 0; k < K; ++k) {
        const double x = 360.0 * k / K;
        while (j < m && pr[j].first < x) ++j;
        // Neighbours lo <= x < hi, periodic.
        const auto& hi = pr[j % m];
        const auto& lo = pr[(j + m - 1) % m];
        const double xh = j < m ? hi.first : hi.first + 360.0;
        const double xl = j > 0 ? lo.first : lo.first - 360.0;
        if (xh == x) {
          c.lut_deg[k] = hi.second;
          continue;
        }
        const double w = (x - xl) / (xh - xl);
        c.lut_deg[k] = (1 - w) * lo.second + w * hi.second;
      }
      return c;
    }
  }
  return c;
}

Correction correct_channels(const Eigen::MatrixXd& channels, int turns) {
  if (channels.cols() != 2) throw InputError("ogp calibration needs two channel columns (u_cos, u_sin)");
  Correction c;
  c.method.kind = CalibrationKind::Ogp;
  c.turns = turns;
  c.ellipse = fit_channel_ellipse(channels.col(0), channels.col(1));
  return c;
}

Correction calibrate(const CalibrationMethod& method, const AngleErrorResult& at, SensorPrinciple p) {
  const int turns = electrical_turns(p);
  if (method.kind == CalibrationKind::Ogp) return correct_channels(at.channels, turns);
  return correct_pairs(method, at.theta_deg + at.eps_deg, at.eps_deg, turns);
}

Correction calibrate(const CalibrationMethod& method, const AngleErrorResult& at, SensorPrinciple p,
                     const ReferenceReadout& readout, std::mt19937& rng) {
  if (method.kind == CalibrationKind::Ogp) return calibrate(method, at, p);
  Eigen::VectorXd ref, err;
  observe_curve(at.theta_deg, at.eps_deg, readout, rng, ref, err);
  return correct_pairs(method, ref + err, err, electrical_turns(p));
}

Eigen::VectorXd residual_of_pairs(const Correction& c, const Eigen::VectorXd& theta_deg,
                                  const Eigen::VectorXd& eps_deg) {
  if (c.method.kind == CalibrationKind::Ogp)
    throw InputError("calibration method ogp corrects the raw channels: the curve must give theta_deg,u_cos,u_sin");
  if (theta_deg.size() != eps_deg.size()) throw InputError("residual: angles and errors differ in size");
  Eigen::VectorXd r(eps_deg.size());
  const double t = c.turns;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    r[i] = wrap_deg(t * eps_deg[i] - c.e_deg(t * (theta_deg[i] + eps_deg[i]))) / t;
  return r;
}

namespace {
// calibrated_pp_deg's harmonics:N route on t eps (deg) and the unit vectors of psi = t (theta + eps) at the
// calibration state (e, c1, s1) and at the run (er, cr, sr).
double harmonics_residual_pp(int N, double t, const Eigen::VectorXd& e, const Eigen::VectorXd& c1,
                             const Eigen::VectorXd& s1, const Eigen::VectorXd& er, const Eigen::VectorXd& cr,
                             const Eigen::VectorXd& sr) {
  const Eigen::Index n = e.size();
  const int P = 2 * N + 1;
  // The fit of e on psi. Its normal equations from power sums: with C_m = sum cos(m psi), S_m = sum
  // sin(m psi) (m = 0..2N, the powers of e^{i psi} by angle addition, all pairs at once: core/vector_math.hpp),
  // sum cos j cos k = (C_{j-k} + C_{j+k}) / 2, sum sin j sin k = (C_{j-k} - C_{j+k}) / 2, sum cos j sin k =
  // (S_{j+k} - S_{j-k}) / 2; A^T e from the same powers.
  thread_local std::vector<double> Cm, Sm, WC, WS;
  Cm.resize(std::size_t(2 * N + 1));
  Sm.resize(std::size_t(2 * N + 1));
  WC.resize(std::size_t(N + 1));
  WS.resize(std::size_t(N + 1));
  unit_power_sums(c1.data(), s1.data(), e.data(), std::size_t(n), 2 * N, N, Cm.data(), Sm.data(), WC.data(), WS.data());
  Eigen::VectorXd Ate(P);
  Ate[0] = WC[0];
  for (int m = 1; m <= N; ++m) {
    Ate[2 * m - 1] = WC[std::size_t(m)];
    Ate[2 * m] = WS[std::size_t(m)];
  }
  const auto C = [&](int m) { return Cm[std::size_t(std::abs(m))]; };
  const auto S = [&](int m) { return m < 0 ? -Sm[std::size_t(-m)] : Sm[std::size_t(m)]; };
  Eigen::MatrixXd AtA(P, P);
  AtA(0, 0) = Cm[0];
  for (int k = 1; k <= N; ++k) {
    AtA(2 * k - 1, 0) = AtA(0, 2 * k - 1) = C(k);
    AtA(2 * k, 0) = AtA(0, 2 * k) = S(k);
    for (int j = 1; j <= N; ++j) {
      AtA(2 * j - 1, 2 * k - 1) = 0.5 * (C(j - k) + C(j + k));
      AtA(2 * j, 2 * k) = 0.5 * (C(j - k) - C(j + k));
      AtA(2 * j - 1, 2 * k) = 0.5 * (S(j + k) - S(j - k));  // sum cos(j psi) sin(k psi)
      AtA(2 * k, 2 * j - 1) = AtA(2 * j - 1, 2 * k);
    }
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(AtA);
  Eigen::VectorXd h;
  if (llt.info() == Eigen::Success) {
    h = llt.solve(Ate);
  } else {
    // The fit matrix itself, its columns by the same angle addition, and QR.
    Eigen::MatrixXd A(n, P);
    A.col(0).setOnes();
    Eigen::ArrayXd c = c1.array(), s = s1.array(), cn(n);
    for (int m = 1; m <= N; ++m) {
      if (m > 1) {
        cn = c * c1.array() - s * s1.array();
        s = s * c1.array() + c * s1.array();
        c.swap(cn);
      }
      A.col(2 * m - 1) = c.matrix();
      A.col(2 * m) = s.matrix();
    }
    h = A.colPivHouseholderQr().solve(e);
  }
  // The residual of the run: wrap(t eps_run - e_psi(psi_run)) / t, the series summed at every pair at once.
  thread_local std::vector<double> v;
  v.resize(std::size_t(n));
  unit_series(cr.data(), sr.data(), std::size_t(n), h.data(), N, v.data());
  thread_local Eigen::ArrayXd x;
  x = er.array() - Eigen::Map<const Eigen::ArrayXd>(v.data(), n);
  double lo = x.minCoeff(), hi = x.maxCoeff();
  if (lo > -180.0 && hi <= 180.0) return (hi - lo) / t;  // nothing to wrap (the usual case)
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double r = (x[i] > -180.0 && x[i] <= 180.0 ? x[i] : wrap_deg(x[i])) / t;
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  return hi - lo;
}

// The two calls calibrated_pp_deg stands for.
double pairs_residual_pp(const CalibrationMethod& method, const Eigen::VectorXd& theta_deg,
                         const Eigen::VectorXd& eps_cal_deg, const Eigen::VectorXd& eps_run_deg, int turns) {
  const Correction c = correct_pairs(method, theta_deg + eps_cal_deg, eps_cal_deg, turns);
  const Eigen::VectorXd r = residual_of_pairs(c, theta_deg, eps_run_deg);
  return r.maxCoeff() - r.minCoeff();
}

bool harmonics_route(const CalibrationMethod& method, Eigen::Index n, Eigen::Index n_cal, Eigen::Index n_run) {
  return method.kind == CalibrationKind::Harmonics && n >= 4 * (2 * method.order + 1) && n_cal == n && n_run == n;
}
}  // namespace

double calibrated_pp_deg(const CalibrationMethod& method, const Eigen::VectorXd& theta_deg,
                         const Eigen::VectorXd& eps_cal_deg, const Eigen::VectorXd& eps_run_deg, int turns) {
  const Eigen::Index n = theta_deg.size();
  if (!harmonics_route(method, n, eps_cal_deg.size(), eps_run_deg.size()))
    return pairs_residual_pp(method, theta_deg, eps_cal_deg, eps_run_deg, turns);
  const double t = turns;
  // psi = t (theta + eps): one sincos per pair.
  const Eigen::VectorXd e = t * eps_cal_deg, er = t * eps_run_deg;
  Eigen::VectorXd c1(n), s1(n), cr(n), sr(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double p = deg_to_rad(t * (theta_deg[i] + eps_cal_deg[i])), q = deg_to_rad(t * (theta_deg[i] + eps_run_deg[i]));
    c1[i] = std::cos(p);
    s1[i] = std::sin(p);
    cr[i] = std::cos(q);
    sr[i] = std::sin(q);
  }
  return harmonics_residual_pp(method.order, t, e, c1, s1, er, cr, sr);
}

double calibrated_pp_deg(const CalibrationMethod& method, const Eigen::VectorXd& theta_deg,
                         const Eigen::VectorXd& eps_cal_deg, const Eigen::VectorXd& cos_cal,
                         const Eigen::VectorXd& sin_cal, const Eigen::VectorXd& eps_run_deg,
                         const Eigen::VectorXd& cos_run, const Eigen::VectorXd& sin_run) {
  const Eigen::Index n = theta_deg.size();
  if (!harmonics_route(method, n, eps_cal_deg.size(), eps_run_deg.size()) || cos_cal.size() != n ||
      sin_cal.size() != n || cos_run.size() != n || sin_run.size() != n)
    return pairs_residual_pp(method, theta_deg, eps_cal_deg, eps_run_deg, 1);
  return harmonics_residual_pp(method.order, 1.0, eps_cal_deg, cos_cal, sin_cal, eps_run_deg, cos_run, sin_run);
}

Eigen::VectorXd residual_deg(const Correction& c, const AngleErrorResult& run) {
  if (c.method.kind != CalibrationKind::Ogp) return residual_of_pairs(c, run.theta_deg, run.eps_deg);
  if (run.channels.rows() != run.theta_deg.size() || run.channels.cols() != 2)
    throw InputError("calibration method ogp needs the run's raw channels");
  Eigen::VectorXd r(run.theta_deg.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const double psi = c.ellipse.angle_deg(run.channels(i, 0), run.channels(i, 1));
    const ChipOrientation& o = run.orientation;  // the chip's direction and zero apply to the corrected angle too
    r[i] = o.identity() ? wrap_deg(psi - c.turns * run.theta_deg[i]) / c.turns
                        : wrap_deg(o.direction * psi + c.turns * (o.zero_deg - run.theta_deg[i])) / c.turns;
  }
  return r;
}

AngleErrorResult corrected(const Correction& c, AngleErrorResult run) {
  if (c.method.none()) return run;
  run.eps_deg = residual_deg(c, run);
  const auto M = run.theta_deg.size();
  bool uniform = M >= 16;
  for (Eigen::Index m = 0; uniform && m < M; ++m)
    uniform = std::abs(run.theta_deg[m] - 360.0 * static_cast<double>(m) / static_cast<double>(M)) < 1e-9;
  if (uniform) run.spectrum = spectrum_of(run.eps_deg, run.spectrum.pole_pairs);
  return run;
}

CalibrationMethod calibration_method(const Config& cfg) {
  return CalibrationMethod::parse(cfg.str("calibration.method"), "calibration.method");
}

Config calibration_state(const Config& cfg) {
  Config state = cfg;
  const ConfigTables at = cfg.tables("calibration.at");
  if (at.empty()) return state;
  for (const auto& entry : at.front().settings("set")) {
    const std::string& key = entry.first;  // not a structured binding: clang 14 cannot capture one in a lambda
    const auto& value = entry.second;
    const auto refuse = [&](const std::string& why) {
      throw InputError("calibration.at key " + key + ": " + why +
                       ": allowed declared mount, sensor, stray, environment keys (not calibration.*, magnet.*)");
    };
    if (key.rfind("calibration.", 0) == 0) refuse("a calibration key cannot set the calibration state");
    if (key.rfind("magnet.", 0) == 0) refuse("the field source is the run's, a magnet key would not change it");
    if (!cfg.find(key)) refuse("not a configuration key");
    try {
      state.set_value(key, std::visit([](const auto& y) { return ConfigValue(y); }, value));
    } catch (const InputError& e) {
      throw InputError(std::string("calibration.at: ") + e.what());
    }
  }
  return state;
}

Correction correction_from_config(const FieldSource& field, const Config& cfg, const std::string& array_spec,
                                  const std::string& what) {
  const CalibrationMethod method = calibration_method(cfg);
  if (method.none()) return Correction{};
  const Config state = calibration_state(cfg);
  const ProbeSetup setup = sensor_setup_from_config(state, array_spec, what);
  const AngleErrorResult at = angle_error(field, setup, Mount::from_config(state));
  return calibrate(method, at, setup.principle);
}

namespace {
// calibration.at: a table of any configuration keys, set over the run's own values for the calibration state.
KeySpec calibration_at_key() {
  KeySpec s;
  s.key = "calibration.at";
  s.type = KeySpec::Type::Settings;
  s.default_value = "{ mount.sx_mm = 0.1, mount.dx_mm = 0.1 }";
  s.help = "the calibration state: a table of configuration keys (mount, sensor, ...) set over the run's own "
           "values, e.g. { mount.sx_mm = 0.1, mount.dx_mm = 0.1 }";
  return s;
}
}  // namespace

std::vector<KeySpec> calibration_keys() {
  return {
      // Calibration (docs/physics.md "Calibration"; analysis/calibration.hpp).
      string_key("calibration.method", "none", {},
                 "factory correction taken at calibration.at: none, harmonics:N (least-squares harmonics of the "
                 "error over the sensor's angle), lut:K (K-point periodic linear table), ogp (channel offsets, "
                 "gain ratio, phase)"),
      calibration_at_key(),
  };
}

}  // namespace magenc
