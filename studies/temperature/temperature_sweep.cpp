#include "studies/temperature/temperature_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/sensor_principles.hpp"
#include "core/errors.hpp"

namespace magenc {

std::vector<KeySpec> TemperatureOptions::keys() {
  const TemperatureOptions d;
  std::vector<KeySpec> k = {
      string_list_key("study.sensors", d.sensors, {},
                      "sensors: bz arrays two, diff4, ring:N (on sensor.r0_mm) and inplane (mT offsets drift)"),
      string_key("study.field", "analytic", {}, "field source (analytic, fem:DIR, grid:FILE.vti, table:FILE)"),
      real_key("study.temperature_min_C", d.temperature_min_C, -273.15, 1000, "C", "lowest temperature"),
      real_key("study.temperature_max_C", d.temperature_max_C, -273.15, 1000, "C", "highest temperature"),
      real_key("study.temperature_step_K", d.temperature_step_K, 0, 1000, "K", "temperature step", true),
      int_key("study.samples", d.samples, 1, 10000000, "Monte Carlo samples of the box at 20 C (p99 mount)"),
      int_key("study.seed", 1, 0, 2147483647, "Monte Carlo seed"),
      int_key("study.steps", d.steps, 16, 100000, "theta samples per turn"),
  };
  ToleranceBox box;  // sx, sy 0.1, dx, dy 0.05, dz 0.2 mm; sensor tilts 0.5 deg
  box.dx_mm = box.dy_mm = 0.05;
  box.tilt_x_deg = box.tilt_y_deg = 0.5;
  const auto tol = mount_box_keys(box, false, "tolerance box");
  k.insert(k.end(), tol.begin(), tol.end());
  return k;
}

TemperatureOptions TemperatureOptions::from_config(const Config& cfg) {
  TemperatureOptions o;
  o.sensors = cfg.strings("study.sensors");
  o.temperature_min_C = cfg.real("study.temperature_min_C");
  o.temperature_max_C = cfg.real("study.temperature_max_C");
  o.temperature_step_K = cfg.real("study.temperature_step_K");
  if (!(o.temperature_min_C <= o.temperature_max_C))
    throw InputError("study.temperature_min_C = " + num(o.temperature_min_C) + " exceeds study.temperature_max_C = " +
                     num(o.temperature_max_C) + ": allowed min <= max");
  if ((o.temperature_max_C - o.temperature_min_C) / o.temperature_step_K > 10000)
    throw InputError("study.temperature_step_K = " + num(o.temperature_step_K) +
                     " makes more than 10000 temperatures: allowed a step >= (max - min) / 10000");
  o.samples = cfg.integer("study.samples");
  o.seed = static_cast<std::uint64_t>(cfg.integer("study.seed"));
  o.steps = static_cast<int>(cfg.integer("study.steps"));
  o.box = mount_box_from_config(cfg, false);
  return o;
}

std::vector<double> TemperatureOptions::temperatures_C() const {
  std::vector<double> t;
  const int n = static_cast<int>(std::floor((temperature_max_C - temperature_min_C) / temperature_step_K + 1e-9));
  for (int i = 0; i <= n; ++i) t.push_back(temperature_min_C + i * temperature_step_K);
  if (t.back() < temperature_max_C - 1e-9) t.push_back(temperature_max_C);
  return t;
}

namespace {

TemperatureCurve sweep(const FieldSource& field, const ProbeSetup& setup, const Mount& mount, const std::string& sensor,
                       const std::string& label, const std::vector<double>& temps) {
  TemperatureCurve c;
  c.sensor = sensor;
  c.mount_label = label;
  c.mount = mount;
  for (double t : temps) {
    ProbeSetup s = setup;
    s.env.temperature_C = t;
    const AngleErrorResult r = angle_error(field, s, mount);
    TemperaturePoint p;
    p.temperature_C = t;
    p.br_scale = s.env.br_scale();
    p.spectrum = r.spectrum;
    p.field_min_mT = r.field_min_mT;
    p.field_max_mT = r.field_max_mT;
    p.in_window = r.in_window;
    p.margin_low_mT = r.field_min_mT - s.window.min_mT;
    p.margin_high_mT = s.window.max_mT - r.field_max_mT;
    c.points.push_back(p);
  }
  return c;
}

}  // namespace

TemperatureResult run_temperature_sweep(const FieldSource& field, const ProbeSetup& base, const Mount& mount,
                                        const TemperatureOptions& opt) {
  TemperatureResult r;
  r.field = field.name();
  r.coefficients = base.env;
  r.coefficients.temperature_C = kReferenceTemperature_C;
  r.window = base.window;
  const std::vector<double> temps = opt.temperatures_C();
  const std::vector<ToleranceCase> cases = monte_carlo_cases(opt.box, opt.samples, opt.seed);
  for (const auto& entry : opt.sensors) {
    PrincipleSensor sen = principle_sensor(entry, base, "study.sensors");
    sen.setup.steps = opt.steps;
    if (sen.setup.principle == SensorPrinciple::Xmr || sen.setup.principle == SensorPrinciple::Amr)
      throw InputError("study.sensors: '" + entry + "' has relative offsets that do not drift in uT/K: allowed two, "
                       "diff4, ring:N, inplane");
    r.curves.push_back(sweep(field, sen.setup, mount, entry, "mount", temps));
    // The box at 20 C: the sample nearest the 99th percentile of pp.
    ProbeSetup at20 = sen.setup;
    at20.env.temperature_C = kReferenceTemperature_C;
    const Eigen::MatrixXd pp = evaluate_cases(cases, 1, [&](std::size_t, const ToleranceCase& c, double* out) {
      out[0] = angle_error(field, at20, c.mount).spectrum.pp_deg;
    });
    std::vector<double> v(pp.data(), pp.data() + pp.rows());
    const double p99 = percentile(v, 99.0);
    std::size_t best = 0;
    for (std::size_t i = 1; i < v.size(); ++i)
      if (std::abs(v[i] - p99) < std::abs(v[best] - p99)) best = i;
    r.p99_pp_deg.push_back(p99);
    r.curves.push_back(sweep(field, sen.setup, cases[best].mount, entry, "box p99", temps));
  }
  return r;
}

}  // namespace magenc
