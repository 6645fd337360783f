#include "analysis/sensor_principles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace magenc {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

bool is_principle_entry(const std::string& e) { return e == "inplane" || e == "xmr" || e == "amr"; }
}  // namespace

PrincipleSensor principle_sensor(const std::string& entry, const ProbeSetup& base, const std::string& what) {
  PrincipleSensor s;
  s.label = entry;
  s.setup = base;
  if (is_principle_entry(entry)) {
    s.setup.principle = parse_principle(entry, what);
    s.setup.array = ProbeArray::parse("point", what);
  } else {
    if (entry == "point" || entry == "bz")
      throw InputError(what + ": '" + entry + "' is not a sensor: allowed two, diff4, ring:N, inplane, xmr, amr");
    s.setup.principle = SensorPrinciple::Bz;
    try {
      s.setup.array = ProbeArray::parse(entry, what);
    } catch (const InputError&) {
      throw InputError(what + ": '" + entry + "' is not a sensor: allowed two, diff4, ring:N, inplane, xmr, amr");
    }
  }
  return s;
}

std::vector<KeySpec> SensorPrinciplesOptions::keys() {
  std::vector<KeySpec> k = {
      string_list_key("study.sensors", {"two", "diff4", "ring:8", "inplane", "xmr", "amr"}, {},
                      "sensors to compare: bz arrays two, diff4, ring:N (on sensor.r0_mm) and the one-spot "
                      "principles inplane, xmr, amr"),
      string_key("study.field", "analytic", {}, "field source (analytic, fem:DIR, grid:FILE.vti, table:FILE with Bx, By)"),
      int_key("study.samples", 400, 1, 10000000, "Monte Carlo samples over the tolerance box (the same for every sensor)"),
      int_key("study.seed", 1, 0, 2147483647, "Monte Carlo seed"),
      int_key("study.mc_steps", 360, 16, 100000, "theta samples per turn of the Monte Carlo cases"),
      real_key("study.case_offset_mm", 0.1, 0, 10, "mm", "single-error cases: sx, sy, dx, dy", true),
      real_key("study.case_dz_mm", 0.2, 0, 10, "mm", "single-error case dz (with dx = case_residual_dx_mm)", true),
      real_key("study.case_residual_dx_mm", 0.05, 0, 10, "mm", "dx of the dz case (dz alone changes nothing)"),
      real_key("study.case_tilt_deg", 1.0, 0, 10, "deg", "single-error cases: sensor tilt x, y; magnet tilt", true),
  };
  ToleranceBox box;  // the default box: sx, sy 0.1, dx, dy 0.05, dz 0.2 mm; sensor tilts 1, magnet lean 0.5 deg
  box.dx_mm = box.dy_mm = 0.05;
  box.tilt_x_deg = box.tilt_y_deg = 1.0;
  box.magnet_tilt_deg = 0.5;
  const auto tol = mount_box_keys(box, true, "tolerance box");
  k.insert(k.end(), tol.begin(), tol.end());
  for (const char* p : {"bz", "inplane", "xmr", "amr"}) {
    k.push_back(real_key(std::string("window.") + p + "_min_mT", 0.0, 0, 1e6, "mT",
                         std::string("field window of the ") + p + " sensors: least magnitude (0 = none)"));
    k.push_back(real_key(std::string("window.") + p + "_max_mT", kInf, 0, kInf, "mT",
                         std::string("field window of the ") + p + " sensors: largest magnitude (inf = none)", true));
  }
  return k;
}

SensorPrinciplesOptions SensorPrinciplesOptions::from_config(const Config& cfg) {
  SensorPrinciplesOptions o;
  o.sensors = cfg.strings("study.sensors");
  o.samples = cfg.integer("study.samples");
  o.seed = static_cast<std::uint64_t>(cfg.integer("study.seed"));
  o.mc_steps = static_cast<int>(cfg.integer("study.mc_steps"));
  o.case_offset_mm = cfg.real("study.case_offset_mm");
  o.case_dz_mm = cfg.real("study.case_dz_mm");
  o.case_residual_dx_mm = cfg.real("study.case_residual_dx_mm");
  o.case_tilt_deg = cfg.real("study.case_tilt_deg");
  o.box = mount_box_from_config(cfg, true);
  for (const auto& s : o.sensors) {
    const std::string p = is_principle_entry(s) ? s : "bz";
    FieldWindow w{cfg.real("window." + p + "_min_mT"), cfg.real("window." + p + "_max_mT")};
    if (w.min_mT > w.max_mT)
      throw InputError("window." + p + "_min_mT = " + num(w.min_mT) + " exceeds window." + p +
                       "_max_mT = " + num(w.max_mT) + ": allowed min <= max");
    o.windows.push_back(w);
  }
  return o;
}

std::vector<std::pair<std::string, Mount>> principle_cases(const SensorPrinciplesOptions& opt) {
  std::vector<std::pair<std::string, Mount>> c;
  auto add = [&](const std::string& label, auto set) {
    Mount m;
    set(m);
    c.emplace_back(label, m);
  };
  const double o = opt.case_offset_mm, t = opt.case_tilt_deg;
  add("sx", [&](Mount& m) { m.sx_mm = o; });
  add("sy", [&](Mount& m) { m.sy_mm = o; });
  add("dx", [&](Mount& m) { m.dx_mm = o; });
  add("dy", [&](Mount& m) { m.dy_mm = o; });
  add("dz", [&](Mount& m) {
    m.dz_mm = opt.case_dz_mm;
    m.dx_mm = opt.case_residual_dx_mm;
  });
  add("tilt_x", [&](Mount& m) { m.tilt_x_deg = t; });
  add("tilt_y", [&](Mount& m) { m.tilt_y_deg = t; });
  add("magnet_tilt", [&](Mount& m) { m.magnet_tilt_deg = t; });
  return c;
}

SensorPrinciplesResult run_sensor_principles(const FieldSource& field, const ProbeSetup& base,
                                             const SensorPrinciplesOptions& opt) {
  SensorPrinciplesResult res;
  res.field = field.name();
  res.cases = principle_cases(opt);
  if (opt.windows.size() != opt.sensors.size())
    throw InputError("sensor_principles: one field window per sensor is needed");
  std::vector<PrincipleSensor> sensors;
  for (std::size_t i = 0; i < opt.sensors.size(); ++i) {
    sensors.push_back(principle_sensor(opt.sensors[i], base, "study.sensors"));
    sensors.back().setup.window = opt.windows[i];
  }
  // Everything checked before the work: each sensor on the ideal mount (source, principle, window).
  for (const auto& s : sensors) {
    ProbeSetup t = s.setup;
    t.steps = 16;
    (void)angle_error(field, t, Mount{});
  }
  const std::vector<ToleranceCase> samples = monte_carlo_cases(opt.box, opt.samples, opt.seed);
  for (const auto& s : sensors) {
    PrincipleSensorResult r;
    r.label = s.label;
    r.principle = s.setup.principle;
    r.window = s.setup.window;
    // 1. The ideal mount and each error alone (sensor.steps samples).
    const AngleErrorResult ideal = angle_error(field, s.setup, Mount{});
    r.ideal_field_min_mT = ideal.field_min_mT;
    r.ideal_field_max_mT = ideal.field_max_mT;
    for (const auto& [label, mount] : res.cases) {
      r.cases.push_back(angle_error(field, s.setup, mount));
      SpectrumRow row;
      row.field = field.name();
      row.array = s.setup.array.name;
      row.r0_mm = s.setup.array.is_point() ? 0.0 : s.setup.r0_mm;  // the point array has no radius
      row.mount = mount;
      row.spectrum = r.cases.back().spectrum;
      auto g10 = [](double v) { return fmt_sig(v, 10); };
      row.extra = {{"sensor", s.label},
                   {"principle", principle_name(s.setup.principle)},
                   {"case", label},
                   {"tilt_x_deg", g10(mount.tilt_x_deg)},
                   {"tilt_y_deg", g10(mount.tilt_y_deg)},
                   {"magnet_tilt_deg", g10(mount.magnet_tilt_deg)},
                   {"field_min_mT", g10(r.cases.back().field_min_mT)},
                   {"field_max_mT", g10(r.cases.back().field_max_mT)},
                   {"in_window", r.cases.back().in_window ? "1" : "0"}};
      res.spectra.push_back(std::move(row));
      r.cases.back().probe_B_T.resize(0, 0);  // keep the result small: spectra and extremes are what is reported
      r.cases.back().inplane_B_T.resize(0, 0);
    }
    // 2. Monte Carlo over the box (mc_steps samples per turn): pp, field min, field max per sample.
    ProbeSetup mc_setup = s.setup;
    mc_setup.steps = opt.mc_steps;
    const Eigen::MatrixXd v = evaluate_cases(samples, 3, [&](std::size_t, const ToleranceCase& c, double* out) {
      const AngleErrorResult a = angle_error(field, mc_setup, c.mount);
      out[0] = a.spectrum.pp_deg;
      out[1] = a.field_min_mT;
      out[2] = a.field_max_mT;
    });
    std::vector<double> kept;
    r.mc_field_min_mT = v.col(1).minCoeff();
    r.mc_field_max_mT = v.col(2).maxCoeff();
    r.margin_low_mT = r.window.min_mT > 0 ? r.mc_field_min_mT - r.window.min_mT : kInf;
    r.margin_high_mT = std::isinf(r.window.max_mT) ? kInf : r.window.max_mT - r.mc_field_max_mT;
    for (Eigen::Index i = 0; i < v.rows(); ++i) {
      if (r.window.contains(v(i, 1), v(i, 2))) kept.push_back(v(i, 0));
      else ++r.mc_out_of_window;
    }
    if (kept.empty()) r.mc = SampleStats{0, kInf, kInf, kInf, kInf};
    else r.mc = sample_stats(Eigen::Map<const Eigen::VectorXd>(kept.data(), static_cast<Eigen::Index>(kept.size())));
    res.sensors.push_back(std::move(r));
  }
  return res;
}

}  // namespace magenc
