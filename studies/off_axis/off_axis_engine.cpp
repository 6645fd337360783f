#include "off_axis_engine.hpp"

#include <chrono>
#include <cmath>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/units.hpp"
#include "probe/angle_error.hpp"
#include "probe/inplane_ellipse.hpp"

namespace magenc {

std::vector<KeySpec> OffAxisOptions::keys() {
  const OffAxisOptions d;
  KeySpec center = real_list_key("off_axis.side_center_mm", {18.0, 0.0}, -1000, 1000, "mm",
                                 "side-shaft chip: die centre [x, y] beside the ring (sensor.center_mm of those readers)",
                                 false, 2);
  std::vector<KeySpec> k = {
      center,
      real_key("off_axis.side_height_mm", -2.0, -1000, 1000, "mm",
               "side-shaft chip: sensing plane height above the top face (-L/2 = the ring's mid-plane)"),
      string_list_key("off_axis.side_principles", d.side_principles, {"inplane", "xmr"},
                      "side-shaft principles (one spot each)"),
      string_list_key("off_axis.methods", d.methods, {},
                      "calibration methods applied to the raw side-shaft reading (ogp, harmonics:N, lut:K), each "
                      "taken at the nominal mount"),
      string_list_key("off_axis.bore_arrays", d.bore_arrays, {}, "Bz arrays around the bore (two, diff4, ring:N)"),
      real_key("off_axis.bore_r0_mm", 13.5, 0, 1000, "mm", "bore arrays: probe radius r0", true),
      real_key("off_axis.bore_height_mm", 1.0, -1000, 1000, "mm",
               "bore arrays: sensing plane height above the top face (negative below the ring)"),
      int_key("off_axis.samples", 200, 1, 1000000, "Monte Carlo samples of the tolerance box per reader"),
      int_key("off_axis.seed", 1, 0, 1000000000, "seed of the Monte Carlo samples (the same mounts for every reader)"),
      int_key("off_axis.steps", 360, 16, 100000, "rotor angles per turn of every curve"),
      real_list_key("off_axis.scan_side_x_mm", d.scan_side_x_mm, -1000, 1000, "mm",
                    "side-shaft read radii of the p99 scan (die centre [x, 0])"),
      real_list_key("off_axis.scan_gap_mm", d.scan_gap_mm, -1000, 1000, "mm", "bore-array plane heights of the p99 scan"),
      int_key("off_axis.scan_samples", 60, 1, 1000000, "Monte Carlo samples per point of the scans and the budget"),
  };
  ToleranceBox box;
  box.sx_mm = 0.1;
  box.sy_mm = 0.1;
  box.dx_mm = 0.05;
  box.dy_mm = 0.05;
  box.dz_mm = 0.2;
  box.tilt_x_deg = 0.5;
  box.tilt_y_deg = 0.5;
  box.magnet_tilt_deg = 0.2;
  for (auto& s : mount_box_keys(box, true, "off_axis")) k.push_back(s);
  return k;
}

OffAxisOptions OffAxisOptions::from_config(const Config& cfg) {
  OffAxisOptions o;
  const std::vector<double> c = cfg.reals("off_axis.side_center_mm");
  if (c.size() != 2)
    throw InputError("off_axis.side_center_mm has " + std::to_string(c.size()) + " numbers: allowed [x, y] in mm");
  o.side_center_mm = {c[0], c[1]};
  o.side_height_mm = cfg.real("off_axis.side_height_mm");
  o.side_principles = cfg.strings("off_axis.side_principles");
  o.methods = cfg.strings("off_axis.methods");
  for (const auto& m : o.methods) (void)CalibrationMethod::parse(m, "off_axis.methods");
  o.bore_arrays = cfg.strings("off_axis.bore_arrays");
  for (const auto& a : o.bore_arrays)
    if (ProbeArray::parse(a, "off_axis.bore_arrays").is_point())
      throw InputError("off_axis.bore_arrays = 'point' is not a Bz array: allowed two, diff4, ring:N");
  o.bore_r0_mm = cfg.real("off_axis.bore_r0_mm");
  o.bore_height_mm = cfg.real("off_axis.bore_height_mm");
  o.box = mount_box_from_config(cfg, true);
  o.samples = cfg.integer("off_axis.samples");
  o.seed = static_cast<std::uint64_t>(cfg.integer("off_axis.seed"));
  o.steps = static_cast<int>(cfg.integer("off_axis.steps"));
  o.scan_side_x_mm = cfg.reals("off_axis.scan_side_x_mm");
  o.scan_gap_mm = cfg.reals("off_axis.scan_gap_mm");
  o.scan_samples = cfg.integer("off_axis.scan_samples");
  if (cfg.real("magnet.inner_radius_mm") <= 0)
    throw InputError("magnet.inner_radius_mm = 0: the off_axis study reads a ring: allowed 0 < inner_radius_mm < radius_mm");
  return o;
}

namespace {

// The probe setup of one reader: the configuration with the reader's sensor keys set over it (so the
// sensor keys' own checks apply: a sensing point in the ring's material is refused), "auto" resolved.
ProbeSetup reader_setup(const FieldSource& field, const Config& cfg, const OffAxisOptions& o,
                        const std::string& principle, const std::string& array, const Eigen::Vector2d& center,
                        double height_mm, bool trim) {
  Config c = cfg;
  c.set("sensor.principle=" + principle);
  c.set("sensor.center_mm=[" + fmt_sig(center.x(), 17) + ", " + fmt_sig(center.y(), 17) + "]");
  c.set("sensor.plane_height_mm=" + fmt_sig(height_mm, 17));
  if (principle == "bz") c.set("sensor.r0_mm=" + fmt_sig(o.bore_r0_mm, 17));
  c.set("sensor.steps=" + std::to_string(o.steps));
  c.set("sensor.direction=auto");
  c.set("sensor.zero_deg=auto");
  c.set(std::string("sensor.gain_trim=") + (trim ? "auto" : "none"));
  try {
    return resolve_orientation(field, sensor_setup_from_config(c, array, "off_axis"));
  } catch (const InputError& e) {
    throw InputError(std::string("off_axis reader ") + principle + " " + array +
                     " (sensor keys from off_axis.side_center_mm, side_height_mm, bore_r0_mm, bore_height_mm, "
                     "scan_side_x_mm, scan_gap_mm): " + e.what());
  }
}

// Per mount: pp, c_1..c_8, field min and max (mT) of the reader (after its correction).
constexpr int kOut = 11;
void evaluate(const FieldSource& field, const ProbeSetup& s, const Correction& corr, const Mount& m, double* out) {
  AngleErrorResult r = angle_error(field, s, m);
  if (!corr.method.none()) r = corrected(corr, r);
  out[0] = r.spectrum.pp_deg;
  for (int n = 1; n <= 8; ++n) out[n] = r.spectrum.c_deg[static_cast<std::size_t>(n)];
  out[9] = r.field_min_mT;
  out[10] = r.field_max_mT;
}

Eigen::MatrixXd over_box(const FieldSource& field, const ProbeSetup& s, const Correction& corr,
                         const ToleranceBox& box, long n, std::uint64_t seed) {
  const std::vector<Mount> mounts = monte_carlo_samples(box, n, seed);
  return evaluate_cases(mounts, kOut, [&](std::size_t, const Mount& m, double* out) { evaluate(field, s, corr, m, out); });
}

double p99_of(const Eigen::MatrixXd& table) {
  return percentile(std::vector<double>(table.col(0).data(), table.col(0).data() + table.rows()), 99);
}

// The Monte Carlo statistics and the budget of one reader.
void fill_statistics(const FieldSource& field, const OffAxisOptions& o, const std::vector<std::string>& groups,
                     OffAxisReader& r) {
  const Eigen::MatrixXd t = over_box(field, r.setup, r.correction, o.box, o.samples, o.seed);
  const std::vector<double> pp(t.col(0).data(), t.col(0).data() + t.rows());
  r.p50_deg = percentile(pp, 50);
  r.p99_deg = percentile(pp, 99);
  r.mean_c_deg = t.block(0, 1, t.rows(), 8).colwise().mean().transpose();
  r.field_min_mT = t.col(9).minCoeff();
  r.field_max_mT = t.col(10).maxCoeff();
  for (const auto& g : groups)
    r.budget_p99_deg.push_back(p99_of(over_box(field, r.setup, r.correction, o.box.only(g), o.scan_samples, o.seed)));
}

// A reader: its setup, the nominal curve, its correction (taken at the nominal mount) and statistics.
OffAxisReader make_reader(const FieldSource& field, const OffAxisOptions& o, const std::vector<std::string>& groups,
                          std::string label, std::string layout, std::string principle, std::string treatment,
                          ProbeSetup setup, const CalibrationMethod& method) {
  OffAxisReader r;
  r.label = std::move(label);
  r.layout = std::move(layout);
  r.principle = std::move(principle);
  r.treatment = std::move(treatment);
  r.setup = std::move(setup);
  const AngleErrorResult nominal = angle_error(field, r.setup, Mount{});
  if (!method.none()) r.correction = calibrate(method, nominal, r.setup.principle);
  const AngleErrorResult shown = method.none() ? nominal : corrected(r.correction, nominal);
  r.nominal_eps_deg = shown.eps_deg;
  r.nominal_pp_deg = shown.spectrum.pp_deg;
  fill_statistics(field, o, groups, r);
  return r;
}

void side_readers(const FieldSource& field, const Config& cfg, const OffAxisOptions& o, OffAxisResult& res) {
  for (const auto& p : o.side_principles) {
    const ProbeSetup raw = reader_setup(field, cfg, o, p, "point", o.side_center_mm, o.side_height_mm, false);
    const ProbeSetup trim = reader_setup(field, cfg, o, p, "point", o.side_center_mm, o.side_height_mm, true);
    if (&p == &o.side_principles.front()) {
      const AngleErrorResult nominal = angle_error(field, raw, Mount{});
      res.k = inplane_ellipse_k(nominal);
      res.trim_gain_mismatch = trim.chain.gain_mismatch;
      res.ogp_trim = 1.0 / correct_channels(nominal.channels).ellipse.gain_ratio - 1.0;
    }
    res.readers.push_back(make_reader(field, o, res.groups, "side " + p + " raw", "side-shaft", p, "raw", raw, {}));
    res.readers.push_back(
        make_reader(field, o, res.groups, "side " + p + " trimmed", "side-shaft", p, "trimmed (BCT)", trim, {}));
    for (const auto& m : o.methods)
      res.readers.push_back(make_reader(field, o, res.groups, "side " + p + " " + m, "side-shaft", p, m, raw,
                                        CalibrationMethod::parse(m, "off_axis.methods")));
  }
}

void scans(const FieldSource& field, const Config& cfg, const OffAxisOptions& o, OffAxisResult& res) {
  const std::string p = o.side_principles.front();
  for (double x : o.scan_side_x_mm) {
    const Eigen::Vector2d c(x, 0.0);
    const ProbeSetup raw = reader_setup(field, cfg, o, p, "point", c, o.side_height_mm, false);
    const ProbeSetup trim = reader_setup(field, cfg, o, p, "point", c, o.side_height_mm, true);
    res.scan_side_k.push_back(p == "inplane" ? inplane_ellipse_k(angle_error(field, raw, Mount{})) : 0.0);
    res.scan_side_p99_raw.push_back(p99_of(over_box(field, raw, {}, o.box, o.scan_samples, o.seed)));
    res.scan_side_p99_trim.push_back(p99_of(over_box(field, trim, {}, o.box, o.scan_samples, o.seed)));
  }
  for (const auto& a : o.bore_arrays) {
    std::vector<double> row;
    for (double g : o.scan_gap_mm) {
      const ProbeSetup s = reader_setup(field, cfg, o, "bz", a, Eigen::Vector2d::Zero(), g, false);
      row.push_back(p99_of(over_box(field, s, {}, o.box, o.scan_samples, o.seed)));
    }
    res.scan_gap_p99.push_back(row);
  }
}

void field_map(const FieldSource& field, const Magnet& m, OffAxisResult& res) {
  const int n = 48;
  const double half = 1.5 * m.radius_mm, step = 2.0 * half / n;
  for (int i = 0; i < n; ++i) res.map_x_mm.push_back(-half + (i + 0.5) * step);
  res.map_y_mm = res.map_x_mm;
  Eigen::Matrix3Xd p(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) p.col(j * n + i) = Eigen::Vector3d(res.map_x_mm[i], res.map_y_mm[j], 0.0);
  const Eigen::Matrix3Xd B = field.B_T(p);
  for (int j = n - 1; j >= 0; --j) {
    std::vector<double> row;
    for (int i = 0; i < n; ++i) row.push_back(1e3 * std::hypot(B(0, j * n + i), B(1, j * n + i)));
    res.map_mT.push_back(row);
  }
}

}  // namespace

OffAxisResult run_off_axis(const Config& cfg, const OffAxisOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  OffAxisResult res;
  res.magnet = Magnet::from_config(cfg);
  const AnalyticField field(res.magnet);
  for (const auto& g : {"static", "dynamic", "air gap", "sensor tilt", "magnet tilt"}) res.groups.emplace_back(g);
  res.theta_deg = uniform_theta_deg(o.steps);
  side_readers(field, cfg, o, res);
  for (const auto& a : o.bore_arrays) {
    const ProbeSetup s = reader_setup(field, cfg, o, "bz", a, Eigen::Vector2d::Zero(), o.bore_height_mm, false);
    res.readers.push_back(make_reader(field, o, res.groups, "bore " + a, "bore", "bz", a, s, {}));
  }
  scans(field, cfg, o, res);
  field_map(field, res.magnet, res);
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace magenc
