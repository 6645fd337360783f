#include "speed_engine.hpp"

#include <algorithm>
#include <cmath>

#include "analysis/calibration.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

std::vector<KeySpec> SpeedStudyOptions::keys() {
  const SpeedStudyOptions d;
  return {
      string_key("study.field", "analytic", {}, "field source (analytic, fem:DIR, grid:FILE.vti, table:FILE)"),
      string_list_key("study.timing_names", {"AS5045 fast", "AS5045 slow"}, {}, "names of the timings compared"),
      real_list_key("study.timing_delay_us", {96, 384}, 0, 1e6, "us", "delay of each timing (sensor.delay_us)"),
      real_list_key("study.timing_filter_hz", {0, 0}, 0, 1e9, "Hz", "channel filter of each timing; 0 = none"),
      real_list_key("study.timing_sample_hz", {10416.67, 2604.17}, 0, 1e9, "Hz",
                    "output update rate of each timing; 0 = continuous"),
      real_key("study.rpm_max", d.rpm_max, 0, 1e6, "rpm", "fastest speed of the sweeps", true),
      int_key("study.rpm_points", d.rpm_points, 2, 10000, "speeds 0..rpm_max of the sweeps"),
      real_key("study.filter_hz", d.filter_hz, 0, 1e9, "Hz", "first-order filter of the attenuation part", true),
      int_list_key("study.pole_pairs", d.pole_pairs, 1, 1000, "motor pole pairs of the commutation part"),
      string_key("study.calibration_method", d.calibration_method, {},
                 "correction taken at rest and at study.calibration_rpm: harmonics:N, lut:K"),
      string_key("study.calibration_timing", "", {}, "timing of the calibration part (a study.timing_names entry; "
                 "empty: the first)"),
      real_key("study.calibration_rpm", d.calibration_rpm, -1e6, 1e6, "rpm", "speed of the moving calibration"),
      int_key("study.steps", d.steps, 16, 100000, "theta samples per turn"),
  };
}

SpeedStudyOptions SpeedStudyOptions::from_config(const Config& cfg) {
  SpeedStudyOptions o;
  const auto names = cfg.strings("study.timing_names");
  const auto delay = cfg.reals("study.timing_delay_us"), filter = cfg.reals("study.timing_filter_hz"),
             sample = cfg.reals("study.timing_sample_hz");
  if (delay.size() != names.size() || filter.size() != names.size() || sample.size() != names.size())
    throw InputError("study.timing_delay_us, study.timing_filter_hz, study.timing_sample_hz have " +
                     std::to_string(delay.size()) + ", " + std::to_string(filter.size()) + ", " +
                     std::to_string(sample.size()) + " values: allowed one per study.timing_names (" +
                     std::to_string(names.size()) + ")");
  for (std::size_t i = 0; i < names.size(); ++i) o.timings.push_back({names[i], delay[i], filter[i], sample[i]});
  o.rpm_max = cfg.real("study.rpm_max");
  o.rpm_points = static_cast<int>(cfg.integer("study.rpm_points"));
  o.filter_hz = cfg.real("study.filter_hz");
  o.pole_pairs = cfg.integers("study.pole_pairs");
  o.calibration_method = cfg.str("study.calibration_method");
  const CalibrationMethod method = CalibrationMethod::parse(o.calibration_method, "study.calibration_method");
  if (method.none() || method.kind == CalibrationKind::Ogp)
    throw InputError("study.calibration_method = " + o.calibration_method + " is not a table: allowed harmonics:N, lut:K");
  o.calibration_rpm = cfg.real("study.calibration_rpm");
  const std::string cal_timing = cfg.str("study.calibration_timing");
  std::string allowed;
  for (const auto& t : o.timings) {
    allowed += (allowed.empty() ? "" : ", ") + t.name;
    if (t.name == cal_timing || (cal_timing.empty() && &t == &o.timings.front())) o.calibration_timing = t;
  }
  if (o.calibration_timing.name.empty() && !o.timings.empty())
    throw InputError("study.calibration_timing = '" + cal_timing + "' is not a timing: allowed one of " + allowed);
  o.steps = static_cast<int>(cfg.integer("study.steps"));
  const double f_rot_hz = std::max(o.rpm_max, std::abs(o.calibration_rpm)) / 60.0;
  for (const auto& t : o.timings)
    if (t.sample_hz > 0 && t.sample_hz < 2 * f_rot_hz)
      throw InputError("study.timing_sample_hz = " + num(t.sample_hz) + " (" + t.name +
                       ") is below twice the rotation frequency at study.rpm_max = " + num(o.rpm_max) +
                       ": allowed 0 or >= " + num(2 * f_rot_hz) + " Hz");
  return o;
}

std::vector<double> SpeedStudyOptions::rpms() const {
  std::vector<double> r;
  for (int i = 0; i < rpm_points; ++i) r.push_back(rpm_max * i / (rpm_points - 1));
  return r;
}

namespace {

ProbeSetup with_speed(ProbeSetup s, double rpm, const SpeedTiming& t, Prediction p) {
  s.speed = SpeedChain{};
  s.speed.rpm = rpm;
  s.speed.delay_us = t.delay_us;
  s.speed.filter_hz = t.filter_hz;
  s.speed.sample_hz = t.sample_hz;
  s.speed.prediction = rpm != 0 ? p : Prediction::None;  // at rest there is nothing to predict
  return s;
}

CommutationPoint commutation_of(const SpeedPoint& sp, const Eigen::VectorXd& eps_deg, int p) {
  CommutationPoint c{sp.timing, sp.prediction, sp.rpm, p};
  c.electrical_mean_deg = p * sp.spectrum.a0_deg;
  c.electrical_max_deg = p * eps_deg.cwiseAbs().maxCoeff();
  const Eigen::ArrayXd torque = (eps_deg.array() * (p * kPi / 180.0)).cos();
  c.torque_mean = torque.mean();
  c.torque_min = torque.minCoeff();
  return c;
}

void run_sweep(const FieldSource& field, const ProbeSetup& base, const Mount& mount, SpeedStudyResult& r) {
  for (const auto& t : r.options.timings)
    for (const Prediction p : {Prediction::None, Prediction::Ideal})
      for (const double rpm : r.options.rpms()) {
        const AngleErrorResult e = angle_error(field, with_speed(base, rpm, t, p), mount);
        const SpeedPoint sp{t.name, p, rpm, e.spectrum};
        r.sweep.push_back(sp);
        for (const long pp : r.options.pole_pairs) r.commutation.push_back(commutation_of(sp, e.eps_deg, int(pp)));
      }
}

void run_attenuation(const FieldSource& field, const ProbeSetup& base, const Mount& mount, SpeedStudyResult& r) {
  SpeedTiming filter_only{"filter", 0, r.options.filter_hz, 0};
  for (const double rpm : r.options.rpms())
    r.attenuation.push_back({rpm, angle_error(field, with_speed(base, rpm, filter_only, Prediction::None), mount).spectrum});
}

void run_calibration(const FieldSource& field, const ProbeSetup& base, const Mount& mount, SpeedStudyResult& r) {
  const SpeedStudyOptions& o = r.options;
  const CalibrationMethod method = CalibrationMethod::parse(o.calibration_method, "study.calibration_method");
  SpeedTiming timing = o.calibration_timing;
  timing.sample_hz = 0;  // (the hold's sawtooth is the sampling's, not a function of the angle)
  auto at = [&](double rpm) { return angle_error(field, with_speed(base, rpm, timing, Prediction::None), mount); };
  const Correction at_rest = calibrate(method, at(0.0), base.principle);
  const Correction moving = calibrate(method, at(o.calibration_rpm), base.principle);
  for (const double rpm : o.rpms()) {
    const AngleErrorResult run = at(rpm);
    const Eigen::VectorXd rest = residual_deg(at_rest, run), mov = residual_deg(moving, run);
    auto pp = [](const Eigen::VectorXd& v) { return v.maxCoeff() - v.minCoeff(); };
    r.calibration.push_back({rpm, run.spectrum.pp_deg, pp(rest), pp(mov), run.eps_deg.cwiseAbs().maxCoeff(),
                             rest.cwiseAbs().maxCoeff(), mov.cwiseAbs().maxCoeff()});
  }
}

}  // namespace

SpeedStudyResult run_speed_study(const FieldSource& field, const ProbeSetup& base_in, const Mount& mount,
                                 const SpeedStudyOptions& opt) {
  SpeedStudyResult r;
  r.field = field.name();
  r.mount = mount;
  r.options = opt;
  ProbeSetup base = base_in;
  base.steps = opt.steps;
  r.array = base.array.name;
  run_sweep(field, base, mount, r);
  run_attenuation(field, base, mount, r);
  run_calibration(field, base, mount, r);
  return r;
}

}  // namespace magenc
