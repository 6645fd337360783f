#include "analysis/sweep.hpp"

#include <cmath>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "analysis/fit.hpp"
#include "fields/magnet.hpp"

namespace magenc {

namespace {
const std::vector<std::string>& swept_names() {
  static const std::vector<std::string> names = {"sx_mm", "sy_mm", "dx_mm", "dy_mm", "dz_mm", "r0_mm"};
  return names;
}
}  // namespace

ProbeSetup probe_setup_from_config(const Config& cfg, const std::string& array_spec, const std::string& what) {
  return sensor_setup_from_config(cfg, array_spec, what);
}

void check_swept_name(const std::string& swept, const std::string& what) {
  for (const auto& n : swept_names())
    if (n == swept) return;
  throw InputError(what + " = '" + swept + "': allowed one of sx_mm, sy_mm, dx_mm, dy_mm, dz_mm, r0_mm");
}

std::string offset_symbol(const std::string& swept) {
  check_swept_name(swept);
  return swept.substr(0, swept.size() - 3);
}

std::string offset_description(const std::string& swept) {
  const std::string sym = offset_symbol(swept);
  if (sym[0] == 's') return "static eccentricity " + sym;
  if (sym == "dz") return "air-gap offset dz";
  if (sym[0] == 'd') return "dynamic eccentricity " + sym;
  return "probe radius r0";
}

Mount with_offset(Mount base, const std::string& swept, double value_mm) {
  if (swept == "sx_mm") base.sx_mm = value_mm;
  else if (swept == "sy_mm") base.sy_mm = value_mm;
  else if (swept == "dx_mm") base.dx_mm = value_mm;
  else if (swept == "dy_mm") base.dy_mm = value_mm;
  else if (swept == "dz_mm") base.dz_mm = value_mm;
  else throw InputError("mount offset '" + swept + "': allowed one of sx_mm, sy_mm, dx_mm, dy_mm, dz_mm");
  return base;
}

std::vector<double> linspace(double a, double b, int n) {
  if (n < 2) throw InputError("sweep of " + std::to_string(n) + " points: allowed >= 2");
  std::vector<double> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = a + (b - a) * i / (n - 1);
  return v;
}

void check_coef_names(const std::vector<std::string>& coefs, const std::string& what) {
  const auto& allowed = spectrum_columns();
  for (const auto& c : coefs) {
    bool ok = false;
    for (const auto& a : allowed) ok = ok || a == c;
    if (!ok) throw InputError(what + ": '" + c + "' is not a spectra column: allowed a0_deg..a8_deg, b1_deg..b8_deg, c1_deg..c8_deg, pp_deg");
  }
}

std::vector<double> SweepResult::column(const std::string& coef) const {
  std::vector<double> y;
  y.reserve(rows.size());
  for (const auto& r : rows) y.push_back(r.spectrum.column(coef));
  return y;
}

SweepResult run_sweep(const FieldSource& field, const ProbeSetup& setup, const SweepSpec& spec) {
  check_swept_name(spec.swept, "sweep '" + spec.label + "'");
  if (spec.values_mm.empty()) throw InputError("sweep '" + spec.label + "' has no values");
  SweepResult res;
  res.spec = spec;
  res.field = field.name();
  res.setup = setup;
  res.rows.reserve(spec.values_mm.size());
  for (double v : spec.values_mm) {
    ProbeSetup s = setup;
    Mount m = spec.base;
    if (spec.swept == "r0_mm") s.r0_mm = v;
    else m = with_offset(spec.base, spec.swept, v);
    SpectrumRow row;
    row.field = res.field;
    row.array = s.array.name;
    row.r0_mm = s.r0_mm;
    row.mount = m;
    row.spectrum = error_spectrum(field, s, m);
    row.extra = {{"sweep", spec.label}};
    res.rows.push_back(std::move(row));
  }
  return res;
}

std::vector<FitRow> fit_sweep(const SweepResult& sweep, const std::string& study,
                              const std::vector<std::string>& coefs) {
  const auto xs = sweep.x_mm();
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(xs.data(), static_cast<Eigen::Index>(xs.size()));
  std::vector<FitRow> fits;
  for (const auto& coef : coefs) {
    const auto ys = sweep.column(coef);
    Eigen::VectorXd y = Eigen::Map<const Eigen::VectorXd>(ys.data(), static_cast<Eigen::Index>(ys.size()));
    FitRow f;
    f.study = study;
    f.swept = sweep.spec.swept;
    f.coef = coef;
    f.p = fit_cubic(x, y);
    f.extra = {{"field", sweep.field},
               {"array", sweep.setup.array.name},
               {"r0_mm", fmt_sig(sweep.setup.r0_mm, 12)},
               {"sweep", sweep.spec.label}};
    fits.push_back(std::move(f));
  }
  return fits;
}

double eval_cubic(const std::array<double, 4>& p, double x) {
  return ((p[0] * x + p[1]) * x + p[2]) * x + p[3];
}

const FitRow* find_fit(const std::vector<FitRow>& fits, const SweepResult& sweep, const std::string& coef) {
  for (const auto& f : fits) {
    if (f.swept != sweep.spec.swept || f.coef != coef) continue;
    bool same = true;
    for (const auto& [k, v] : f.extra) {
      if (k == "sweep" && v != sweep.spec.label) same = false;
      if (k == "array" && v != sweep.setup.array.name) same = false;
      if (k == "field" && v != sweep.field) same = false;
    }
    if (same) return &f;
  }
  return nullptr;
}

}  // namespace magenc
