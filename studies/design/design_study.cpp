#include "studies/design/design_study.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>

#include <omp.h>

#include "analysis/radius_scan.hpp"
#include "probe/sensor.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "probe/environment.hpp"

namespace magenc {

namespace {
constexpr std::uint64_t kDriftStream = 0x9E3779B97F4A7C15ULL;

std::vector<std::string> material_names() {
  std::vector<std::string> n;
  for (const auto& m : magnet_materials()) n.push_back(m.name);
  return n;
}

}  // namespace

std::vector<KeySpec> DesignOptions::keys() {
  const DesignOptions d;
  std::vector<KeySpec> k = {
      string_list_key("design.materials", d.space.materials, material_names(),
                      "magnet materials (their Br temperature coefficient); one Br per material in design.br_T"),
      real_list_key("design.br_T", d.space.br_T, 0, 3, "T", "remanence at 20 C of each material of design.materials",
                    true),
      real_list_key("design.magnet_radius_mm", d.space.magnet_radius_mm, 0, 100, "mm", "magnet radii R to try", true),
      real_list_key("design.magnet_height_mm", d.space.magnet_height_mm, 0, 100, "mm", "magnet heights L to try",
                    true),
      real_list_key("design.magnet_inner_radius_mm", d.space.magnet_inner_radius_mm, 0, 100, "mm",
                    "ring magnets' inner radii Ri to try (0: a solid cylinder; every Ri < every design.magnet_radius_mm)"),
      real_list_key("design.gap_mm", d.space.gap_mm, 0, 100, "mm",
                    "air gaps to try: sensing plane height above the magnet's top face", true),
      real_list_key("design.r0_mm", d.space.r0_mm, 0, 100, "mm", "probe radii r0 to try (every sensor)", true),
      string_list_key("design.sensors", {"two", "diff4", "ring:8"}, {},
                      "Bz arrays to try: two, diff4, ring:N (3 <= N <= 1024); at design.r0_mm and design.gap_mm "
                      "(around a ring's bore: the bore array's circle and plane)",
                      0),
      string_list_key("design.side_principles", {}, {"inplane", "xmr"},
                      "side-shaft readers to try (one spot beside the magnet, direction, zero and gain trim automatic "
                      "at the nominal mount) at design.side_radius_mm and design.side_height_mm; [] none",
                      0),
      real_list_key("design.side_radius_mm", d.space.side_radius_mm, 0, 1000, "mm",
                    "side-shaft read radii to try: the die centre at [radius, 0] (every radius clear of the magnet "
                    "by the tolerance box's and drift's reach where the plane crosses it)",
                    true),
      real_list_key("design.side_height_mm", d.space.side_height_mm, -1000, 1000, "mm",
                    "side-shaft die plane heights to try, above the magnet's mid-plane (0: the mid-plane)"),
      real_key("design.target_p99_deg", d.req.target_p99_deg, 0, 180, "deg",
               "requirement: p99 of the peak-to-peak angle error (calibrated unless design.calibration = none)", true),
      real_key("design.temperature_min_C", d.req.temperature_min_C, -273.15, 1000, "C",
               "requirement: lowest operating temperature (field window checked here; run states drawn in the range)"),
      real_key("design.temperature_max_C", d.req.temperature_max_C, -273.15, 1000, "C",
               "requirement: highest operating temperature"),
      real_key("design.stray_mT", d.req.stray_mT, 0, 1e4, "mT",
               "requirement: largest homogeneous stray field (run states: magnitude uniform in [0, this], any direction)"),
      string_key("design.calibration", "none", {},
                 "calibration at the factory state: none, harmonics:N, lut:K (ogp needs channels: not in the fast path)"),
      real_key("design.drift_inplane_mm", d.drift_inplane_mm, 0, 10, "mm",
               "drift after calibration: half-width of each of sx, sy, dx, dy added at the run state"),
      real_key("design.drift_dz_mm", d.drift_dz_mm, 0, 10, "mm", "drift after calibration: half-width of the air gap"),
      int_key("design.samples", d.samples, 1, 10000000, "Monte Carlo samples per design"),
      int_key("design.seed", static_cast<long>(d.seed), 0, 2147483647, "Monte Carlo base seed"),
      bool_key("design.seed_per_design", d.seed_per_design,
               "true: each design's samples come from the base seed and its index; false: every design uses the base "
               "seed's samples (common random numbers)"),
      int_key("design.fast_steps", d.fast_steps, 8, 100000, "theta samples per turn of the fast pipeline"),
      int_key("design.surrogate_order", d.surrogate_order, 2, 4, "polynomial degree of the local field models"),
      string_key("design.surrogate_build", "automatic", {"automatic", "axis_aligned", "symmetry"},
                 "how the local field models are built: symmetry (the exact field's rotational symmetry: 2-3 fits; "
                 "readings at 24 theta, interpolated exactly) or axis_aligned (a direct fit per node; p99 moves at the "
                 "fit-residual level between the two); automatic: symmetry (the design study's field is the exact "
                 "one), as radius.surrogate_build"),
  };
  ToleranceBox box;  // radius study's defaults
  for (auto& t : mount_box_keys(box, true, "mounting tolerance")) k.push_back(t);
  return k;
}

DesignOptions DesignOptions::from_config(const Config& cfg) {
  DesignOptions o;
  o.speed = SpeedChain::from_config(cfg);
  o.space.materials = cfg.strings("design.materials");
  o.space.br_T = cfg.reals("design.br_T");
  o.space.magnet_radius_mm = cfg.reals("design.magnet_radius_mm");
  o.space.magnet_height_mm = cfg.reals("design.magnet_height_mm");
  o.space.gap_mm = cfg.reals("design.gap_mm");
  o.space.magnet_inner_radius_mm = cfg.reals("design.magnet_inner_radius_mm");
  o.space.r0_mm = cfg.reals("design.r0_mm");
  for (const auto& s : cfg.strings("design.sensors")) {
    const ProbeArray a = ProbeArray::parse(s, "design.sensors");
    if (a.is_point())
      throw InputError("design.sensors: '" + s +
                       "' is a one-spot principle, not in the fast path: allowed two, diff4, ring:N");
    o.space.sensors.push_back(a);
  }
  for (const auto& s : cfg.strings("design.side_principles"))
    o.space.side_principles.push_back(parse_principle(s, "design.side_principles"));
  o.space.side_radius_mm = cfg.reals("design.side_radius_mm");
  o.space.side_height_mm = cfg.reals("design.side_height_mm");
  o.req.target_p99_deg = cfg.real("design.target_p99_deg");
  o.req.temperature_min_C = cfg.real("design.temperature_min_C");
  o.req.temperature_max_C = cfg.real("design.temperature_max_C");
  o.req.stray_mT = cfg.real("design.stray_mT");
  o.req.calibration = CalibrationMethod::parse(cfg.str("design.calibration"), "design.calibration");
  if (cfg.has("sensor.field_min_mT")) {
    o.req.window.min_mT = cfg.real("sensor.field_min_mT");
    o.req.window.max_mT = cfg.real("sensor.field_max_mT");
    o.req.window.validate();
  }
  if (cfg.has("sensor.principle") && cfg.str("sensor.principle") != "bz")
    throw InputError("sensor.principle = " + cfg.str("sensor.principle") +
                     ": the design study searches Bz arrays (design.sensors): allowed bz");
  o.box = mount_box_from_config(cfg, true);
  require_on_axis_layout(cfg, "the design study");
  o.drift_inplane_mm = cfg.real("design.drift_inplane_mm");
  o.drift_dz_mm = cfg.real("design.drift_dz_mm");
  o.samples = cfg.integer("design.samples");
  o.seed = static_cast<std::uint64_t>(cfg.integer("design.seed"));
  o.seed_per_design = cfg.flag("design.seed_per_design");
  o.fast_steps = static_cast<int>(cfg.integer("design.fast_steps"));
  o.surrogate_order = static_cast<int>(cfg.integer("design.surrogate_order"));
  o.surrogate_build = CircleFieldModel::construction_named(cfg.str("design.surrogate_build"));
  o.validate();
  return o;
}

void DesignOptions::validate() const {
  if (space.materials.empty()) throw InputError("design.materials is empty: allowed one or more materials");
  if (space.br_T.size() != space.materials.size())
    throw InputError("design.br_T has " + std::to_string(space.br_T.size()) + " values: allowed one per material of "
                     "design.materials (" + std::to_string(space.materials.size()) + ")");
  for (const auto& m : space.materials) magnet_material(m);
  auto nonempty = [](const std::vector<double>& v, const char* key) {
    if (v.empty()) throw InputError(std::string(key) + " is empty: allowed one or more values");
  };
  nonempty(space.magnet_radius_mm, "design.magnet_radius_mm");
  nonempty(space.magnet_height_mm, "design.magnet_height_mm");
  nonempty(space.gap_mm, "design.gap_mm");
  nonempty(space.magnet_inner_radius_mm, "design.magnet_inner_radius_mm");
  {
    const double ri = *std::max_element(space.magnet_inner_radius_mm.begin(), space.magnet_inner_radius_mm.end());
    const double r = *std::min_element(space.magnet_radius_mm.begin(), space.magnet_radius_mm.end());
    if (!(ri < r))
      throw InputError("design.magnet_inner_radius_mm has " + num(ri) + " mm: allowed every value below every "
                       "design.magnet_radius_mm (smallest " + num(r) + " mm)");
  }
  nonempty(space.r0_mm, "design.r0_mm");
  if (space.sensors.empty() && space.side_principles.empty())
    throw InputError("design.sensors is empty and so is design.side_principles: allowed one or more of two, diff4, "
                     "ring:N (or a side-shaft principle)");
  validate_side();
  for (const auto& a : space.sensors)
    if (a.name == "point")
      throw InputError("design.sensors: 'point' is a one-spot principle, not in the fast path: allowed two, diff4, "
                       "ring:N");
  if (req.temperature_min_C > req.temperature_max_C)
    throw InputError("design.temperature_min_C = " + num(req.temperature_min_C) +
                     " is out of range: allowed <= design.temperature_max_C = " + num(req.temperature_max_C));
  if (req.calibration.kind == CalibrationKind::Ogp)
    throw InputError("design.calibration = ogp needs the raw channels, not in the fast path: allowed none, "
                     "harmonics:N, lut:K");
  if (req.calibration.kind == CalibrationKind::Harmonics && 2 * req.calibration.order + 1 > fast_steps)
    throw InputError("design.calibration = " + req.calibration.name() + " needs at least " +
                     std::to_string(2 * req.calibration.order + 1) + " theta samples: allowed design.fast_steps >= that");
  box.validate("tol.");
  const double reach = box.max_inplane_mm() + 4 * drift_inplane_mm;
  for (double r0 : space.r0_mm)
    if (!(r0 > reach))
      throw InputError("design.r0_mm = " + num(r0) + " is out of range: the tolerance box and drift move probes by up to " +
                       num(reach) + " mm, allowed > " + num(reach) + " mm");
  for (const auto& a : space.sensors)
    for (double b : a.angle_deg) {
      const double k = b * fast_steps / 360.0;
      if (std::abs(k - std::round(k)) > 1e-9)
        throw InputError("design.fast_steps = " + std::to_string(fast_steps) + " does not place sensor " + a.name +
                         "'s probes on the theta grid: allowed a multiple of its probe count");
    }
}

void DesignOptions::validate_side() const {
  if (space.side_principles.empty()) return;
  auto nonempty = [](const std::vector<double>& v, const char* key) {
    if (v.empty()) throw InputError(std::string(key) + " is empty: allowed one or more values with design.side_principles");
  };
  nonempty(space.side_radius_mm, "design.side_radius_mm");
  nonempty(space.side_height_mm, "design.side_height_mm");
  if (fast_steps < 16)
    throw InputError("design.fast_steps = " + std::to_string(fast_steps) +
                     " is out of range with design.side_principles: allowed >= 16 (the direct pipeline's turn)");
  for (SensorPrinciple p : space.side_principles)
    if (p != SensorPrinciple::InPlane && p != SensorPrinciple::Xmr)
      throw InputError("design.side_principles: '" + principle_name(p) + "' is not a side-shaft reader: allowed inplane, xmr");
  // The spot's reach: the box's and the drift's in-plane offsets, the magnet lean's sway of the magnet (its
  // height and radius times the sine of the largest lean), the air gap's offset along z.
  const double lean = std::sin(std::sqrt(2.0) * box.magnet_tilt_deg * kPi / 180.0);
  for (double R : space.magnet_radius_mm)
    for (double L : space.magnet_height_mm)
      for (double Ri : space.magnet_inner_radius_mm)
        for (double rs : space.side_radius_mm)
          for (double h : space.side_height_mm) {
            const double reach = box.max_inplane_mm() + 4 * drift_inplane_mm + L * lean;
            const double reach_z = box.dz_mm + drift_dz_mm + R * lean;
            if (std::abs(h) < 0.5 * L + reach_z && rs + reach > Ri && rs - reach < R)
              throw InputError("design.side_radius_mm = " + num(rs) + " with design.side_height_mm = " + num(h) +
                               " is out of range: the tolerance box and drift move the chip by up to " + num(reach) +
                               " mm into the magnet (R " + num(R) + ", Ri " + num(Ri) + ", L " + num(L) +
                               " mm): allowed > " + num(R + reach) + " mm, or a plane beyond +-" +
                               num(0.5 * L + reach_z) + " mm");
          }
}

ToleranceBox DesignOptions::run_box(double br_tc_per_K) const {
  ToleranceBox d;
  d.sx_mm = d.sy_mm = d.dx_mm = d.dy_mm = drift_inplane_mm;
  d.dz_mm = drift_dz_mm;
  d.temperature_min_C = req.temperature_min_C;
  d.temperature_max_C = req.temperature_max_C;
  d.stray_mT = req.stray_mT;
  d.env_coefficients.br_tc_per_K = br_tc_per_K;
  return d;
}

double Design::volume_mm3() const {
  return kPi * (magnet_radius_mm * magnet_radius_mm - magnet_inner_radius_mm * magnet_inner_radius_mm) * magnet_height_mm;
}

std::string DesignSpace::sensor_name(std::size_t sensor) const {
  return is_side(sensor) ? "side " + principle_name(side_principles[sensor - sensors.size()]) : sensors[sensor].name;
}

Design design_at(const DesignSpace& s, std::size_t index) {
  if (index >= s.size()) throw InputError("design index " + std::to_string(index) + " is out of range: allowed < " +
                                          std::to_string(s.size()));
  Design d;
  d.index = index;
  std::size_t i = index;
  std::size_t reader = i % s.readers();
  i /= s.readers();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (reader < s.bz_readers()) {
    d.sensor = reader % s.sensors.size();
    reader /= s.sensors.size();
    d.r0_mm = s.r0_mm[reader % s.r0_mm.size()];
    reader /= s.r0_mm.size();
    d.gap_mm = s.gap_mm[reader];
    d.side_radius_mm = d.side_height_mm = nan;
  } else {
    reader -= s.bz_readers();
    d.side = true;
    d.sensor = s.sensors.size() + reader % s.side_principles.size();
    reader /= s.side_principles.size();
    d.side_height_mm = s.side_height_mm[reader % s.side_height_mm.size()];
    reader /= s.side_height_mm.size();
    d.side_radius_mm = s.side_radius_mm[reader];
    d.gap_mm = d.r0_mm = nan;
  }
  d.magnet_height_mm = s.magnet_height_mm[i % s.magnet_height_mm.size()];
  i /= s.magnet_height_mm.size();
  d.magnet_inner_radius_mm = s.magnet_inner_radius_mm[i % s.magnet_inner_radius_mm.size()];
  i /= s.magnet_inner_radius_mm.size();
  d.magnet_radius_mm = s.magnet_radius_mm[i % s.magnet_radius_mm.size()];
  i /= s.magnet_radius_mm.size();
  d.material = s.materials[i];
  d.br_T = s.br_T[i];
  d.br_tc_per_K = magnet_material(d.material).br_tc_per_K;
  return d;
}

void DesignResult::to(double* v) const {
  const double a[kValues] = {p99_uncal_deg, p99_cal_deg, p50_uncal_deg, p50_cal_deg, field_min_mT,
                             field_max_mT,  field_lo_mT, field_hi_mT,   margin_mT,   bz_amplitude_mT};
  std::copy(a, a + kValues, v);
}

DesignResult DesignResult::from(const double* v) {
  DesignResult r;
  r.p99_uncal_deg = v[0];
  r.p99_cal_deg = v[1];
  r.p50_uncal_deg = v[2];
  r.p50_cal_deg = v[3];
  r.field_min_mT = v[4];
  r.field_max_mT = v[5];
  r.field_lo_mT = v[6];
  r.field_hi_mT = v[7];
  r.margin_mT = v[8];
  r.bz_amplitude_mT = v[9];
  return r;
}

std::string DesignResult::reason(const DesignRequirements& r) const {
  std::string why;
  auto add = [&](const std::string& s) { why += (why.empty() ? "" : "; ") + s; };
  if (!(p99_req_deg(r) <= r.target_p99_deg))
    add(std::string(r.calibration.none() ? "p99 " : "calibrated p99 ") + fmt_sig(p99_req_deg(r), 3) + " deg > " +
        fmt_sig(r.target_p99_deg, 3) + " deg");
  if (field_lo_mT < r.window.min_mT) add("field " + fmt_sig(field_lo_mT, 3) + " mT below window " + fmt_sig(r.window.min_mT, 3) + " mT");
  if (field_hi_mT > r.window.max_mT) add("field " + fmt_sig(field_hi_mT, 3) + " mT above window " + fmt_sig(r.window.max_mT, 3) + " mT");
  return why;
}

std::uint64_t design_seed(const DesignOptions& o, std::size_t index) {
  return o.seed_per_design ? splitmix64(o.seed ^ splitmix64(static_cast<std::uint64_t>(index) + 1)) : o.seed;
}

namespace {

// The magnet of one design point.
Magnet design_magnet(const Design& d) {
  Magnet m;
  m.radius_mm = d.magnet_radius_mm;
  m.height_mm = d.magnet_height_mm;
  m.inner_radius_mm = d.magnet_inner_radius_mm;
  m.br_T = d.br_T;
  m.validate();
  return m;
}

// The random streams of one design: the factory samples of the mounting box, and per sample the drift to its
// run state (a re-mount and the run environment) when the design is judged with drift.
struct DesignSamples {
  std::vector<ToleranceCase> factory;
  ToleranceBox run_box;
  bool has_run = false;
  std::uint64_t drift_seed = 0;
  DesignSamples(const DesignOptions& o, const Design& d, const ToleranceBox& box, bool drift) {
    const std::uint64_t seed = design_seed(o, d.index);
    factory = monte_carlo_cases(box, o.samples, seed);
    run_box = o.run_box(d.br_tc_per_K);
    has_run = drift && !run_box.empty();
    drift_seed = splitmix64(seed + kDriftStream);
  }
  // Sample i at its run state: the drift's offsets added to the factory mount, the run environment (has_run).
  ToleranceCase at_run(const ToleranceCase& fc, std::size_t i) const {
    ToleranceCase rc = fc;
    const ToleranceCase dc = run_box.case_sample(drift_seed, i);
    rc.mount.sx_mm += dc.mount.sx_mm;
    rc.mount.sy_mm += dc.mount.sy_mm;
    rc.mount.dx_mm += dc.mount.dx_mm;
    rc.mount.dy_mm += dc.mount.dy_mm;
    rc.mount.dz_mm += dc.mount.dz_mm;
    rc.env = dc.env;
    return rc;
  }
};

// The local field models of one geometry (material, magnet, gap, r0) and the pipeline of one sensor.
struct DesignModel {
  std::unique_ptr<AnalyticField> field;
  std::unique_ptr<CircleFieldModel> model;
  // Bz = f(rho, z) cos(phi - theta) with f < 0 on the probe circle (over a ring's inner rim or its bore): the
  // array reads theta + 180 deg, the constant that the chip's zero takes out at installation (as zero =
  // auto does for a side-shaft reader); the design reads it with its channels' signs turned instead of a
  // wrapped error of 360 deg. Never for a solid magnet above its top face (f > 0).
  bool reversed = false;
  DesignModel(const DesignOptions& o, const Design& d, const ToleranceBox& box, bool drift) {
    field = std::make_unique<AnalyticField>(design_magnet(d));
    // The displacements the models must serve: the mounting box plus the drift (the radius study's reach
    // function on the sum; its spectra cases' floor keeps the models those of the radius study).
    RadiusScanOptions ro;
    ro.box = box;
    if (drift) {
      const ToleranceBox run = o.run_box(d.br_tc_per_K);
      ro.box.sx_mm += run.sx_mm;
      ro.box.sy_mm += run.sy_mm;
      ro.box.dx_mm += run.dx_mm;
      ro.box.dy_mm += run.dy_mm;
      ro.box.dz_mm += run.dz_mm;
      ro.box.temperature_min_C = run.temperature_min_C;
      ro.box.temperature_max_C = run.temperature_max_C;
      ro.box.env_coefficients = run.env_coefficients;
    }
    ro.plane_z_mm = d.plane_z_mm();
    ro.magnet_height_mm = d.magnet_height_mm;
    const auto [xy, z] = model_reach_mm(ro, d.r0_mm);
    model = std::make_unique<CircleFieldModel>(*field, d.r0_mm, d.plane_z_mm(), o.fast_steps, xy, z, o.surrogate_order,
                                               box.has_tilts(), o.surrogate_build);
    reversed = field->Bz_T(Vec3(d.r0_mm, 0, d.plane_z_mm())) < 0;
  }
};

// The field window's extremes over a design's samples (min of fmin, max of fmax) without every sample's exact
// window. eps_field_bounds gives each sample's fmin in [min_lo, min_hi] and fmax in [max_lo, max_hi]; each
// thread keeps the smallest fmin and the largest fmax it has recorded. A sample's exact window is computed
// only where its bounds could pass them (max_hi above the thread's largest fmax, min_lo below its smallest
// fmin); otherwise it records max_lo and min_hi, which cannot pass the true extremes. The design's min and
// max of the recorded values are then exactly those of every sample's exact window, for any thread count and
// order: the bounds are strict (max_lo < fmax < max_hi), so every recorded value is at most the true max F,
// and the sample that holds F has max_hi > F, above every recorded value: it is always evaluated exactly
// (the same for the min).
class WindowExtremes {
 public:
  WindowExtremes() : lo_(std::size_t(omp_get_max_threads()), kInf), hi_(lo_.size(), -kInf) {}
  void record(const FastPipeline& fast, const ToleranceCase& c, const double bounds[4], double* fmin, double* fmax) {
    const std::size_t t = std::size_t(omp_get_thread_num());
    *fmin = bounds[1];
    *fmax = bounds[2];
    const bool need_min = bounds[0] < lo_[t], need_max = bounds[3] > hi_[t];
    if (need_min || need_max) {
      thread_local std::vector<Eigen::VectorXd> e;
      double emin = 0, emax = 0;
      fast.eps_field(c, e, &emin, &emax);
      if (need_min) *fmin = emin;
      if (need_max) *fmax = emax;
    }
    lo_[t] = std::min(lo_[t], *fmin);
    hi_[t] = std::max(hi_[t], *fmax);
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> lo_, hi_;  // per OpenMP thread
};

DesignResult result_of(const DesignOptions& o, const Design& d, const Eigen::MatrixXd& v);

DesignResult evaluate_with(const DesignOptions& o, const Design& d, const CircleFieldModel& model,
                           const ToleranceBox& box, bool drift, bool reversed) {
  ProbeArray array = o.space.sensors[d.sensor];
  if (reversed)
    for (std::size_t k = 0; k < array.w_cos.size(); ++k) {
      array.w_cos[k] = -array.w_cos[k];
      array.w_sin[k] = -array.w_sin[k];
    }
  const FastPipeline fast(model, {array}, d.magnet_height_mm);
  FastPipeline fast_run = fast;  // the run state: at speed.rpm when the encoder turns
  fast_run.set_speed(o.speed);
  const bool moving = o.speed.acts();
  const DesignSamples samples(o, d, box, drift);
  const bool has_run = samples.has_run;
  const Eigen::VectorXd theta = uniform_theta_deg(o.fast_steps);
  const bool cal = !o.req.calibration.none();
  // Per sample: uncalibrated pp, calibrated pp, field min, field max (factory state, 20 C; the field
  // window recorded so that its extremes over the samples are exact: WindowExtremes).
  WindowExtremes window;
  auto f = [&](std::size_t i, const ToleranceCase& fc, double* out) {
    // eps at the factory state (computed once) and at the run state, and the sensor's angles there (the
    // calibration's abscissae); per thread, so that a sample allocates nothing.
    thread_local std::vector<Eigen::VectorXd> ef, er;
    thread_local std::vector<UnitAngles> pf, pr;
    double bounds[4];  // fmin in [0], [1]; fmax in [2], [3]
    fast.eps_field_bounds(fc, ef, &bounds[0], &bounds[1], &bounds[2], &bounds[3], cal ? &pf : nullptr);
    window.record(fast, fc, bounds, &out[2], &out[3]);
    if (has_run) {
      fast_run.eps(samples.at_run(fc, i), er, cal ? &pr : nullptr);
    } else if (moving) {
      fast_run.eps(fc, er, cal ? &pr : nullptr);
    }
    const Eigen::VectorXd& run = has_run || moving ? er[0] : ef[0];
    out[0] = run.maxCoeff() - run.minCoeff();
    if (cal) {
      const UnitAngles& run_psi = has_run || moving ? pr[0] : pf[0];
      out[1] = calibrated_pp_deg(o.req.calibration, theta, ef[0], pf[0].cos_psi, pf[0].sin_psi, run, run_psi.cos_psi,
                                 run_psi.sin_psi);
    } else {
      out[1] = out[0];
    }
  };
  DesignResult r = result_of(o, d, evaluate_cases(samples.factory, 4, f));
  r.bz_amplitude_mT = 1e3 * model.amplitude_T();
  return r;
}

// The numbers of a design from its samples' rows (uncalibrated pp, calibrated pp, field min, field max).
DesignResult result_of(const DesignOptions& o, const Design& d, const Eigen::MatrixXd& v) {
  DesignResult r;
  const SampleStats su = sample_stats(v.col(0)), sc = sample_stats(v.col(1));
  r.p99_uncal_deg = su.p99;
  r.p99_cal_deg = sc.p99;
  r.p50_uncal_deg = percentile(std::vector<double>(v.col(0).data(), v.col(0).data() + v.rows()), 50);
  r.p50_cal_deg = percentile(std::vector<double>(v.col(1).data(), v.col(1).data() + v.rows()), 50);
  r.field_min_mT = v.col(2).minCoeff();
  r.field_max_mT = v.col(3).maxCoeff();
  // Br(T)/Br(20 C) at the two extremes (linear in T: the extremes of the range are the extremes of the scale).
  const double s1 = 1.0 + d.br_tc_per_K * (o.req.temperature_min_C - kReferenceTemperature_C);
  const double s2 = 1.0 + d.br_tc_per_K * (o.req.temperature_max_C - kReferenceTemperature_C);
  r.field_lo_mT = std::max(0.0, r.field_min_mT * std::min(s1, s2) - o.req.stray_mT);
  r.field_hi_mT = r.field_max_mT * std::max(s1, s2) + o.req.stray_mT;
  r.margin_mT = o.req.window.active()
                    ? std::min(r.field_lo_mT - o.req.window.min_mT, o.req.window.max_mT - r.field_hi_mT)
                    : std::numeric_limits<double>::infinity();
  return r;
}

// A side-shaft reader on the exact field: one spot, fast_steps per turn, direction, zero and gain trim (BCT)
// resolved once at the nominal mount.
ProbeSetup side_setup(const DesignOptions& o, const Design& d, const AnalyticField& field) {
  ProbeSetup s;
  s.array = ProbeArray::parse("point");
  s.principle = o.space.side_principles[d.sensor - o.space.sensors.size()];
  s.plane_z_mm = d.side_height_mm;
  s.center_mm = {d.side_radius_mm, 0.0};
  s.steps = o.fast_steps;
  s.magnet_height_mm = d.magnet_height_mm;
  s.orientation.direction_auto = s.orientation.zero_auto = s.orientation.gain_auto = true;
  try {
    return resolve_orientation(field, s);
  } catch (const InputError& e) {
    throw InputError("design.side_radius_mm = " + num(d.side_radius_mm) + " with design.side_height_mm = " +
                     num(d.side_height_mm) + " (design " + std::to_string(d.index) + "): " + e.what());
  }
}

// A side-shaft design: the direct pipeline (angle_error) on the same samples, drift, environment, speed and
// calibration as a Bz array's fast path; the field window is the in-plane magnitude's over the turn.
DesignResult evaluate_side(const DesignOptions& o, const Design& d, const ToleranceBox& box, bool drift) {
  const AnalyticField field(design_magnet(d));
  const ProbeSetup nominal = side_setup(o, d, field);
  ProbeSetup turning = nominal;
  turning.speed = o.speed;
  const bool moving = o.speed.acts();
  const DesignSamples samples(o, d, box, drift);
  const bool has_run = samples.has_run;
  const Eigen::VectorXd theta = uniform_theta_deg(o.fast_steps);
  auto f = [&](std::size_t i, const ToleranceCase& fc, double* out) {
    ProbeSetup at_factory = nominal;
    at_factory.env = fc.env;
    const AngleErrorResult at = angle_error(field, at_factory, fc.mount);
    out[2] = at.field_min_mT;
    out[3] = at.field_max_mT;
    AngleErrorResult later;
    if (has_run || moving) {
      const ToleranceCase rc = has_run ? samples.at_run(fc, i) : fc;
      ProbeSetup s = turning;
      s.env = rc.env;
      later = angle_error(field, s, rc.mount);
    }
    const Eigen::VectorXd& run = has_run || moving ? later.eps_deg : at.eps_deg;
    out[0] = run.maxCoeff() - run.minCoeff();
    out[1] = o.req.calibration.none() ? out[0] : calibrated_pp_deg(o.req.calibration, theta, at.eps_deg, run);
  };
  DesignResult r = result_of(o, d, evaluate_cases(samples.factory, 4, f));
  r.bz_amplitude_mT = std::numeric_limits<double>::quiet_NaN();
  return r;
}

bool same_geometry(const Design& a, const Design& b) {
  return a.material == b.material && a.br_T == b.br_T && a.magnet_radius_mm == b.magnet_radius_mm &&
         a.magnet_height_mm == b.magnet_height_mm && a.magnet_inner_radius_mm == b.magnet_inner_radius_mm &&
         a.gap_mm == b.gap_mm && a.r0_mm == b.r0_mm;
}

}  // namespace

DesignResult evaluate_design(const DesignOptions& o, std::size_t index, const ToleranceBox& box, bool drift) {
  const Design d = design_at(o.space, index);
  if (d.side) return evaluate_side(o, d, box, drift);
  const DesignModel dm(o, d, o.box, true);  // the models of the full box: the same for every budget line
  return evaluate_with(o, d, *dm.model, box, drift, dm.reversed);
}

std::vector<DesignResult> evaluate_designs(const DesignOptions& o, std::size_t begin, std::size_t end) {
  std::vector<DesignResult> out;
  std::unique_ptr<DesignModel> dm;
  Design last;
  for (std::size_t i = begin; i < end; ++i) {
    const Design d = design_at(o.space, i);
    if (d.side) {
      out.push_back(evaluate_side(o, d, o.box, true));
      continue;
    }
    // The models depend on the geometry alone (sensors innermost): reuse them across sensors.
    if (!dm || !same_geometry(d, last)) dm = std::make_unique<DesignModel>(o, d, o.box, true);
    last = d;
    out.push_back(evaluate_with(o, d, *dm->model, o.box, true, dm->reversed));
  }
  return out;
}

DesignStudyResult summarize_designs(const DesignOptions& o, std::vector<DesignResult> results) {
  if (results.size() != o.space.size())
    throw ComputeError("design results: " + std::to_string(results.size()) + " for " + std::to_string(o.space.size()) +
                       " designs");
  DesignStudyResult s;
  s.results = std::move(results);
  for (std::size_t i = 0; i < s.results.size(); ++i) s.designs.push_back(design_at(o.space, i));
  s.pareto.resize(o.space.sensor_count());
  auto better = [&](std::size_t a, std::size_t b) {  // smaller volume, then p99, then index
    const double va = s.designs[a].volume_mm3(), vb = s.designs[b].volume_mm3();
    if (va != vb) return va < vb;
    const double pa = s.results[a].p99_req_deg(o.req), pb = s.results[b].p99_req_deg(o.req);
    if (pa != pb) return pa < pb;
    return a < b;
  };
  for (std::size_t sensor = 0; sensor < o.space.sensor_count(); ++sensor) {
    std::vector<std::size_t> cand;
    for (std::size_t i = 0; i < s.designs.size(); ++i)
      if (s.designs[i].sensor == sensor && s.results[i].field_ok()) cand.push_back(i);
    std::sort(cand.begin(), cand.end(), better);
    // Sweep by increasing volume: a design is on the front when its p99 is below every smaller one's.
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i : cand) {
      const double p = s.results[i].p99_req_deg(o.req);
      if (p < best) {
        s.pareto[sensor].push_back(i);
        best = p;
      }
    }
  }
  for (std::size_t i = 0; i < s.designs.size(); ++i) {
    if (!s.results[i].pass(o.req)) continue;
    ++s.passing;
    if (s.recommended < 0 || better(i, static_cast<std::size_t>(s.recommended))) s.recommended = static_cast<long>(i);
  }
  if (s.recommended >= 0) s.budget = design_budget(o, static_cast<std::size_t>(s.recommended));
  return s;
}

std::vector<BudgetEntry> design_budget(const DesignOptions& o, std::size_t index) {
  std::vector<BudgetEntry> b;
  for (const auto& g : ToleranceBox::groups()) {
    const ToleranceBox only = o.box.only(g);
    if (only.empty()) continue;
    const DesignResult r = evaluate_design(o, index, only, false);
    b.push_back({g, r.p99_uncal_deg, r.p99_cal_deg});
  }
  const ToleranceBox run = o.run_box(0.0);
  if (!run.empty()) {
    ToleranceBox none;  // no mounting tolerance
    none.sx_mm = none.sy_mm = none.dx_mm = none.dy_mm = none.dz_mm = 0;
    const DesignResult r = evaluate_design(o, index, none, true);
    b.push_back({"drift and environment", r.p99_uncal_deg, r.p99_cal_deg});
  }
  const DesignResult all = evaluate_design(o, index, o.box, true);
  b.push_back({"all", all.p99_uncal_deg, all.p99_cal_deg});
  return b;
}

}  // namespace magenc
