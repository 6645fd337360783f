#include "studies/calibration/calibration_study.hpp"

#include <chrono>
#include <cmath>

#include "analysis/sensor_principles.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "probe/mounting.hpp"

namespace magenc {

namespace {

// Uniform in [-1, 1) for (seed, sample, drift key).
double drift_unit(std::uint64_t seed, std::uint64_t i, std::uint64_t j) {
  const std::uint64_t h = splitmix64(splitmix64(seed ^ 0xC0FFEE1234567ULL) + i * 1024 + j);
  return 2.0 * static_cast<double>(h >> 11) * 0x1.0p-53 - 1.0;
}

// The factory state of sample c in configuration form (mount keys and the chain).
void set_case(Config& s, const ToleranceCase& c, SensorPrinciple p) {
  const Mount& m = c.mount;
  s.set_value("mount.sx_mm", m.sx_mm);
  s.set_value("mount.sy_mm", m.sy_mm);
  s.set_value("mount.dx_mm", m.dx_mm);
  s.set_value("mount.dy_mm", m.dy_mm);
  s.set_value("mount.dz_mm", m.dz_mm);
  s.set_value("mount.tilt_x_deg", m.tilt_x_deg);
  s.set_value("mount.tilt_y_deg", m.tilt_y_deg);
  s.set_value("mount.magnet_tilt_deg", m.magnet_tilt_deg);
  s.set_value("mount.magnet_tilt_azimuth_deg", m.magnet_tilt_azimuth_deg);
  if (!c.chain.ideal() && !relative_offsets(p)) {
    s.set_value("sensor.offset_cos_mT", c.chain.offset_cos_mT);
    s.set_value("sensor.offset_sin_mT", c.chain.offset_sin_mT);
  }
  if (!c.chain.ideal()) {
    s.set_value("sensor.gain_mismatch", c.chain.gain_mismatch);
    s.set_value("sensor.phase_error_deg", c.chain.phase_error_deg);
  }
}

double pp(const Eigen::VectorXd& v) { return v.maxCoeff() - v.minCoeff(); }

}  // namespace

std::vector<KeySpec> CalibrationStudyOptions::keys() {
  std::vector<KeySpec> k = {
      string_list_key("study.sensors", {"two", "diff4", "inplane", "xmr"}, {},
                      "sensors: bz arrays two, diff4, ring:N (on sensor.r0_mm) and the one-spot principles inplane, xmr, amr"),
      string_list_key("study.methods", {"harmonics:8", "lut:32", "ogp"}, {},
                      "calibration methods compared: harmonics:N, lut:K, ogp"),
      string_key("study.field", "analytic", {}, "field source (analytic, fem:DIR, grid:FILE.vti, table:FILE with Bx, By)"),
      int_key("study.samples", 1000, 1, 10000000, "Monte Carlo factory states (each with its drift draw)"),
      int_key("study.seed", 1, 0, 2147483647, "seed of the factory states and the drift draws"),
      int_key("study.mc_steps", 360, 16, 100000, "theta samples per turn of every state"),
      real_list_key("study.drift_scales", {0.25, 0.5, 1, 2}, 0, 100, "",
                    "scale factors of the drift box for the p99-vs-drift-size scan (1 = the box itself)"),
  };
  ToleranceBox box;  // the factory box: sx, sy 0.1, dx, dy 0.05, dz 0.2 mm; no tilts
  box.dx_mm = box.dy_mm = 0.05;
  const auto tol = mount_box_keys(box, true, "factory tolerance box");
  k.insert(k.end(), tol.begin(), tol.end());
  k.push_back(
      table_list_key("drift.keys",
                     {required(string_key("key", "", {}, "a real configuration key (mount.sx_mm, sensor.gain_mismatch, ...)")),
                      required(real_key("half_width", 0, 0, 1e6, "", "the drift is uniform in +-half_width (the key's unit)"))},
                     "[{ key = \"mount.sx_mm\", half_width = 0.02 }, { key = \"mount.sy_mm\", half_width = 0.02 }, "
                     "{ key = \"mount.dx_mm\", half_width = 0.02 }, { key = \"mount.dy_mm\", half_width = 0.02 }, "
                     "{ key = \"mount.dz_mm\", half_width = 0.05 }]",
                     "the drift box: configuration keys and half-widths added to each factory state (a re-mount within a "
                     "smaller tolerance by default; temperature, stray fields as further lines)"));
  return k;
}

CalibrationStudyOptions CalibrationStudyOptions::from_config(const Config& cfg) {
  CalibrationStudyOptions o;
  o.sensors = cfg.strings("study.sensors");
  o.methods = cfg.strings("study.methods");
  for (const auto& m : o.methods) (void)CalibrationMethod::parse(m, "study.methods");
  o.samples = cfg.integer("study.samples");
  o.seed = static_cast<std::uint64_t>(cfg.integer("study.seed"));
  o.mc_steps = static_cast<int>(cfg.integer("study.mc_steps"));
  o.scales = cfg.reals("study.drift_scales");
  o.box = mount_box_from_config(cfg, true);
  for (const auto& t : cfg.tables("drift.keys")) {
    DriftKey d{t.text("key"), 0};
    for (const auto& e : t.entries)
      if (e.field == "half_width") d.half_width = std::get<double>(e.value);
    const KeySpec* k = cfg.find(d.key);
    const std::string allowed = ": allowed a declared real key other than calibration.*, magnet.*, study.*, tol.*, drift.*";
    if (!k || k->type != KeySpec::Type::Real) throw InputError("drift.keys key '" + d.key + "' is not a real configuration key" + allowed);
    for (const char* bad : {"calibration.", "magnet.", "study.", "tol.", "drift."})
      if (d.key.rfind(bad, 0) == 0) throw InputError("drift.keys key '" + d.key + "' cannot drift" + allowed);
    for (const auto& x : o.drift)
      if (x.key == d.key) throw InputError("drift.keys key '" + d.key + "' is given twice: allowed each key once");
    o.drift.push_back(d);
  }
  bool has1 = false;
  for (double s : o.scales) has1 = has1 || s == 1.0;
  if (!has1) o.scales.push_back(1.0);
  return o;
}

CalibrationStudyResult run_calibration_study(const FieldSource& field, const Config& cfg,
                                             const CalibrationStudyOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  CalibrationStudyResult res;
  res.field = field.name();
  for (const auto& m : opt.methods) res.methods.push_back(CalibrationMethod::parse(m, "study.methods"));
  const auto nm = static_cast<Eigen::Index>(res.methods.size());
  const std::vector<ToleranceCase> cases = monte_carlo_cases(opt.box, opt.samples, opt.seed);
  const auto nk = opt.drift.size();
  // Scenarios: the factory state itself, the whole drift box at each scale, each key alone at scale 1.
  std::vector<std::string> scen{"factory"};
  std::vector<std::vector<double>> scale_of_key{std::vector<double>(nk, 0.0)};
  std::size_t scale1 = 0;
  for (double s : opt.scales) {
    if (s == 1.0 && scale1 == 0) scale1 = scen.size();
    scen.push_back("drift x" + fmt_sig(s, 4));
    scale_of_key.push_back(std::vector<double>(nk, s));
  }
  for (std::size_t j = 0; j < nk; ++j) {
    scen.push_back(opt.drift[j].key + " alone");
    std::vector<double> v(nk, 0.0);
    v[j] = 1.0;
    scale_of_key.push_back(v);
  }
  const auto ns = static_cast<int>(scen.size());

  for (const auto& label : opt.sensors) {
    // The sensor's base configuration: principle, steps; its array.
    Config base = cfg;
    ProbeSetup probe = sensor_setup_from_config(cfg, "two");
    const PrincipleSensor ps = principle_sensor(label, probe, "study.sensors");
    base.set_value("sensor.principle", principle_name(ps.setup.principle));
    base.set_value("sensor.steps", static_cast<long>(opt.mc_steps));
    const std::string array = ps.setup.array.name;
    // Per case: uncalibrated pp per scenario, residual pp per scenario x method, c_1..8 of the residual and of the
    // uncalibrated error at scale 1.
    const int n_out = ns + ns * static_cast<int>(nm) + 8 * static_cast<int>(nm) + 8;
    const Eigen::MatrixXd v = evaluate_cases(cases, n_out, [&](std::size_t i, const ToleranceCase& c, double* out) {
      Config ca = base;
      set_case(ca, c, ps.setup.principle);
      const ProbeSetup sa = sensor_setup_from_config(ca, array, "study.sensors");
      const AngleErrorResult at = angle_error(field, sa, Mount::from_config(ca));
      std::vector<Correction> corr;
      for (const auto& m : res.methods) corr.push_back(calibrate(m, at, sa.principle));
      for (int s = 0; s < ns; ++s) {
        AngleErrorResult run;
        if (s == 0) {
          run = at;
        } else {
          Config cb = ca;
          for (std::size_t j = 0; j < nk; ++j) {
            const double f = scale_of_key[static_cast<std::size_t>(s)][j];
            if (f == 0) continue;
            const std::string& key = opt.drift[j].key;
            cb.set_value(key, ca.real(key) + f * opt.drift[j].half_width * drift_unit(opt.seed, i, j));
          }
          run = angle_error(field, sensor_setup_from_config(cb, array, "study.sensors"), Mount::from_config(cb));
        }
        out[s] = pp(run.eps_deg);
        for (Eigen::Index m = 0; m < nm; ++m) {
          const AngleErrorResult r = corrected(corr[static_cast<std::size_t>(m)], run);
          out[ns + s * nm + m] = pp(r.eps_deg);
          if (static_cast<std::size_t>(s) == scale1)
            for (int n = 1; n <= 8; ++n) out[ns + ns * nm + m * 8 + n - 1] = r.spectrum.c_deg[n];
        }
        if (static_cast<std::size_t>(s) == scale1)
          for (int n = 1; n <= 8; ++n) out[ns + ns * nm + nm * 8 + n - 1] = run.spectrum.c_deg[n];
      }
    });
    CalibrationSensorResult r;
    r.label = label;
    r.scenarios = scen;
    r.scale1 = scale1;
    r.uncal_p50.resize(ns);
    r.uncal_p99.resize(ns);
    r.p50.resize(ns, nm);
    r.p99.resize(ns, nm);
    auto col = [&](Eigen::Index k) {
      const Eigen::VectorXd x = v.col(k);
      return std::vector<double>(x.data(), x.data() + x.size());
    };
    for (int s = 0; s < ns; ++s) {
      r.uncal_p50[s] = percentile(col(s), 50);
      r.uncal_p99[s] = percentile(col(s), 99);
      for (Eigen::Index m = 0; m < nm; ++m) {
        r.p50(s, m) = percentile(col(ns + s * nm + m), 50);
        r.p99(s, m) = percentile(col(ns + s * nm + m), 99);
      }
    }
    r.mean_c.resize(nm, 8);
    for (Eigen::Index m = 0; m < nm; ++m)
      for (int n = 0; n < 8; ++n) r.mean_c(m, n) = v.col(ns + ns * nm + m * 8 + n).mean();
    r.uncal_mean_c.resize(8);
    for (int n = 0; n < 8; ++n) r.uncal_mean_c[n] = v.col(ns + ns * nm + nm * 8 + n).mean();
    res.sensors.push_back(std::move(r));
  }
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace magenc
