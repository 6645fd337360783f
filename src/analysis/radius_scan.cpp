#include "analysis/radius_scan.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>

#include <Eigen/Dense>

#include "probe/angle_error.hpp"
#include "probe/signal_chain.hpp"
#include "core/errors.hpp"
#include "fields/analytic_field.hpp"
#include "fields/magnet.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// ---------------------------------------------------------------------------
// Options

std::vector<KeySpec> RadiusScanOptions::keys() {
  std::vector<KeySpec> k = {
      string_list_key("radius.fields", {"analytic"}, {},
                      "field sources to scan (analytic, linear, grid:FILE.vti, table:FILE, fem:DIR)"),
      string_key("radius.fem_dir", "output/field", {},
                 "add fem:<dir> when <dir>/solve.json exists and no fem: field is listed (empty = never)"),
      string_list_key("radius.arrays", {"two", "diff4", "ring:8"}, {}, "probe arrays to compare"),
      real_key("radius.r0_min_mm", 0.5, 0, 1000, "mm", "smallest probe radius scanned", true),
      real_key("radius.r0_max_mm", 3.5, 0, 1000, "mm", "largest probe radius scanned", true),
      real_key("radius.r0_step_mm", 0.05, 0, 100, "mm", "probe radius step", true),
      real_key("radius.tol_sx_mm", 0.1, 0, 10, "mm", "tolerance box: |sx| <= this"),
      real_key("radius.tol_sy_mm", 0.1, 0, 10, "mm", "tolerance box: |sy| <= this"),
      real_key("radius.tol_dx_mm", 0.1, 0, 10, "mm", "tolerance box: |dx| <= this"),
      real_key("radius.tol_dy_mm", 0.1, 0, 10, "mm", "tolerance box: |dy| <= this"),
      real_key("radius.tol_dz_mm", 0.2, 0, 10, "mm", "tolerance box: |dz| <= this"),
      real_key("radius.tol_tilt_x_deg", 0.5, 0, 10, "deg", "tolerance box: |sensor tilt about x| <= this"),
      real_key("radius.tol_tilt_y_deg", 0.5, 0, 10, "deg", "tolerance box: |sensor tilt about y| <= this"),
      real_key("radius.tol_magnet_tilt_deg", 0.5, 0, 10, "deg",
               "tolerance box: each magnet lean component (toward x, toward y) within +-this"),
      real_key("radius.tol_offset_cos_mT", 0, 0, 100, "mT", "tolerance box: |cos channel offset| <= this (0 = signal chain off)"),
      real_key("radius.tol_offset_sin_mT", 0, 0, 100, "mT", "tolerance box: |sin channel offset| <= this"),
      real_key("radius.tol_gain_mismatch", 0, 0, 0.5, "", "tolerance box: |gain mismatch| <= this (0.01 = 1 %)"),
      real_key("radius.tol_phase_error_deg", 0, 0, 45, "deg", "tolerance box: |channel phase error| <= this"),
      real_key("radius.tol_magnetization_elevation_deg", 0, 0, 45, "deg",
               "tolerance box: |magnetization elevation - magnet.magnetization_elevation_deg| <= this (analytic field only)"),
      real_key("radius.tol_temperature_min_C", 20, -273.15, 1000, "C",
               "tolerance box: temperature drawn uniform in [min, max] (both 20 = off); coefficients: "
               "magnet.br_tc_per_K, sensor.offset_*_tc_uT_per_K, mount.dz_tc_um_per_K"),
      real_key("radius.tol_temperature_max_C", 20, -273.15, 1000, "C", "tolerance box: highest temperature"),
      real_key("radius.tol_stray_mT", 0, 0, 1e4, "mT",
               "tolerance box: homogeneous stray field, magnitude uniform in [0, this], direction uniform (0 = off)"),
      real_key("radius.case_offset_mm", 0.1, 0, 10, "mm", "spectra cases: this much of each of sx, sy, dx, dy"),
      real_key("radius.case_dz_mm", 0.2, 0, 10, "mm", "spectra cases: dz = +-this (with the residual dx)"),
      real_key("radius.case_residual_dx_mm", 0.05, 0, 10, "mm", "spectra cases: residual dx of the dz cases"),
      int_key("radius.samples", 10000, 1, 100000000, "Monte Carlo samples per radius"),
      int_key("radius.seed", 1, 0, 4000000000000000000L, "Monte Carlo base seed"),
      int_key("radius.fast_steps", 360, 16, 100000, "theta samples per turn of the surrogate pipeline"),
      int_key("radius.surrogate_order", 4, 2, 4, "degree of the local field polynomials of the surrogate"),
      string_key("radius.surrogate_build", "automatic", {"automatic", "axis_aligned", "symmetry", "symmetrized"},
                 "how the surrogate's node models are built: symmetry (the exact field's rotational symmetry: 2-3 "
                 "fits; readings at 24 theta, interpolated exactly; exact field only), symmetrized (the symmetric "
                 "part of any field from 12 azimuths, read as with symmetry, plus the field's own asymmetry at the "
                 "nodes) or axis_aligned (a direct fit per node; p99 moves at the fit-residual level between them); "
                 "automatic: symmetry for a field that declares it (the exact field), symmetrized for the others "
                 "whose asymmetry at the nodes is within 1e-4 of the Bz amplitude (an FE solve), else axis_aligned"),
      int_key("radius.validate_radii", 4, 0, 1000, "radii checked against the direct pipeline"),
      int_key("radius.validate_samples", 4, 0, 100000, "MC samples checked per validation radius"),
      real_key("radius.band_rel", 0.05, 0, 10, "", "near-optimal band: total_p99 within (1 + this) of the best"),
  };
  for (auto& n : SensorNoise::keys()) k.push_back(n);
  return k;
}

RadiusScanOptions RadiusScanOptions::from_config(const Config& cfg) {
  RadiusScanOptions o;
  for (const auto& a : cfg.strings("radius.arrays")) o.arrays.push_back(ProbeArray::parse(a, "radius.arrays"));
  const double lo = cfg.real("radius.r0_min_mm"), hi = cfg.real("radius.r0_max_mm"),
               step = cfg.real("radius.r0_step_mm");
  if (!(hi >= lo))
    throw InputError("radius.r0_max_mm = " + num(hi) + " is out of range: allowed >= radius.r0_min_mm = " + num(lo));
  const long n = static_cast<long>(std::floor((hi - lo) / step + 1e-9)) + 1;
  if (n > 100000) throw InputError("radius.r0_step_mm = " + num(step) + " gives more than 100000 radii: allowed fewer");
  for (long i = 0; i < n; ++i) o.r0_mm.push_back(lo + step * static_cast<double>(i));
  o.plane_z_mm = sensing_plane_z_mm(cfg);
  o.direct_steps = static_cast<int>(cfg.integer("sensor.steps"));
  o.fast_steps = static_cast<int>(cfg.integer("radius.fast_steps"));
  o.surrogate_order = static_cast<int>(cfg.integer("radius.surrogate_order"));
  o.surrogate_build = CircleFieldModel::construction_named(cfg.str("radius.surrogate_build"));
  o.box.sx_mm = cfg.real("radius.tol_sx_mm");
  o.box.sy_mm = cfg.real("radius.tol_sy_mm");
  o.box.dx_mm = cfg.real("radius.tol_dx_mm");
  o.box.dy_mm = cfg.real("radius.tol_dy_mm");
  o.box.dz_mm = cfg.real("radius.tol_dz_mm");
  o.box.tilt_x_deg = cfg.real("radius.tol_tilt_x_deg");
  o.box.tilt_y_deg = cfg.real("radius.tol_tilt_y_deg");
  o.box.magnet_tilt_deg = cfg.real("radius.tol_magnet_tilt_deg");
  o.box.offset_cos_mT = cfg.real("radius.tol_offset_cos_mT");
  o.box.offset_sin_mT = cfg.real("radius.tol_offset_sin_mT");
  o.box.gain_mismatch = cfg.real("radius.tol_gain_mismatch");
  o.box.phase_error_deg = cfg.real("radius.tol_phase_error_deg");
  o.box.magnetization_elevation_deg = cfg.real("radius.tol_magnetization_elevation_deg");
  o.box.temperature_min_C = cfg.real("radius.tol_temperature_min_C");
  o.box.temperature_max_C = cfg.real("radius.tol_temperature_max_C");
  o.box.stray_mT = cfg.real("radius.tol_stray_mT");
  {
    // The coefficients of the drawn environment; its temperature and stray field come from the box, so a
    // configured one would be ignored: refuse it.
    Environment coeff = Environment::from_config(cfg);
    if (coeff.temperature_C != kReferenceTemperature_C || coeff.stray.active())
      throw InputError("environment.temperature_C / stray.*: the radius study draws the temperature and the stray "
                       "field from its tolerance box: allowed the defaults (set radius.tol_temperature_min_C, "
                       "tol_temperature_max_C, tol_stray_mT)");
    o.box.env_coefficients = coeff;
  }
  o.elevation_deg = cfg.real("magnet.magnetization_elevation_deg");
  o.magnet_height_mm = cfg.real("magnet.height_mm");
  o.case_offset_mm = cfg.real("radius.case_offset_mm");
  o.case_dz_mm = cfg.real("radius.case_dz_mm");
  o.case_residual_dx_mm = cfg.real("radius.case_residual_dx_mm");
  o.samples = cfg.integer("radius.samples");
  o.seed = static_cast<std::uint64_t>(cfg.integer("radius.seed"));
  o.noise = SensorNoise::from_config(cfg);
  o.validate_radii = static_cast<int>(cfg.integer("radius.validate_radii"));
  o.validate_samples = static_cast<int>(cfg.integer("radius.validate_samples"));
  o.band_rel = cfg.real("radius.band_rel");
  require_on_axis_layout(cfg, "the radius study");
  if (cfg.has("sensor.principle") && cfg.str("sensor.principle") != "bz")
    throw InputError("sensor.principle = " + cfg.str("sensor.principle") +
                     ": the radius study scans the probe radius of Hall arrays: allowed bz (compare the principles "
                     "with the sensor_principles study)");
  if (cfg.has("sensor.plate_mm") && cfg.real("sensor.plate_mm") != 0.0)
    throw InputError("sensor.plate_mm = " + num(cfg.real("sensor.plate_mm")) +
                     ": the radius study's surrogate reads Bz at points: allowed 0");
  if (cfg.has("sensor.field_min_mT")) {
    o.window.min_mT = cfg.real("sensor.field_min_mT");
    o.window.max_mT = cfg.real("sensor.field_max_mT");
    o.window.validate();
  }
  // The study's mounts and signal chains come from its tolerance box (mount.* keys are not read
  // here): refuse a configured chain rather than ignore it.
  if (!SignalChain::from_config(cfg).ideal())
    throw InputError("sensor.offset_cos_mT/offset_sin_mT/gain_mismatch/phase_error_deg: the radius study takes the "
                     "signal chain from its tolerance box: allowed 0 (set radius.tol_offset_cos_mT, tol_offset_sin_mT, "
                     "tol_gain_mismatch, tol_phase_error_deg)");
  o.validate();
  return o;
}

void RadiusScanOptions::validate() const {
  box.validate("radius.tol_");
  noise.validate();
  if (samples < 1) throw InputError("radius.samples = " + std::to_string(samples) + " is out of range: allowed >= 1");
  if (r0_mm.empty()) throw InputError("radius.r0_min_mm/r0_max_mm give no radii");
  if (arrays.empty()) throw InputError("radius.arrays is empty");
  // Every mounting case must leave the probes off the rotation axis.
  const double reach = std::max(box.max_inplane_mm(), std::max(std::sqrt(2.0) * case_offset_mm, case_residual_dx_mm));
  if (!(r0_mm.front() > reach))
    throw InputError("radius.r0_min_mm = " + num(r0_mm.front()) + " is out of range: the tolerance box moves probes by up to " +
                     num(reach) + " mm, allowed r0_min_mm > " + num(reach) + " mm");
}

std::vector<std::pair<std::string, Mount>> spectra_cases(const RadiusScanOptions& opt) {
  std::vector<std::pair<std::string, Mount>> c(6);
  c[0].first = "sx";
  c[0].second.sx_mm = opt.case_offset_mm;
  c[1].first = "sy";
  c[1].second.sy_mm = opt.case_offset_mm;
  c[2].first = "dx";
  c[2].second.dx_mm = opt.case_offset_mm;
  c[3].first = "dy";
  c[3].second.dy_mm = opt.case_offset_mm;
  c[4].first = "dz+";
  c[4].second.dz_mm = opt.case_dz_mm;
  c[4].second.dx_mm = opt.case_residual_dx_mm;
  c[5].first = "dz-";
  c[5].second.dz_mm = -opt.case_dz_mm;
  c[5].second.dx_mm = opt.case_residual_dx_mm;
  return c;
}

// ---------------------------------------------------------------------------
// Peak, recommendation

Peak find_peak(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.empty() || x.size() != y.size()) throw InputError("find_peak: x and y must be non-empty and of equal length");
  const std::size_t i = static_cast<std::size_t>(std::max_element(y.begin(), y.end()) - y.begin());
  Peak p{x[i], y[i], i == 0 || i + 1 == x.size()};
  if (p.at_edge) return p;
  // Parabola through (x[i-1], y[i-1]), (x[i], y[i]), (x[i+1], y[i+1]).
  const double x0 = x[i - 1], x1 = x[i], x2 = x[i + 1], y0 = y[i - 1], y1 = y[i], y2 = y[i + 1];
  const double d0 = (y1 - y0) / (x1 - x0), d1 = (y2 - y1) / (x2 - x1);
  const double a = (d1 - d0) / (x2 - x0);
  if (a < 0) {
    const double b = d0 - a * (x0 + x1);
    const double xv = -b / (2 * a);
    if (xv > x0 && xv < x2) {
      p.x = xv;
      p.y = y1 + d0 * (xv - x1) + a * (xv - x0) * (xv - x1);
    }
  }
  return p;
}

Recommendation recommend(const std::vector<RadiusRow>& rows, double band_rel) {
  if (rows.empty()) throw InputError("recommend: no rows");
  Recommendation r;
  r.field = rows.front().field;
  r.array = rows.front().array;
  std::size_t best = 0, best_mount = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].total_p99_pp_deg < rows[best].total_p99_pp_deg) best = i;
    if (rows[i].mc.p99 < rows[best_mount].mc.p99) best_mount = i;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.r0_best_mm = rows[best].r0_mm;
  r.total_p99_best_deg = rows[best].total_p99_pp_deg;
  r.mc_p99_best_deg = rows[best].mc.p99;
  r.noise_pp_best_deg = rows[best].noise.pp_deg;
  r.total_p99_left_deg = best > 0 ? rows[best - 1].total_p99_pp_deg : nan;
  r.total_p99_right_deg = best + 1 < rows.size() ? rows[best + 1].total_p99_pp_deg : nan;
  r.r0_best_mount_only_mm = rows[best_mount].r0_mm;
  r.at_scan_edge = best == 0 || best + 1 == rows.size();
  const double limit = (1.0 + band_rel) * r.total_p99_best_deg;
  std::size_t lo = best, hi = best;
  while (lo > 0 && rows[lo - 1].total_p99_pp_deg <= limit) --lo;
  while (hi + 1 < rows.size() && rows[hi + 1].total_p99_pp_deg <= limit) ++hi;
  r.band_lo_mm = rows[lo].r0_mm;
  r.band_hi_mm = rows[hi].r0_mm;
  return r;
}

std::pair<double, double> model_reach_mm(const RadiusScanOptions& opt, double r0_mm) {
  double xy = std::max(opt.box.max_inplane_mm(), std::max(opt.case_offset_mm, std::hypot(opt.case_residual_dx_mm, 0.0)));
  double z = std::max(opt.box.dz_mm, opt.case_dz_mm);
  if (opt.box.has_environment()) {  // the air gap's drift over the box's temperatures
    const double dT = std::max(std::abs(opt.box.temperature_min_C - kReferenceTemperature_C),
                               std::abs(opt.box.temperature_max_C - kReferenceTemperature_C));
    z = std::max(z, opt.box.dz_mm + 1e-3 * std::abs(opt.box.env_coefficients.dz_tc_um_per_K) * dT);
  }
  if (opt.box.has_tilts()) {
    // Sensor tilt a, b: a probe at radius r0 rises or sinks by up to r0 (sin a + sin b) and moves in
    // plane by r0 (2 - cos a - cos b). Magnet lean g (up to sqrt(2) x the half-width): a point at height
    // H above the pivot (H = z_s + dz + L/2) moves in plane by H sin g and vertically by
    // (r0 + in-plane reach) sin g + H (1 - cos g). 5 % margin.
    const double a = deg_to_rad(opt.box.tilt_x_deg), b = deg_to_rad(opt.box.tilt_y_deg);
    const double g = deg_to_rad(std::sqrt(2.0) * opt.box.magnet_tilt_deg);
    const double H = opt.plane_z_mm + z + 0.5 * opt.magnet_height_mm;
    const double xy0 = xy;
    xy += 1.05 * (r0_mm * (2.0 - std::cos(a) - std::cos(b)) + H * std::sin(g));
    z += 1.05 * (r0_mm * (std::sin(a) + std::sin(b)) + (r0_mm + xy0) * std::sin(g) + H * (1.0 - std::cos(g)));
  }
  return {xy, z};
}

// ---------------------------------------------------------------------------
// The scan

void check_field_serves_box(const FieldSource& field, const std::string& spec, const RadiusScanOptions& opt) {
  if (!opt.box.has_elevation()) return;
  const double tol = opt.box.magnetization_elevation_deg;
  if (!field.exact_magnet())
    throw InputError("radius.tol_magnetization_elevation_deg = " + num(tol) + ": field '" + spec +
                     "' has one fixed magnetization (only the analytic field can vary its elevation): allowed 0");
  if (!(std::abs(opt.elevation_deg) + tol <= 90.0))
    throw InputError("radius.tol_magnetization_elevation_deg = " + num(tol) + " is out of range with "
                     "magnet.magnetization_elevation_deg = " + num(opt.elevation_deg) + ": allowed <= " +
                     num(90.0 - std::abs(opt.elevation_deg)));
}

void check_distinct_field_kinds(const std::vector<std::pair<std::string, FieldSourcePtr>>& fields) {
  for (std::size_t i = 0; i < fields.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (fields[i].second->name() == fields[j].second->name())
        throw InputError("radius.fields: '" + fields[j].first + "' and '" + fields[i].first + "' are both " +
                         fields[i].second->name() + " fields, whose rows would merge: allowed one field of each " +
                         "kind (analytic, linear, fem, grid, table) per run");
}

namespace {
// The field models of one radius: the field itself, or (elevation in the box) its diametric and
// axial parts, and the pipeline over them.
struct RadiusModels {
  std::unique_ptr<AnalyticField> diametric_field, axial_field;
  std::unique_ptr<CircleFieldModel> model, axial;
  std::unique_ptr<FastPipeline> fast;
  double amplitude_T = 0;  // Bz amplitude of the configured field on the circle
  double fit_residual_T = 0;
  double node_residual_rel = 0;  // symmetrized models: the asymmetry at the nodes over the Bz amplitude

  RadiusModels(const FieldSource& field, const RadiusScanOptions& opt, double r0, const std::vector<ProbeArray>& arrays) {
    const auto [reach_xy, reach_z] = model_reach_mm(opt, r0);
    const bool tilts = opt.box.has_tilts();
    const CircleFieldModel::Construction how = opt.surrogate_build;
    if (how == CircleFieldModel::Construction::symmetry && !field.axisymmetric_parts())
      throw InputError("radius.surrogate_build = symmetry needs the exact field: field " + field.name() +
                       " declares no rotational symmetry: allowed axis_aligned or automatic");
    if (!opt.box.has_elevation()) {
      model = std::make_unique<CircleFieldModel>(field, r0, opt.plane_z_mm, opt.fast_steps, reach_xy, reach_z,
                                                 opt.surrogate_order, tilts, how);
      fast = std::make_unique<FastPipeline>(*model, arrays, opt.magnet_height_mm);
      amplitude_T = model->amplitude_T();
      fit_residual_T = model->fit_residual_T();
      node_residual_rel = model->node_residual_max_T() / model->amplitude_T();
      return;
    }
    // B(al) = cos(al) B_diametric + sin(al) B_axial (check_field_serves_box: the exact field).
    const Magnet& mag = *field.exact_magnet();
    Magnet md = mag, ma = mag;
    md.magnetization_elevation_deg = 0;
    ma.magnetization_elevation_deg = 90;
    diametric_field = std::make_unique<AnalyticField>(md);
    axial_field = std::make_unique<AnalyticField>(ma);
    model = std::make_unique<CircleFieldModel>(*diametric_field, r0, opt.plane_z_mm, opt.fast_steps, reach_xy, reach_z,
                                               opt.surrogate_order, tilts, how);
    axial = std::make_unique<CircleFieldModel>(*axial_field, r0, opt.plane_z_mm, opt.fast_steps, reach_xy, reach_z,
                                               opt.surrogate_order, tilts, how);
    fast = std::make_unique<FastPipeline>(*model, arrays, opt.magnet_height_mm, axial.get(), opt.elevation_deg);
    // The axial part is symmetric about the axis: no first angular harmonic.
    amplitude_T = std::cos(deg_to_rad(opt.elevation_deg)) * model->amplitude_T();
    fit_residual_T = std::max(model->fit_residual_T(), axial->fit_residual_T());
  }
};
}  // namespace

namespace {

// Validation radii: spread evenly over the scan (indices round(i*(n-1)/(k-1))).
std::vector<std::size_t> validation_radii(const RadiusScanOptions& opt) {
  std::vector<std::size_t> vidx;
  const std::size_t nr = opt.r0_mm.size();
  for (int i = 0; i < opt.validate_radii; ++i) {
    const std::size_t j = opt.validate_radii == 1
                              ? nr / 2
                              : static_cast<std::size_t>(std::lround(static_cast<double>(i) * (nr - 1) / (opt.validate_radii - 1)));
    if (std::find(vidx.begin(), vidx.end(), j) == vidx.end()) vidx.push_back(j);
  }
  return vidx;
}

// Spectra cases through the surrogate at one radius.
void push_spectra(const FieldSource& field, const RadiusScanOptions& opt, const std::vector<std::pair<std::string, Mount>>& cases, const FastPipeline& fast, double r0,
                  RadiusScanResult& out) {
  const std::size_t A = opt.arrays.size();
  for (const auto& [label, mount] : cases) {
    std::vector<Eigen::VectorXd> eps;
    fast.eps(mount, eps);
    for (std::size_t a = 0; a < A; ++a) {
      SpectrumRow row;
      row.field = field.name();
      row.array = opt.arrays[a].name;
      row.r0_mm = r0;
      row.mount = mount;
      row.spectrum = spectrum_of(eps[a]);
      row.extra = {{"case", label}};
      out.spectra.push_back(std::move(row));
    }
  }
}

// One array's row at one radius: worst corner and Monte Carlo statistics (inside the field window if one is set),
// noise and totals.
RadiusRow radius_row(const FieldSource& field, const RadiusScanOptions& opt, const RadiusModels& models, double r0,
                     std::size_t a, const std::vector<double>& ideal_pp, const std::vector<ToleranceCase>& corners,
                     const Eigen::MatrixXd& corner_pp, const Eigen::MatrixXd& mc_pp, bool windowed) {
  const std::size_t A = opt.arrays.size();
  RadiusRow row;
  row.field = field.name();
  row.array = opt.arrays[a].name;
  row.r0_mm = r0;
  row.bz_amplitude_T = models.amplitude_T;
  row.ideal_pp_deg = ideal_pp[a];
  if (!windowed) {
    const WorstCase w = worst_case(corner_pp, static_cast<int>(a));
    row.worst_pp_deg = w.value;
    row.worst_corner = corner_text(corners[w.row]);
    row.mc = sample_stats(mc_pp.col(static_cast<Eigen::Index>(a)));
  } else {
    const auto ia = static_cast<Eigen::Index>(a), iA = static_cast<Eigen::Index>(A);
    auto inside = [&](const Eigen::MatrixXd& v, Eigen::Index i) {
      return opt.window.contains(v(i, iA + ia), v(i, 2 * iA + ia));
    };
    row.worst_pp_deg = 0;
    row.worst_corner = "none in the field window";
    bool any = false;
    for (Eigen::Index i = 0; i < corner_pp.rows(); ++i) {
      if (!inside(corner_pp, i)) {
        ++row.corners_out_of_window;
        continue;
      }
      if (!any || clearly_larger(corner_pp(i, ia), row.worst_pp_deg)) {
        row.worst_pp_deg = corner_pp(i, ia);
        row.worst_corner = corner_text(corners[static_cast<std::size_t>(i)]);
      }
      any = true;
    }
    std::vector<double> kept;
    row.field_min_mT = mc_pp.col(iA + ia).minCoeff();
    row.field_max_mT = mc_pp.col(2 * iA + ia).maxCoeff();
    for (Eigen::Index i = 0; i < mc_pp.rows(); ++i) {
      if (inside(mc_pp, i)) kept.push_back(mc_pp(i, ia));
      else ++row.mc_out_of_window;
    }
    // No sample in the window: the statistics are +inf (this radius fails), n = 0.
    if (kept.empty()) {
      const double inf = std::numeric_limits<double>::infinity();
      row.mc = SampleStats{0, inf, inf, inf, inf};
    } else {
      row.mc = sample_stats(Eigen::Map<const Eigen::VectorXd>(kept.data(), static_cast<Eigen::Index>(kept.size())));
    }
  }
  row.noise = angle_noise(opt.arrays[a], models.amplitude_T, opt.noise);
  row.total_p99_pp_deg = row.mc.p99 + row.noise.pp_deg;
  row.total_worst_pp_deg = row.worst_pp_deg + row.noise.pp_deg;
  return row;
}

// Validation against the direct pipeline at one radius.
void validate_at(const FieldSource& field, const RadiusScanOptions& opt, const std::vector<std::pair<std::string, Mount>>& cases, const std::vector<ToleranceCase>& corners,
                 const std::vector<ToleranceCase>& samples, const Eigen::MatrixXd& corner_pp, const FastPipeline& fast, double r0,
                 RadiusScanResult& out) {
  const std::size_t A = opt.arrays.size();
  std::vector<std::pair<std::string, ToleranceCase>> vcases;
  for (const auto& [label, mount] : cases) vcases.emplace_back(label, ToleranceCase{mount, SignalChain{}, 0.0});
  for (std::size_t a = 0; a < A; ++a) {
    const WorstCase w = worst_case(corner_pp, static_cast<int>(a));
    vcases.emplace_back("worst corner " + opt.arrays[a].name, corners[w.row]);
  }
  for (int i = 0; i < opt.validate_samples && i < static_cast<int>(samples.size()); ++i)
    vcases.emplace_back("mc sample " + std::to_string(i), samples[static_cast<std::size_t>(i)]);
  for (const auto& [label, vc] : vcases) {
    const Mount& mount = vc.mount;
    std::vector<Eigen::VectorXd> eps;
    fast.eps(vc, eps);
    // The direct pipeline on the case's own field (elevation) and signal chain.
    std::unique_ptr<AnalyticField> elevated;
    if (vc.elevation_deg != 0) {
      Magnet mag = *field.exact_magnet();
      mag.magnetization_elevation_deg = opt.elevation_deg + vc.elevation_deg;
      elevated = std::make_unique<AnalyticField>(mag);
    }
    const FieldSource& case_field = elevated ? *elevated : field;
    for (std::size_t a = 0; a < A; ++a) {
      ProbeSetup setup;
      setup.array = opt.arrays[a];
      setup.r0_mm = r0;
      setup.plane_z_mm = opt.plane_z_mm;
      setup.steps = opt.direct_steps;
      setup.magnet_height_mm = opt.magnet_height_mm;
      setup.chain = vc.chain;
      const Spectrum direct = error_spectrum(case_field, setup, mount);
      setup.steps = opt.fast_steps;
      const Spectrum coarse = error_spectrum(case_field, setup, mount);
      const Spectrum sur = spectrum_of(eps[a]);
      ValidationRow v;
      v.field = field.name();
      v.array = opt.arrays[a].name;
      v.label = label;
      v.r0_mm = r0;
      v.mount = mount;
      v.pp_direct_deg = direct.pp_deg;
      v.pp_direct_coarse_deg = coarse.pp_deg;
      v.pp_surrogate_deg = sur.pp_deg;
      double d = std::abs(sur.a0_deg - direct.a0_deg);
      for (int n = 1; n <= kHarmonics; ++n)
        d = std::max({d, std::abs(sur.a_deg[n] - direct.a_deg[n]), std::abs(sur.b_deg[n] - direct.b_deg[n])});
      v.max_coef_diff_deg = d;
      out.validation.push_back(v);
    }
  }
}

// Bz peak and recommendations.
void recommend_arrays(const RadiusScanOptions& opt, const std::vector<std::vector<RadiusRow>>& rows, FieldScanInfo& info,
                      RadiusScanResult& out) {
  const std::size_t A = opt.arrays.size();
  std::vector<double> amp;
  for (const auto& r : rows[0]) amp.push_back(r.bz_amplitude_T);
  const Peak pk = find_peak(opt.r0_mm, amp);
  info.r_bz_peak_mm = pk.x;
  info.bz_peak_T = pk.y;
  info.peak_at_edge = pk.at_edge;
  for (std::size_t a = 0; a < A; ++a) {
    out.recommendations.push_back(recommend(rows[a], opt.band_rel));
    out.rows.insert(out.rows.end(), rows[a].begin(), rows[a].end());
  }
}

// Error budget at each array's recommended r0: the same MC samples with one group of the box at a time.
void error_budget(const FieldSource& field, const RadiusScanOptions& opt, const std::vector<ToleranceCase>& samples, RadiusScanResult& out) {
  const std::size_t A = opt.arrays.size();
  for (std::size_t a = 0; a < A; ++a) {
    const Recommendation& rec = out.recommendations[out.recommendations.size() - A + a];
    const RadiusModels models(field, opt, rec.r0_best_mm, {opt.arrays[a]});
    const FastPipeline& fast = *models.fast;
    auto pp_of = [&](std::size_t, const ToleranceCase& c, double* o) { fast.pp(c, o); };
    const Eigen::MatrixXd all = evaluate_cases(samples, 1, pp_of);
    const double p99_all = sample_stats(all.col(0)).p99;
    for (const auto& group : ToleranceBox::groups()) {
      const ToleranceBox only = opt.box.only(group);
      if (only.empty()) continue;  // group not in the box
      const Eigen::MatrixXd pp = evaluate_cases(monte_carlo_cases(only, opt.samples, opt.seed), 1, pp_of);
      BudgetRow b;
      b.field = field.name();
      b.array = opt.arrays[a].name;
      b.r0_mm = rec.r0_best_mm;
      b.group = group;
      b.p99_only_deg = sample_stats(pp.col(0)).p99;
      b.p99_all_deg = p99_all;
      b.share = p99_all > 0 ? b.p99_only_deg / p99_all : 0.0;
      out.budget.push_back(b);
    }
  }
}

}  // namespace

void run_radius_scan(const FieldSource& field, const std::string& spec, const RadiusScanOptions& opt,
                     RadiusScanResult& out) {
  opt.validate();
  check_field_serves_box(field, spec, opt);
  const std::size_t A = opt.arrays.size();
  const auto cases = spectra_cases(opt);
  const std::vector<ToleranceCase> corners = opt.box.case_corners();
  const std::vector<ToleranceCase> samples = monte_carlo_cases(opt.box, opt.samples, opt.seed);

  const std::vector<std::size_t> vidx = validation_radii(opt);
  const std::size_t nr = opt.r0_mm.size();

  FieldScanInfo info;
  info.field = field.name();
  info.spec = spec;
  std::vector<std::vector<RadiusRow>> rows(A);  // per array, over r0
  for (std::size_t ir = 0; ir < nr; ++ir) {
    const double r0 = opt.r0_mm[ir];
    // 1. Local field models on the probe circle.
    auto t0 = std::chrono::steady_clock::now();
    // The displacements the local models must serve: the box (tilts included) and the spectra cases.
    const RadiusModels models(field, opt, r0, opt.arrays);
    const FastPipeline& fast = *models.fast;
    info.max_fit_residual_T = std::max(info.max_fit_residual_T, models.fit_residual_T);
    info.max_node_residual_rel = std::max(info.max_node_residual_rel, models.node_residual_rel);
    const std::string build = CircleFieldModel::construction_name(models.model->construction());
    if (info.builds.empty() || info.builds.back().first != build) info.builds.emplace_back(build, 0);
    ++info.builds.back().second;
    info.t_models_s += seconds_since(t0);

    // 2. Spectra cases, corners and Monte Carlo samples through the surrogate.
    t0 = std::chrono::steady_clock::now();
    push_spectra(field, opt, cases, fast, r0, out);
    std::vector<double> ideal_pp(A);
    fast.pp(Mount{}, ideal_pp.data());
    auto pp_of = [&](std::size_t, const ToleranceCase& c, double* o) { fast.pp(c, o); };
    // With a field window: pp, field min, field max per array (columns a, A + a, 2A + a).
    auto pp_field_of = [&](std::size_t, const ToleranceCase& c, double* o) { fast.pp_field(c, o, o + A, o + 2 * A); };
    const bool windowed = opt.window.active();
    const int n_out = static_cast<int>(windowed ? 3 * A : A);
    const ToleranceCaseFunction case_fn =
        windowed ? ToleranceCaseFunction(pp_field_of) : ToleranceCaseFunction(pp_of);
    const Eigen::MatrixXd corner_pp = evaluate_cases(corners, n_out, case_fn);
    const Eigen::MatrixXd mc_pp = evaluate_cases(samples, n_out, case_fn);
    for (std::size_t a = 0; a < A; ++a)
      rows[a].push_back(radius_row(field, opt, models, r0, a, ideal_pp, corners, corner_pp, mc_pp, windowed));
    info.t_cases_s += seconds_since(t0);

    // 3. Validation against the direct pipeline at a few radii.
    if (std::find(vidx.begin(), vidx.end(), ir) == vidx.end()) continue;
    t0 = std::chrono::steady_clock::now();
    validate_at(field, opt, cases, corners, samples, corner_pp, fast, r0, out);
    info.t_validate_s += seconds_since(t0);
  }

  // 4. Bz peak and recommendations.
  recommend_arrays(opt, rows, info, out);

  // 5. Error budget at each array's recommended r0: the same MC samples with one group of the box at a time.
  error_budget(field, opt, samples, out);
  out.fields.push_back(info);
}

std::vector<std::string> radius_field_specs(const Config& cfg, std::vector<std::string>& notes,
                                            const SolveMismatch& solve_mismatch) {
  std::vector<std::string> specs = cfg.strings("radius.fields");
  const std::string dir = cfg.str("radius.fem_dir");
  const bool has_fem = std::any_of(specs.begin(), specs.end(), [](const std::string& s) { return s.rfind("fem:", 0) == 0; });
  // A listed fem:DIR must be a solve of the configured magnet: it is compared with the analytic field.
  for (const auto& s : specs)
    if (s.rfind("fem:", 0) == 0)
      if (const std::string why = solve_mismatch(s.substr(4)); !why.empty())
        throw InputError("radius.fields: '" + s + "' " + why);
  if (dir.empty()) {
    notes.push_back("radius.fem_dir is empty: no FEM field added automatically.");
  } else if (has_fem) {
    notes.push_back("radius.fields lists a fem: field; radius.fem_dir not used.");
  } else if (const std::string why = std::filesystem::exists(std::filesystem::path(dir) / "solve.json")
                                         ? solve_mismatch(dir)
                                         : std::string();
             !why.empty()) {
    notes.push_back("The solved field in " + dir + " " + why + "; FEM field not run.");
  } else if (std::filesystem::exists(std::filesystem::path(dir) / "solve.json")) {
    specs.push_back("fem:" + dir);
    notes.push_back("Solved field found in " + dir + " (solve.json): added fem:" + dir + ".");
  } else {
    notes.push_back("No solved field in " + dir + " (no solve.json): FEM field not run; run solve_field first.");
  }
  return specs;
}

}  // namespace magenc
