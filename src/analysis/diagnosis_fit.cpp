#include "analysis/diagnosis_fit.hpp"

#include <ceres/ceres.h>
#include <omp.h>

#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <iterator>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/units.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

// ---------------------------------------------------------------------------------------------------------
// 1. The parameter table. One line per parameter: name, key, json name, unit, bounds, typical scale, setter,
// getter, words. Bounds are generous fit limits (the model itself rejects degenerate mounts).
// ---------------------------------------------------------------------------------------------------------
namespace {

#define MAGENC_MOUNT_PARAM(NAME, FIELD, UNIT, LO, HI, SCALE, WHAT)                                             \
  FitParameter {                                                                                                \
    NAME, "mount." #FIELD, #FIELD, UNIT, LO, HI, SCALE, [](ModelState& s, double v) { s.mount.FIELD = v; },     \
        [](const ModelState& s) { return s.mount.FIELD; }, WHAT                                                  \
  }

#define MAGENC_CHAIN_PARAM(NAME, FIELD, UNIT, LO, HI, SCALE, WHAT)                                             \
  FitParameter {                                                                                                \
    NAME, "sensor." #FIELD, #FIELD, UNIT, LO, HI, SCALE, [](ModelState& s, double v) { s.setup.chain.FIELD = v; }, \
        [](const ModelState& s) { return s.setup.chain.FIELD; }, WHAT                                            \
  }

// Magnet tilt as components: x = g cos psi, y = g sin psi (deg).
double magnet_tilt_component(const Mount& m, bool x) {
  const double psi = deg_to_rad(m.magnet_tilt_azimuth_deg);
  return m.magnet_tilt_deg * (x ? std::cos(psi) : std::sin(psi));
}
void set_magnet_tilt(Mount& m, double x_deg, double y_deg) {
  m.magnet_tilt_deg = std::hypot(x_deg, y_deg);
  m.magnet_tilt_azimuth_deg = m.magnet_tilt_deg > 0 ? rad_to_deg(std::atan2(y_deg, x_deg)) : 0.0;
}

std::vector<FitParameter> make_table() {
  return {
      MAGENC_MOUNT_PARAM("sx", sx_mm, "mm", -1.0, 1.0, 0.05, "static eccentricity x (sensor off the axis)"),
      MAGENC_MOUNT_PARAM("sy", sy_mm, "mm", -1.0, 1.0, 0.05, "static eccentricity y"),
      MAGENC_MOUNT_PARAM("dx", dx_mm, "mm", -1.0, 1.0, 0.05, "dynamic eccentricity x (magnet off the axis)"),
      MAGENC_MOUNT_PARAM("dy", dy_mm, "mm", -1.0, 1.0, 0.05, "dynamic eccentricity y"),
      MAGENC_MOUNT_PARAM("dz", dz_mm, "mm", -0.5, 0.5, 0.1, "air-gap offset (+ = farther)"),
      MAGENC_MOUNT_PARAM("tilt_x", tilt_x_deg, "deg", -10.0, 10.0, 1.0, "sensor tilt about x"),
      MAGENC_MOUNT_PARAM("tilt_y", tilt_y_deg, "deg", -10.0, 10.0, 1.0, "sensor tilt about y"),
      // Magnet tilt g towards azimuth psi, fitted as Cartesian components (g cos psi, g sin psi): the polar
      // form has no defined azimuth at g = 0. --free magnet_tilt means both components.
      FitParameter{"magnet_tilt_x", "mount.magnet_tilt_deg*cos(azimuth)", "magnet_tilt_x_deg", "deg", -10.0, 10.0, 1.0,
                   [](ModelState& s, double v) { set_magnet_tilt(s.mount, v, magnet_tilt_component(s.mount, false)); },
                   [](const ModelState& s) { return magnet_tilt_component(s.mount, true); },
                   "magnet tilt component leaning towards +x (g cos psi)"},
      FitParameter{"magnet_tilt_y", "mount.magnet_tilt_deg*sin(azimuth)", "magnet_tilt_y_deg", "deg", -10.0, 10.0, 1.0,
                   [](ModelState& s, double v) { set_magnet_tilt(s.mount, magnet_tilt_component(s.mount, true), v); },
                   [](const ModelState& s) { return magnet_tilt_component(s.mount, false); },
                   "magnet tilt component leaning towards +y (g sin psi)"},
      // Channel offsets: in mT on bz/inplane, relative on xmr/amr (probe/signal_chain.hpp). Each pair acts only
      // on the principles it applies to (elsewhere its setter does nothing, so it moves no curve and is left
      // out of the default free set, or reported not identifiable when asked for).
      FitParameter{"offset_cos", "sensor.offset_cos_mT", "offset_cos_mT", "mT", -5.0, 5.0, 0.5,
                   [](ModelState& s, double v) { if (!relative_offsets(s.setup.principle)) s.setup.chain.offset_cos_mT = v; },
                   [](const ModelState& s) { return s.setup.chain.offset_cos_mT; }, "offset of the cos channel"},
      FitParameter{"offset_sin", "sensor.offset_sin_mT", "offset_sin_mT", "mT", -5.0, 5.0, 0.5,
                   [](ModelState& s, double v) { if (!relative_offsets(s.setup.principle)) s.setup.chain.offset_sin_mT = v; },
                   [](const ModelState& s) { return s.setup.chain.offset_sin_mT; }, "offset of the sin channel"},
      MAGENC_CHAIN_PARAM("gain", gain_mismatch, "", -0.2, 0.2, 0.01, "gain mismatch of the sin channel"),
      MAGENC_CHAIN_PARAM("phase", phase_error_deg, "deg", -10.0, 10.0, 0.5, "phase error of the sin channel"),
      FitParameter{"offset_cos_rel", "sensor.offset_cos_rel", "offset_cos_rel", "", -0.5, 0.5, 0.005,
                   [](ModelState& s, double v) { if (relative_offsets(s.setup.principle)) s.setup.chain.offset_cos_rel = v; },
                   [](const ModelState& s) { return s.setup.chain.offset_cos_rel; },
                   "relative offset of the cos channel (xmr, amr)"},
      FitParameter{"offset_sin_rel", "sensor.offset_sin_rel", "offset_sin_rel", "", -0.5, 0.5, 0.005,
                   [](ModelState& s, double v) { if (relative_offsets(s.setup.principle)) s.setup.chain.offset_sin_rel = v; },
                   [](const ModelState& s) { return s.setup.chain.offset_sin_rel; },
                   "relative offset of the sin channel (xmr, amr)"},
      // Not fitted: magnet.magnetization_elevation_deg. It is a property of the field source (the exact field
      // is built with it, an FE solution has it baked in), and its effect is a common offset on every probe:
      // for `two` the same 1st harmonic as offset_cos = offset_sin, for diff4 and ring:N nothing.
  };
}

#undef MAGENC_MOUNT_PARAM
#undef MAGENC_CHAIN_PARAM

constexpr double kZeroScaleDeg = 0.1;  // typical zero offset between the encoders (scaling only)

std::string fmt_sci(double v) {
  std::ostringstream os;
  os.precision(2);
  os << std::scientific << v;
  return os.str();
}

std::string join_words(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i == 0 ? "" : i + 1 == v.size() ? " and " : ", ") + v[i];
  return s;
}

std::string ordinal(int n) {
  const char* suf = (n % 10 == 1 && n != 11) ? "st" : (n % 10 == 2 && n != 12) ? "nd" : (n % 10 == 3 && n != 13) ? "rd" : "th";
  return std::to_string(n) + suf;
}

// Amplitudes |a0|, c1..c8 from harmonics_ls coefficients.
std::vector<double> amplitudes(const Eigen::VectorXd& h) {
  std::vector<double> a{std::abs(h[0])};
  for (int n = 1; 2 * n < h.size(); ++n) a.push_back(harmonic_amplitude(h, n));
  return a;
}

std::set<int> loaded_harmonics(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& v) {
  const auto a = amplitudes(harmonics_ls(theta_deg, v));
  const double mx = *std::max_element(a.begin(), a.end());
  std::set<int> s;
  if (mx <= 0) return s;
  for (std::size_t n = 0; n < a.size(); ++n)
    if (a[n] >= 0.1 * mx) s.insert(static_cast<int>(n));
  return s;
}

std::string harmonics_words(const std::set<int>& h) {
  std::vector<std::string> w;
  for (int n : h) w.push_back(n == 0 ? std::string("DC") : "the " + ordinal(n) + " harmonic");
  return w.empty() ? std::string("nothing") : join_words(w);
}

}  // namespace

const std::vector<FitParameter>& fit_parameters() {
  static const std::vector<FitParameter> table = make_table();
  return table;
}

int fit_parameter_index(const std::string& name) {
  const auto& t = fit_parameters();
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i].name == name || t[i].json_name == name || t[i].key == name) return static_cast<int>(i);
  return -1;
}

const FitParameter& fit_parameter(const std::string& name) {
  const int i = fit_parameter_index(name);
  if (i < 0) {
    std::vector<std::string> names;
    for (const auto& p : fit_parameters()) names.push_back(p.name);
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ",") + n;
    throw InputError("fit parameter '" + name + "' is unknown: allowed " + list);
  }
  return fit_parameters()[i];
}

std::pair<int, CurveOverride> parse_curve_set(const std::string& text, int curves) {
  const std::string form = "allowed N:key=value or N:key+=value, N = 1.." + std::to_string(curves) +
                           ", key a fit parameter (e.g. 2:mount.dz_mm+=0.5)";
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon == 0) throw InputError("--curve-set '" + text + "': " + form);
  int n = 0;
  try {
    std::size_t used = 0;
    n = std::stoi(text.substr(0, colon), &used);
    if (used != colon) throw std::invalid_argument("n");
  } catch (const std::exception&) {
    throw InputError("--curve-set '" + text + "': curve number is not an integer: " + form);
  }
  if (n < 1 || n > curves) throw InputError("--curve-set '" + text + "': curve " + std::to_string(n) + " does not exist: " + form);
  const std::string rest = text.substr(colon + 1);
  const auto eq = rest.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("--curve-set '" + text + "': " + form);
  CurveOverride o;
  o.add = rest[eq - 1] == '+';
  const std::string key = rest.substr(0, o.add ? eq - 1 : eq);
  o.param = fit_parameter_index(key);
  if (o.param < 0) throw InputError("--curve-set '" + text + "': '" + key + "' is not a fit parameter: " + form);
  const std::string val = rest.substr(eq + 1);
  char* end = nullptr;
  o.value = std::strtod(val.c_str(), &end);
  if (val.empty() || *end != '\0' || !std::isfinite(o.value))
    throw InputError("--curve-set '" + text + "': value '" + val + "' is not a finite number: " + form);
  return {n - 1, o};
}

std::vector<std::string> expand_free_names(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const auto& n : names) {
    if (n == "magnet_tilt" || n == "magnet_tilt_deg" || n == "mount.magnet_tilt_deg") {
      out.push_back("magnet_tilt_x");
      out.push_back("magnet_tilt_y");
    } else {
      out.push_back(n);
    }
  }
  return out;
}

std::string harmonic_loading(const Eigen::VectorXd& theta_deg, const Eigen::VectorXd& v) {
  return harmonics_words(loaded_harmonics(theta_deg, v));
}

Eigen::VectorXd model_curve_deg(const FieldSource& field, const CurveInput& c, const std::vector<double>& values) {
  const auto& t = fit_parameters();
  ModelState s = c.base;
  for (std::size_t i = 0; i < t.size(); ++i) t[i].set(s, values[i]);
  for (const auto& o : c.overrides) t[o.param].set(s, o.add ? values[o.param] + o.value : o.value);
  return angle_error_at(field, s.setup, s.mount, c.curve.theta_deg).eps_deg;
}

// ---------------------------------------------------------------------------------------------------------
// 2. The least-squares problem in scaled variables u: shared free parameters, then one zero offset per curve.
// ---------------------------------------------------------------------------------------------------------
namespace {

// A field that replays the batch readings it recorded: the Jacobian's base evaluation records its batch
// calls, and every evaluation whose probe positions are the same bits (a parameter of the signal chain moves
// no probe) gets those readings back instead of the field's. Bit for bit what a new
// evaluation would give: a batch computes each point on its own. Recording is single-threaded (outside the
// parallel region); replaying only reads.
class BatchReplay final : public FieldSource {
 public:
  explicit BatchReplay(const FieldSource& f) : f_(f) {}
  void set_recording(bool on) { recording_ = on; }
  std::string name() const override { return f_.name(); }
  Vec3 B_T(const Vec3& p_mm) const override { return f_.B_T(p_mm); }
  bool gives_full_vector() const override { return f_.gives_full_vector(); }
  double Bz_T(const Vec3& p_mm) const override { return f_.Bz_T(p_mm); }
  Eigen::Matrix3Xd B_T(const Eigen::Matrix3Xd& p_mm) const override { return replay(full_, p_mm, [&] { return f_.B_T(p_mm); }); }
  Eigen::VectorXd Bz_T(const Eigen::Matrix3Xd& p_mm) const override { return replay(bz_, p_mm, [&] { return f_.Bz_T(p_mm); }); }
  const Magnet* exact_magnet() const override { return f_.exact_magnet(); }
  std::optional<AxisymmetricParts> axisymmetric_parts() const override { return f_.axisymmetric_parts(); }

 private:
  template <class V, class F>
  V replay(std::vector<std::pair<Eigen::Matrix3Xd, V>>& memo, const Eigen::Matrix3Xd& p, F&& eval) const {
    const auto bytes = static_cast<std::size_t>(p.size()) * sizeof(double);
    for (const auto& [key, value] : memo)
      if (key.cols() == p.cols() && std::memcmp(key.data(), p.data(), bytes) == 0) return value;
    V v = eval();
    if (recording_) memo.emplace_back(p, v);
    return v;
  }
  const FieldSource& f_;
  bool recording_ = false;
  mutable std::vector<std::pair<Eigen::Matrix3Xd, Eigen::Matrix3Xd>> full_;
  mutable std::vector<std::pair<Eigen::Matrix3Xd, Eigen::VectorXd>> bz_;
};

struct Problem {
  const FieldSource& field;
  const std::vector<CurveInput>& curves;
  std::vector<int> free_idx;     // table indices of the shared free parameters
  bool free_zero = true;
  std::vector<double> base;      // table values at the configured point (curve 1's base)
  std::vector<double> scale;     // per variable
  double fd_step = 1e-4;         // central-difference step in scaled units
  int n_shared() const { return static_cast<int>(free_idx.size()); }
  int n_vars() const { return n_shared() + (free_zero ? static_cast<int>(curves.size()) : 0); }

  std::vector<double> values(const double* u) const {
    std::vector<double> v = base;
    for (int j = 0; j < n_shared(); ++j) v[free_idx[j]] = u[j] * scale[j];
    return v;
  }
  double zero(const double* u, int c) const { return free_zero ? u[n_shared() + c] * kZeroScaleDeg : 0.0; }
  // Residuals of curve c (deg); throws InputError/ComputeError where the model is undefined.
  Eigen::VectorXd residual(int c, const double* u) const { return residual_on(field, c, u); }
  Eigen::VectorXd residual_on(const FieldSource& f, int c, const double* u) const {
    const Eigen::VectorXd m = model_curve_deg(f, curves[c], values(u));
    const Eigen::VectorXd& y = curves[c].curve.error_deg;
    Eigen::VectorXd r(m.size());
    const double z = zero(u, c);
    for (Eigen::Index i = 0; i < m.size(); ++i) r[i] = wrap_deg(m[i] + z - y[i]);
    return r;
  }
  // Residual and scaled Jacobian (N x n_vars) of curve c by central differences (zero offsets exact). The
  // base evaluation runs first (its field batch on all threads) and records its field readings; the
  // 2*n_shared perturbed evaluations then run in parallel (one OpenMP region: the field's own batch
  // parallelism is nested inside and runs serially there), those that move no probe replaying the base's
  // readings (BatchReplay). So a Jacobian costs two barriers, not 2p + 1 (which matters on a loaded
  // machine, where every barrier waits for a time slice), and a signal-chain parameter costs no field.
  void jacobian(int c, const double* u, Eigen::VectorXd* r, Eigen::MatrixXd* J) const {
    const int ns = n_shared(), evals = 2 * ns + 1;
    std::vector<Eigen::VectorXd> out(evals);
    std::vector<std::string> err(evals);
    BatchReplay replay(field);
    const auto evaluate = [&](int e) {
      std::vector<double> w(u, u + n_vars());
      if (e > 0) w[(e - 1) / 2] += (e % 2 == 1 ? fd_step : -fd_step);
      try {
        out[e] = residual_on(replay, c, w.data());
      } catch (const std::exception& ex) {
        err[e] = ex.what();
      }
    };
    replay.set_recording(true);
    evaluate(0);
    if (!err[0].empty()) throw InputError(err[0]);
    replay.set_recording(false);
#pragma omp parallel for schedule(dynamic, 1)
    for (int e = 1; e < evals; ++e) evaluate(e);
    for (int e = 1; e < evals; ++e)
      if (!err[e].empty()) throw InputError(err[e]);
    if (r) *r = out[0];
    const auto N = curves[c].curve.theta_deg.size();
    J->setZero(N, n_vars());
    for (int j = 0; j < ns; ++j)
      for (Eigen::Index i = 0; i < N; ++i) (*J)(i, j) = wrap_deg(out[2 * j + 1][i] - out[2 * j + 2][i]) / (2 * fd_step);
    if (free_zero) J->col(ns + c).setConstant(kZeroScaleDeg);
  }
};

// Runs the enclosed model evaluations on one thread (restores the previous count): a single residual
// evaluation is too small to pay for an OpenMP barrier on a loaded machine.
class SerialScope {
 public:
  SerialScope() : prev_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~SerialScope() { omp_set_num_threads(prev_); }
  SerialScope(const SerialScope&) = delete;
  SerialScope& operator=(const SerialScope&) = delete;

 private:
  int prev_;
};

class CurveCost final : public ceres::CostFunction {
 public:
  CurveCost(const Problem& p, int c) : p_(p), c_(c) {
    set_num_residuals(static_cast<int>(p.curves[c].curve.theta_deg.size()));
    mutable_parameter_block_sizes()->push_back(p.n_vars());
  }
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    try {
      Eigen::VectorXd r;
      if (jacobians && jacobians[0]) {
        Eigen::MatrixXd J;
        p_.jacobian(c_, params[0], &r, &J);
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            jacobians[0], J.rows(), J.cols()) = J;
      } else {
        SerialScope serial;
        r = p_.residual(c_, params[0]);
      }
      Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r;
      return r.allFinite();
    } catch (const InputError&) {
      return false;  // the step left the model's domain (e.g. a probe path into the magnet): Ceres shrinks it
    } catch (const ComputeError&) {
      return false;
    }
  }

 private:
  const Problem& p_;
  int c_;
};

Eigen::MatrixXd stacked_jacobian(const Problem& p, const double* u, Eigen::VectorXd* r_all) {
  std::vector<Eigen::MatrixXd> Js;
  std::vector<Eigen::VectorXd> rs;
  Eigen::Index rows = 0;
  for (int c = 0; c < static_cast<int>(p.curves.size()); ++c) {
    Eigen::MatrixXd J;
    Eigen::VectorXd r;
    p.jacobian(c, u, &r, &J);
    rows += J.rows();
    Js.push_back(std::move(J));
    rs.push_back(std::move(r));
  }
  Eigen::MatrixXd J(rows, p.n_vars());
  if (r_all) r_all->resize(rows);
  Eigen::Index at = 0;
  for (std::size_t c = 0; c < Js.size(); ++c) {
    J.middleRows(at, Js[c].rows()) = Js[c];
    if (r_all) r_all->segment(at, rs[c].size()) = rs[c];
    at += Js[c].rows();
  }
  return J;
}

// Theta of the stacked rows (for harmonic loadings: each curve's own angles).
Eigen::VectorXd stacked_theta(const std::vector<CurveInput>& curves) {
  Eigen::Index n = 0;
  for (const auto& c : curves) n += c.curve.theta_deg.size();
  Eigen::VectorXd t(n);
  Eigen::Index at = 0;
  for (const auto& c : curves) {
    t.segment(at, c.curve.theta_deg.size()) = c.curve.theta_deg;
    at += c.curve.theta_deg.size();
  }
  return t;
}

std::vector<double> base_values(const std::vector<CurveInput>& curves) {
  std::vector<double> v;
  for (const auto& p : fit_parameters()) v.push_back(p.get(curves.front().base));
  return v;
}

void check_inputs(const std::vector<CurveInput>& curves, const DiagnosisOptions& opts) {
  if (curves.empty()) throw InputError("diagnose needs at least one measured curve (--measured FILE.csv)");
  if (opts.starts < 1) throw InputError("--starts " + std::to_string(opts.starts) + " is invalid: allowed >= 1");
  if (!(opts.cond_limit > 1)) throw InputError("--cond-limit " + num(opts.cond_limit) + " is invalid: allowed > 1");
}

// Circular mean of (measured - model) for a zero offset start value.
double zero_start(const Problem& p, int c, const double* u) {
  std::vector<double> w(u, u + p.n_vars());
  if (p.free_zero) w[p.n_shared() + c] = 0;
  const Eigen::VectorXd r = p.residual(c, w.data());  // model - measured
  double s = 0, co = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    s += std::sin(deg_to_rad(-r[i]));
    co += std::cos(deg_to_rad(-r[i]));
  }
  return rad_to_deg(std::atan2(s, co));
}

// Unit-norm columns; returns the SVD of the normalised matrix and the column norms.
struct NormSvd {
  Eigen::VectorXd norms, s;
  Eigen::MatrixXd V;
};
NormSvd normalised_svd(const Eigen::MatrixXd& J) {
  NormSvd out;
  out.norms = J.colwise().norm().transpose();
  Eigen::MatrixXd Jn = J;
  for (Eigen::Index j = 0; j < J.cols(); ++j)
    if (out.norms[j] > 0) Jn.col(j) /= out.norms[j];
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Jn, Eigen::ComputeThinV);
  out.s = svd.singularValues();
  out.V = svd.matrixV();
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// 3. Default free set: greedy in table order at the configured point.
// ---------------------------------------------------------------------------------------------------------
namespace {
std::vector<std::string> free_set_at(const FieldSource& field, const std::vector<CurveInput>& curves,
                                     const DiagnosisOptions& opts, std::string* note);
}  // namespace

std::vector<std::string> default_free_set(const FieldSource& field, const std::vector<CurveInput>& curves,
                                          const DiagnosisOptions& opts, std::string* note) {
  check_inputs(curves, opts);
  // First at the configured point itself (first-order effects); only when nothing is identifiable there
  // (diff4, ring:N at an ideal mount: every offset acts at second order) at the shifted point.
  DiagnosisOptions o = opts;
  o.nominal_shift = 0.0;
  std::vector<std::string> chosen = free_set_at(field, curves, o, note);
  if (chosen.empty() && opts.nominal_shift != 0.0) {
    std::string first = note ? *note : std::string();
    chosen = free_set_at(field, curves, opts, note);
    if (note)
      *note = "At the configured point no parameter passes (first-order effects cancel), so the set is chosen "
              "at the shifted point. " + *note;
  }
  return chosen;
}

namespace {
std::vector<std::string> free_set_at(const FieldSource& field, const std::vector<CurveInput>& curves,
                                     const DiagnosisOptions& opts, std::string* note) {
  const auto& t = fit_parameters();
  Problem all{field, curves, {}, opts.free_zero, base_values(curves), {}, opts.fd_step};
  for (std::size_t i = 0; i < t.size(); ++i) {
    all.free_idx.push_back(static_cast<int>(i));
    all.scale.push_back(t[i].scale);
  }
  std::vector<double> u(all.n_vars(), 0.0);
  for (int j = 0; j < all.n_shared(); ++j) u[j] = all.base[j] / all.scale[j] + opts.nominal_shift;
  const Eigen::MatrixXd J = stacked_jacobian(all, u.data(), nullptr);  // deg per typical size
  const Eigen::VectorXd theta = stacked_theta(curves);
  const auto rows = static_cast<double>(J.rows());

  std::vector<int> kept;  // columns of J
  for (int c = 0; c < static_cast<int>(curves.size()) && opts.free_zero; ++c) kept.push_back(all.n_shared() + c);
  std::ostringstream os;
  os << "Default free set: parameters taken in table order at the configured point, each kept only if the "
        "column-normalised Jacobian (with the free zero offsets) keeps a condition number <= "
     << num(opts.cond_limit) << ", every kept parameter's predicted sigma at " << num(opts.nominal_noise_deg)
     << " deg noise per sample stays <= " << num(opts.max_sigma_rel) << " of its typical size, and it moves the curve by >= "
     << num(opts.min_effect_deg) << " deg RMS per typical size; evaluated at the configured values"
     << (opts.nominal_shift != 0.0 ? " + " + num(opts.nominal_shift) + " typical sizes on every parameter" : std::string())
     << ".";
  std::vector<std::string> chosen;
  for (int j = 0; j < all.n_shared(); ++j) {
    const double rms = J.col(j).norm() / std::sqrt(rows);  // deg per typical size
    if (rms < opts.min_effect_deg) {
      os << " " << t[j].json_name << ": left out, it barely moves the curve here (RMS " << fmt_sci(rms) << " deg per "
         << num(t[j].scale) << " " << t[j].unit << ").";
      continue;
    }
    std::vector<int> trial = kept;
    trial.push_back(j);
    Eigen::MatrixXd Jt(J.rows(), static_cast<Eigen::Index>(trial.size()));
    for (std::size_t k = 0; k < trial.size(); ++k) Jt.col(static_cast<Eigen::Index>(k)) = J.col(trial[k]);
    const NormSvd ns = normalised_svd(Jt);
    const double cond = ns.s[0] / ns.s[ns.s.size() - 1];
    // Predicted 1-sigma of every kept parameter, in typical sizes, at the nominal noise (J is in deg per
    // typical size): the new parameter must not leave any of them worse than max_sigma_rel.
    double worst = 0;
    std::string worst_name;
    if (cond <= opts.cond_limit) {
      const Eigen::MatrixXd JtJ = Jt.transpose() * Jt;
      const Eigen::MatrixXd cov = opts.nominal_noise_deg * opts.nominal_noise_deg * JtJ.inverse();
      for (std::size_t k = 0; k < trial.size(); ++k) {
        if (trial[k] >= all.n_shared()) continue;  // zero offsets: their size is not a design quantity
        const double sg = std::sqrt(std::max(0.0, cov(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k))));
        if (sg > worst) {
          worst = sg;
          worst_name = t[trial[k]].json_name;
        }
      }
      if (worst <= opts.max_sigma_rel) {
        kept = trial;
        chosen.push_back(t[j].name);
        continue;
      }
    }
    // Which kept parameters it is confounded with: the least-squares combination of the kept (normalised)
    // columns closest to its own column; partners are those with a coefficient above 0.1.
    Eigen::MatrixXd Kn(J.rows(), static_cast<Eigen::Index>(kept.size()));
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const Eigen::VectorXd col = J.col(kept[k]);
      Kn.col(static_cast<Eigen::Index>(k)) = col / std::max(col.norm(), 1e-300);
    }
    const Eigen::VectorXd target = J.col(j) / J.col(j).norm();
    const Eigen::VectorXd coef = Kn.colPivHouseholderQr().solve(target);
    std::vector<std::string> partners;
    std::set<int> shared = loaded_harmonics(theta, J.col(j));
    for (std::size_t k = 0; k < kept.size(); ++k)
      if (std::abs(coef[static_cast<Eigen::Index>(k)]) > 0.1) {
        const int col = kept[k];
        partners.push_back(col >= all.n_shared() ? std::string("the zero offset") : t[col].json_name);
        std::set<int> h = loaded_harmonics(theta, J.col(col)), inter;
        std::set_intersection(shared.begin(), shared.end(), h.begin(), h.end(), std::inserter(inter, inter.begin()));
        if (!inter.empty()) shared = inter;
      }
    const double resid = (Kn * coef - target).norm();
    os << " " << t[j].json_name << ": left out, it and " << (partners.empty() ? std::string("the kept parameters") : join_words(partners))
       << " all load " << harmonics_words(shared) << " (its column is " << fmt(100 * (1 - resid), 1)
       << " % a combination of theirs; ";
    if (cond > opts.cond_limit)
      os << "condition " << fmt_sci(cond) << ").";
    else
      os << "it would leave " << worst_name << " with sigma " << fmt(worst, 2) << " typical sizes at "
         << num(opts.nominal_noise_deg) << " deg noise).";
  }
  if (note) *note = os.str();
  return chosen;
}
}  // namespace

namespace {

// 4.1 Variables: the free parameters' table indices (each once, sorted) and every variable's scale.
Problem make_problem(const FieldSource& field, const std::vector<CurveInput>& curves, const DiagnosisOptions& opts,
                     const std::vector<std::string>& free_names) {
  const auto& t = fit_parameters();
  Problem p{field, curves, {}, opts.free_zero, base_values(curves), {}, opts.fd_step};
  for (const auto& n : free_names) {
    const int i = fit_parameter_index(n);
    if (i < 0) fit_parameter(n);  // throws the listing error
    if (std::find(p.free_idx.begin(), p.free_idx.end(), i) != p.free_idx.end())
      throw InputError("--free lists '" + n + "' twice: allowed each parameter once");
    p.free_idx.push_back(i);
  }
  std::sort(p.free_idx.begin(), p.free_idx.end());
  for (int i : p.free_idx) p.scale.push_back(t[i].scale);
  for (std::size_t c = 0; c < curves.size() && opts.free_zero; ++c) p.scale.push_back(kZeroScaleDeg);
  return p;
}

// The variables' names: the shared parameters' json names, then the zero offsets.
std::vector<std::string> variable_names(const Problem& p, const std::vector<CurveInput>& curves,
                                        const DiagnosisOptions& opts) {
  const auto& t = fit_parameters();
  std::vector<std::string> var_names;
  for (int j = 0; j < p.n_shared(); ++j) var_names.push_back(t[p.free_idx[j]].json_name);
  for (int c = 0; c < static_cast<int>(curves.size()) && opts.free_zero; ++c)
    var_names.push_back(c == 0 ? std::string("zero_offset_deg") : "zero_offset_deg_" + std::to_string(c + 1));
  return var_names;
}

// 4.2 Starts: the configured values, then seeded random points within +-1.5 typical sizes (both signs: the
// mirror-image minima); their zero offsets are set when each start runs.
std::vector<std::vector<double>> start_points(const Problem& p, const DiagnosisOptions& opts) {
  const auto& t = fit_parameters();
  std::mt19937 rng(opts.seed);
  std::uniform_real_distribution<double> uni(-1.5, 1.5);
  std::vector<std::vector<double>> starts;
  for (int s = 0; s < opts.starts; ++s) {
    std::vector<double> u(p.n_vars(), 0.0);
    for (int j = 0; j < p.n_shared(); ++j) {
      const FitParameter& fp = t[p.free_idx[j]];
      const double v = s == 0 ? p.base[p.free_idx[j]] : uni(rng) * fp.scale;
      u[j] = std::clamp(v, fp.lower, fp.upper) / fp.scale;
    }
    starts.push_back(u);
  }
  return starts;
}

// The curves with at most max_samples samples each (every step-th sample).
std::vector<CurveInput> thinned_curves(const std::vector<CurveInput>& curves, int max_samples) {
  std::vector<CurveInput> thin = curves;
  for (auto& c : thin) {
    const auto n = c.curve.theta_deg.size();
    const Eigen::Index step = (n + max_samples - 1) / max_samples;
    if (step <= 1) continue;
    const Eigen::Index m = (n + step - 1) / step;
    MeasuredCurve t2 = c.curve;
    t2.theta_deg.resize(m);
    t2.error_deg.resize(m);
    t2.row.resize(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      t2.theta_deg[i] = c.curve.theta_deg[i * step];
      t2.error_deg[i] = c.curve.error_deg[i * step];
      t2.row[i] = c.curve.row[i * step];
    }
    c.curve = std::move(t2);
  }
  return thin;
}

// A converged start: its cost, its point (scaled variables) and the start it came from.
struct Final {
  double cost;
  std::vector<double> u;
  int start;
};

// The multi-start fit: every converged point on the thinned curves (coarse) and on all samples (finals),
// the best of the latter. start_costs, best_start and iterations of `res` are filled as the starts run.
class MultiStart {
 public:
  MultiStart(const Problem& p, const DiagnosisOptions& opts, bool thinned, DiagnosisResult& res)
      : p_(p), opts_(opts), thinned_(thinned), res_(res) {}

  // One bounded Ceres solve of problem pr from u (set_zero: zero offsets at the circular mean of
  // measured - model first); a converged point goes into `into`.
  void solve_from(const Problem& pr, std::vector<double> u, int s, bool set_zero, std::vector<Final>& into) {
    const auto& t = fit_parameters();
    const int ns = p_.n_shared(), n_curves = static_cast<int>(p_.curves.size());
    try {
      for (int c = 0; c < n_curves && opts_.free_zero && set_zero; ++c)
        u[ns + c] = zero_start(pr, c, u.data()) / kZeroScaleDeg;
    } catch (const InputError&) {
      res_.start_costs.push_back(std::numeric_limits<double>::quiet_NaN());  // start outside the model's domain
      return;
    }
    ceres::Problem problem;
    for (int c = 0; c < n_curves; ++c) problem.AddResidualBlock(new CurveCost(pr, c), nullptr, u.data());
    for (int j = 0; j < ns; ++j) {
      const FitParameter& fp = t[p_.free_idx[j]];
      problem.SetParameterLowerBound(u.data(), j, fp.lower / fp.scale);
      problem.SetParameterUpperBound(u.data(), j, fp.upper / fp.scale);
    }
    for (int c = 0; c < n_curves && opts_.free_zero; ++c) {
      problem.SetParameterLowerBound(u.data(), ns + c, -180.0 / kZeroScaleDeg);
      problem.SetParameterUpperBound(u.data(), ns + c, 180.0 / kZeroScaleDeg);
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = opts_.max_iterations;
    so.function_tolerance = 1e-14;
    so.parameter_tolerance = 1e-12;
    so.gradient_tolerance = 1e-16;
    so.num_threads = 1;  // the Jacobian's model evaluations are parallel themselves
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary sum;
    ceres::Solve(so, &problem, &sum);
    const double cost = sum.IsSolutionUsable() ? sum.final_cost : std::numeric_limits<double>::quiet_NaN();
    if (&into == &coarse || !thinned_) res_.start_costs.push_back(cost);
    if (!std::isfinite(cost)) return;
    into.push_back({cost, u, s});
    if (&into == &finals && cost < best_cost) {
      best_cost = cost;
      best_u = u;
      res_.best_start = s;
      res_.iterations = static_cast<int>(sum.iterations.size()) - 1;
      res_.converged = sum.termination_type == ceres::CONVERGENCE;
      res_.termination = sum.message;
    }
  }

  std::vector<Final> finals, coarse;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<double> best_u;

 private:
  const Problem& p_;
  const DiagnosisOptions& opts_;
  bool thinned_;
  DiagnosisResult& res_;
};

// 4.2 The starts, the mirror image of the best as one more, and (on thinned curves) the polish of the best
// basins on all samples. Throws ComputeError when no start converged.
void run_starts(const Problem& p, const DiagnosisOptions& opts, MultiStart& ms, const Problem& pt, bool thinned) {
  const auto& t = fit_parameters();
  const int nv = p.n_vars(), ns = p.n_shared();
  const std::vector<std::vector<double>> starts = start_points(p, opts);
  std::vector<Final>& first = thinned ? ms.coarse : ms.finals;
  for (int s = 0; s < static_cast<int>(starts.size()); ++s) ms.solve_from(thinned ? pt : p, starts[s], s, true, first);
  // The mirror image of the best point (all shared parameters negated) as one more start: for arrays whose
  // error is even in the offsets (diff4, ring:N) it is an equally good minimum the random starts may miss.
  if (opts.starts > 1 && !first.empty() && ns > 0) {
    const Final* b = &first.front();
    for (const auto& f : first)
      if (f.cost < b->cost) b = &f;
    std::vector<double> m = b->u;
    for (int j = 0; j < ns; ++j) {
      const FitParameter& fp = t[p.free_idx[j]];
      m[j] = std::clamp(-b->u[j] * fp.scale, fp.lower, fp.upper) / fp.scale;
    }
    ms.solve_from(thinned ? pt : p, m, static_cast<int>(starts.size()), true, first);
  }
  if (thinned && !ms.coarse.empty()) {  // polish the best basins on all samples
    double cbest = std::numeric_limits<double>::infinity();
    for (const auto& f : ms.coarse) cbest = std::min(cbest, f.cost);
    std::vector<std::vector<double>> done;
    const std::vector<Final> coarse = ms.coarse;
    for (const auto& f : coarse) {
      if (f.cost > cbest * 1.1 + 1e-15) continue;
      bool dup = false;
      for (const auto& d : done) {
        double dmax = 0;
        for (int j = 0; j < nv; ++j) dmax = std::max(dmax, std::abs(d[j] - f.u[j]));
        if (dmax < 1e-3) dup = true;
      }
      if (dup) continue;
      done.push_back(f.u);
      ms.solve_from(p, f.u, f.start, false, ms.finals);
    }
  }
  if (ms.best_u.empty()) throw ComputeError("diagnose: no start converged (every start left the model's domain)");
}

// A direction of the normalised SVD with singular value below the tolerance: the variables it loads and
// the harmonics they share, in words. Marks those variables unidentifiable.
Confounding confounded_direction(const NormSvd& sv, Eigen::Index k, const Eigen::MatrixXd& J, const Eigen::VectorXd& theta,
                                 const std::vector<std::string>& var_names, std::vector<bool>& unidentifiable) {
  const Eigen::VectorXd v = sv.V.col(k);
  const int nv = static_cast<int>(var_names.size());
  Confounding cf;
  cf.rel_singular = sv.s[k] / sv.s[0];
  std::set<int> shared;
  bool first = true;
  const double vmax = v.cwiseAbs().maxCoeff();
  for (int j = 0; j < nv; ++j)
    if (std::abs(v[j]) > 0.1 * vmax) {
      unidentifiable[j] = true;
      cf.names.push_back(var_names[j]);
      cf.weights.push_back(v[j]);
      if (sv.norms[j] == 0) continue;
      std::set<int> h = loaded_harmonics(theta, J.col(j));
      if (first) {
        shared = h;
        first = false;
      } else {
        std::set<int> inter;
        std::set_intersection(shared.begin(), shared.end(), h.begin(), h.end(), std::inserter(inter, inter.begin()));
        shared = inter.empty() ? shared : inter;
      }
    }
  cf.harmonics = harmonics_words(shared);
  std::ostringstream os;
  if (cf.names.size() == 1)
    os << cf.names[0] << " has (almost) no effect on the curve here";
  else
    os << join_words(cf.names) << " all load " << cf.harmonics << ": the data fix only a combination of them";
  os << " (singular value " << fmt_sci(cf.rel_singular) << " of the largest)";
  cf.text = os.str();
  return cf;
}

// 4.3 Jacobian at the optimum in physical units; uncertainty through the column-normalised SVD. Fills the
// residual statistics, singular values, condition, confounded directions and correlation of `res`;
// returns sigma per variable (infinite where unidentifiable) and marks unidentifiable variables.
Eigen::VectorXd fit_uncertainty(const Problem& p, const DiagnosisOptions& opts, const std::vector<double>& best_u,
                                int N, const std::vector<std::string>& var_names, std::vector<bool>& unidentifiable,
                                DiagnosisResult& res) {
  const auto& t = fit_parameters();
  const int nv = p.n_vars(), ns = p.n_shared();
  Eigen::VectorXd r;
  Eigen::MatrixXd J = stacked_jacobian(p, best_u.data(), &r);
  for (int j = 0; j < nv; ++j) J.col(j) /= p.scale[j];  // deg per physical unit
  res.rss_deg2 = r.squaredNorm();
  res.n_points = N;
  res.n_free = nv;
  res.residual_rms_deg = std::sqrt(res.rss_deg2 / N);
  const double s2 = res.rss_deg2 / (N - nv);
  const NormSvd sv = normalised_svd(J);
  res.singular_values = sv.s;
  const double smax = sv.s[0];
  res.condition = sv.s[sv.s.size() - 1] > 0 ? smax / sv.s[sv.s.size() - 1] : std::numeric_limits<double>::infinity();
  const double tol = smax / opts.cond_limit;
  Eigen::MatrixXd covn = Eigen::MatrixXd::Zero(nv, nv);  // covariance of the normalised variables
  unidentifiable.assign(nv, false);
  const Eigen::VectorXd theta = stacked_theta(p.curves);
  for (Eigen::Index k = 0; k < sv.s.size(); ++k) {
    if (sv.s[k] > tol) {
      const Eigen::VectorXd v = sv.V.col(k);
      covn += v * v.transpose() / (sv.s[k] * sv.s[k]);
      continue;
    }
    res.confounded.push_back(confounded_direction(sv, k, J, theta, var_names, unidentifiable));
  }
  Eigen::VectorXd sigma(nv);
  for (int j = 0; j < nv; ++j)
    sigma[j] = unidentifiable[j] || sv.norms[j] == 0 ? std::numeric_limits<double>::infinity()
                                                      : std::sqrt(s2 * covn(j, j)) / sv.norms[j];
  // A direction can be well conditioned and still barely move the curve: a parameter whose sigma exceeds
  // its typical size is not determined by these data either.
  for (int j = 0; j < nv; ++j)
    if (!unidentifiable[j] && std::isfinite(sigma[j]) && sigma[j] > p.scale[j]) {
      const std::string unit = j < ns ? t[p.free_idx[j]].unit : std::string("deg");
      Confounding cf;
      cf.names = {var_names[j]};
      cf.weights = {1.0};
      cf.rel_singular = std::nan("");
      cf.harmonics = sv.norms[j] > 0 ? harmonics_words(loaded_harmonics(theta, J.col(j))) : "nothing";
      cf.text = var_names[j] + ": sigma " + num(sigma[j]) + " " + unit + " exceeds its typical size " +
                num(p.scale[j]) + " " + unit + ": the curve barely depends on it here";
      res.confounded.push_back(cf);
      unidentifiable[j] = true;
      sigma[j] = std::numeric_limits<double>::infinity();
    }
  res.correlation.resize(nv, nv);
  for (int a = 0; a < nv; ++a)
    for (int b = 0; b < nv; ++b)
      res.correlation(a, b) = (std::isfinite(sigma[a]) && std::isfinite(sigma[b]))
                                  ? covn(a, b) / std::sqrt(covn(a, a) * covn(b, b))
                                  : std::numeric_limits<double>::quiet_NaN();
  return sigma;
}

// 4.4 Other minima as good as the best (cost within 1 %) but more than 3 sigma away in some shared
// parameter: the data cannot choose between them (e.g. mirror images).
void find_alternatives(const Problem& p, const MultiStart& ms, const Eigen::VectorXd& sigma, DiagnosisResult& res) {
  const int nv = p.n_vars(), ns = p.n_shared();
  for (const auto& f : ms.finals) {
    if (f.cost > ms.best_cost * 1.01 + 1e-15) continue;
    bool far = false;
    for (int j = 0; j < ns; ++j) {
      const double d = std::abs(f.u[j] - ms.best_u[j]) * p.scale[j];
      if (std::isfinite(sigma[j]) ? d > 3 * sigma[j] : d > p.scale[j]) far = true;
    }
    if (!far) continue;
    bool dup = false;
    for (const auto& alt : res.alternatives) {
      double dmax = 0;
      for (int j = 0; j < ns; ++j) dmax = std::max(dmax, std::abs(alt.values[j] - f.u[j] * p.scale[j]) / p.scale[j]);
      if (dmax < 1e-3) dup = true;
    }
    if (dup) continue;
    AlternativeMinimum alt;
    alt.cost = f.cost;
    for (int j = 0; j < nv; ++j) alt.values.push_back(f.u[j] * p.scale[j]);
    res.alternatives.push_back(alt);
  }
}

// 4.5 Values: every table parameter, then the zero offsets; the free and the not identifiable variables.
void set_values(const Problem& p, const DiagnosisOptions& opts, const std::vector<double>& best_u,
                const Eigen::VectorXd& sigma, const std::vector<std::string>& var_names,
                const std::vector<bool>& unidentifiable, DiagnosisResult& res) {
  const auto& t = fit_parameters();
  const int nv = p.n_vars(), ns = p.n_shared();
  const std::vector<double> vals = p.values(best_u.data());
  for (std::size_t i = 0; i < t.size(); ++i) {
    ParamValue pv{t[i].name, t[i].json_name, t[i].unit, vals[i], 0.0, false};
    const auto it = std::find(p.free_idx.begin(), p.free_idx.end(), static_cast<int>(i));
    if (it != p.free_idx.end()) {
      pv.free = true;
      pv.sigma = sigma[it - p.free_idx.begin()];
    }
    res.params.push_back(pv);
  }
  for (int c = 0; c < static_cast<int>(p.curves.size()); ++c) {
    ParamValue pv{"zero", var_names.size() > static_cast<std::size_t>(ns + c) ? var_names[ns + c] : "zero_offset_deg", "deg",
                  p.zero(best_u.data(), c), 0.0, opts.free_zero};
    if (!opts.free_zero) pv.json_name = c == 0 ? "zero_offset_deg" : "zero_offset_deg_" + std::to_string(c + 1);
    if (opts.free_zero) pv.sigma = sigma[ns + c];
    res.params.push_back(pv);
  }
  for (int j = 0; j < nv; ++j) {
    res.free.push_back(var_names[j]);
    if (unidentifiable[j]) res.not_identifiable.push_back(var_names[j]);
  }
}

// 4.6 Curves: fitted, residual, spectra.
// 4.7 Whether the fit explains the curves (DiagnosisResult::unexplained).
void judge_fit(const Problem& p, bool free_zero, DiagnosisResult& res) {
  double rss_curves = 0, rss = 0, harmonic = 0;
  for (std::size_t c = 0; c < p.curves.size(); ++c) {
    const Eigen::VectorXd& e = p.curves[c].curve.error_deg;
    const double mean = free_zero ? e.mean() : 0.0;
    rss_curves += (e.array() - mean).square().sum();
    const CurveFit& cf = res.curves[c];
    rss += cf.residual_deg.squaredNorm();
    // harmonics_ls: a0, a1, b1, ..., a8, b8; harmonic k of amplitude A carries A^2 / 2 per sample.
    double hk = 0;
    for (Eigen::Index k = 1; k < cf.residual_h.size(); ++k) hk += 0.5 * cf.residual_h[k] * cf.residual_h[k];
    harmonic += hk * static_cast<double>(e.size());
  }
  res.explained_fraction = rss_curves > 0 ? 1 - rss / rss_curves : 1.0;
  res.residual_harmonic_share = rss > 0 ? std::min(1.0, harmonic / rss) : 0.0;
  if (res.explained_fraction < 0.75 && res.residual_harmonic_share > 0.5)
    res.unexplained = "diagnose: the fit leaves a residual RMS of " + num(res.residual_rms_deg) + " deg, " +
                      num(std::round(100 * std::sqrt(1 - res.explained_fraction))) +
                      " % of the curves' RMS, " + num(std::round(100 * res.residual_harmonic_share)) +
                      " % of it in harmonics 1..8 (an error the model cannot make, not noise): allowed at most 50 % "
                      "(check --array, --r0, --field, --error-sign and the curve's units)";
}

void set_curve_fits(const Problem& p, const std::vector<double>& best_u, DiagnosisResult& res) {
  const auto& curves = p.curves;
  for (int c = 0; c < static_cast<int>(curves.size()); ++c) {
    CurveFit cf;
    const Eigen::VectorXd rr = p.residual(c, best_u.data());
    cf.residual_deg = rr;
    cf.fitted_deg = curves[c].curve.error_deg + rr;
    for (Eigen::Index i = 0; i < cf.fitted_deg.size(); ++i) cf.fitted_deg[i] = wrap_deg(cf.fitted_deg[i]);
    cf.residual_rms_deg = std::sqrt(rr.squaredNorm() / static_cast<double>(rr.size()));
    cf.measured_h = harmonics_ls(curves[c].curve.theta_deg, curves[c].curve.error_deg);
    cf.fitted_h = harmonics_ls(curves[c].curve.theta_deg, cf.fitted_deg);
    cf.residual_h = harmonics_ls(curves[c].curve.theta_deg, rr);
    res.curves.push_back(std::move(cf));
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// 4. The fit.
// ---------------------------------------------------------------------------------------------------------
DiagnosisResult diagnose_curves(const FieldSource& field, const std::vector<CurveInput>& curves,
                                const DiagnosisOptions& opts) {
  check_inputs(curves, opts);
  const auto t0 = std::chrono::steady_clock::now();
  DiagnosisResult res;
  std::vector<std::string> free_names = expand_free_names(opts.free);
  if (free_names.empty())
    free_names = default_free_set(opts.identifiability_field ? *opts.identifiability_field : field, curves, opts,
                                  &res.default_free_note);

  // 4.1 Variables.
  const Problem p = make_problem(field, curves, opts, free_names);
  const int nv = p.n_vars();
  int N = 0;
  for (const auto& c : curves) N += static_cast<int>(c.curve.theta_deg.size());
  if (N <= nv) throw InputError("diagnose: " + std::to_string(N) + " samples for " + std::to_string(nv) + " free parameters: allowed more samples than parameters");

  // 4.2 Starts. They run on a thinned copy of the curves (at most kStartSamples per curve; the starts only
  // have to find the basins), then the best point and every other one within 10 % of its cost are polished
  // on all samples. Without thinning a 3600-sample curve took 5 s for 7 starts.
  constexpr int kStartSamples = 360;
  const std::vector<CurveInput> thin = thinned_curves(curves, kStartSamples);
  const Problem pt{field, thin, p.free_idx, p.free_zero, p.base, p.scale, p.fd_step};
  bool thinned = false;
  for (std::size_t c = 0; c < curves.size(); ++c) thinned |= thin[c].curve.size() != curves[c].curve.size();
  res.starts_thinned = thinned;
  MultiStart ms(p, opts, thinned, res);
  run_starts(p, opts, ms, pt, thinned);

  // 4.3 Uncertainty.
  const std::vector<std::string> var_names = variable_names(p, curves, opts);
  std::vector<bool> unidentifiable;
  const Eigen::VectorXd sigma = fit_uncertainty(p, opts, ms.best_u, N, var_names, unidentifiable, res);
  // 4.4 Alternative minima.
  find_alternatives(p, ms, sigma, res);
  // 4.5 Values.
  set_values(p, opts, ms.best_u, sigma, var_names, unidentifiable, res);
  // 4.6 Curves.
  set_curve_fits(p, ms.best_u, res);
  judge_fit(p, opts.free_zero, res);
  res.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace magenc
