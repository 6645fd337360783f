#include "studies/stray_field/stray_field_engine.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>

#include "analysis/sensor_principles.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A field source that remembers its last batch (points and result) and answers a repeated batch from
// memory. A fixed mount reads the magnet at the same points for every stray field, so the field is
// evaluated once per sensor; any other batch goes to the wrapped source.
class LastBatchField final : public FieldSource {
 public:
  explicit LastBatchField(const FieldSource& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  Vec3 B_T(const Vec3& p_mm) const override { return inner_.B_T(p_mm); }
  double Bz_T(const Vec3& p_mm) const override { return inner_.Bz_T(p_mm); }
  bool gives_full_vector() const override { return inner_.gives_full_vector(); }
  Eigen::Matrix3Xd B_T(const Eigen::Matrix3Xd& p_mm) const override {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!same(p_mm, b_points_)) {
      b_points_ = p_mm;
      b_ = inner_.B_T(p_mm);
    }
    return b_;
  }
  Eigen::VectorXd Bz_T(const Eigen::Matrix3Xd& p_mm) const override {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!same(p_mm, bz_points_)) {
      bz_points_ = p_mm;
      bz_ = inner_.Bz_T(p_mm);
    }
    return bz_;
  }

 private:
  static bool same(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
    return a.cols() == b.cols() && (a.array() == b.array()).all();
  }
  const FieldSource& inner_;
  mutable std::mutex mutex_;
  mutable Eigen::Matrix3Xd b_points_, bz_points_, b_;
  mutable Eigen::VectorXd bz_;
};

AngleErrorResult run_with(const FieldSource& field, ProbeSetup setup, const Mount& mount, const StrayField& stray) {
  setup.env.stray = stray;
  return angle_error(field, setup, mount);
}

// f(0), ..., f(n - 1) on the OpenMP threads (each writes its own result slot); the exception of the lowest
// index that threw, if any, is rethrown, as a serial loop would have.
template <class F>
void for_each_index(long n, const F& f) {
  std::exception_ptr err;
  long err_i = n;
  std::mutex mtx;
#pragma omp parallel for schedule(dynamic, 4)
  for (long i = 0; i < n; ++i) {
    try {
      f(static_cast<std::size_t>(i));
    } catch (...) {
      const std::lock_guard<std::mutex> lock(mtx);
      if (i < err_i) {
        err_i = i;
        err = std::current_exception();
      }
    }
  }
  if (err) std::rethrow_exception(err);
}

StrayField uniform(const Eigen::Vector3d& b_mT) {
  StrayField s;
  s.uniform_mT = b_mT;
  return s;
}

// The largest b in (0, search_max] with worst pp <= threshold. The bracket comes from the magnitude curve
// (b_i, worst pp_i, increasing b): the first b_i above the threshold; past the curve's end, 8 logarithmic
// steps up to search_max. Then bisection in log b to 0.1 %.
ToleratedField tolerated_field(const FieldSource& field, const ProbeSetup& setup, const Mount& mount,
                               const std::vector<Eigen::Vector3d>& dirs, double threshold_deg, double search_max_mT,
                               const std::vector<double>& curve_mT, const std::vector<StrayError>& curve) {
  ToleratedField t;
  t.threshold_deg = threshold_deg;
  auto worst = [&](double b) { return worst_over_directions(field, setup, mount, b, dirs).pp_deg; };
  if (worst(0.0) > threshold_deg) return t;  // the mount alone exceeds it: 0
  double lo = 0, hi = kInf;
  for (std::size_t i = 0; i < curve.size() && curve_mT[i] <= search_max_mT; ++i) {
    if (curve[i].pp_deg > threshold_deg) {
      hi = curve_mT[i];
      break;
    }
    lo = curve_mT[i];
  }
  if (std::isinf(hi) && lo < search_max_mT) {
    const double from = std::max(lo, 1e-6);
    for (int i = 1; i <= 8; ++i) {
      const double b = from * std::pow(search_max_mT / from, i / 8.0);
      if (worst(b) > threshold_deg) {
        hi = b;
        break;
      }
      lo = b;
    }
  }
  if (std::isinf(hi)) {
    t.field_mT = kInf;
    t.beyond = true;
    return t;
  }
  if (lo == 0) {  // below the curve's start: step down by decades
    lo = hi;
    while (lo > 1e-9 && worst(lo) > threshold_deg) lo *= 0.1;
    if (worst(lo) > threshold_deg) return t;
  }
  while (hi / lo > 1.001) {
    const double mid = std::sqrt(lo * hi);
    (worst(mid) > threshold_deg ? hi : lo) = mid;
  }
  t.field_mT = lo;
  return t;
}

}  // namespace

std::vector<KeySpec> StrayFieldOptions::keys() {
  const StrayFieldOptions d;
  return {
      string_list_key("study.sensors", d.sensors, {},
                      "sensors: bz arrays two, diff4, ring:N (on sensor.r0_mm) and the one-spot principles inplane, "
                      "xmr, amr"),
      string_key("study.field", "analytic", {}, "field source (analytic, fem:DIR, grid:FILE.vti, table:FILE with Bx, By)"),
      real_list_key("study.levels_kA_per_m", d.levels_kA_per_m, 0, 1e4, "kA/m",
                    "uniform stray-field test levels H (1 kA/m = 1.257 mT in air)", true),
      real_key("study.curve_min_mT", d.curve_min_mT, 0, 1e4, "mT", "error vs magnitude: smallest |B|", true),
      real_key("study.curve_max_mT", d.curve_max_mT, 0, 1e4, "mT", "error vs magnitude: largest |B|", true),
      int_key("study.curve_points", d.curve_points, 2, 1000, "error vs magnitude: magnitudes (log spaced)"),
      int_key("study.polar_points", d.polar_points, 3, 361, "directions: polar angles 0..180 deg (poles included)"),
      int_key("study.azimuth_points", d.azimuth_points, 1, 720, "directions: azimuths over 360 deg"),
      real_key("study.map_kA_per_m", d.map_kA_per_m, 0, 1e4, "kA/m", "magnitude of the direction maps", true),
      real_list_key("study.thresholds_deg", d.thresholds_deg, 0, 180, "deg",
                    "pp thresholds of the tolerated uniform field", true),
      real_key("study.search_max_mT", d.search_max_mT, 0, 1e5, "mT", "tolerated-field search: largest |B|", true),
      real_list_key("study.wire_distances_mm", d.wire_distances_mm, 0, 1e5, "mm",
                    "conductor distances from the sensor centre (along x)", true),
      real_list_key("study.wire_currents_A", d.wire_currents_A, 0, 1e6, "A", "conductor currents", true),
      int_key("study.steps", d.steps, 16, 100000, "theta samples per turn"),
  };
}

StrayFieldOptions StrayFieldOptions::from_config(const Config& cfg) {
  StrayFieldOptions o;
  o.sensors = cfg.strings("study.sensors");
  o.levels_kA_per_m = cfg.reals("study.levels_kA_per_m");
  o.curve_min_mT = cfg.real("study.curve_min_mT");
  o.curve_max_mT = cfg.real("study.curve_max_mT");
  if (!(o.curve_min_mT < o.curve_max_mT))
    throw InputError("study.curve_min_mT = " + num(o.curve_min_mT) + " is not below study.curve_max_mT = " +
                     num(o.curve_max_mT) + ": allowed curve_min_mT < curve_max_mT");
  o.curve_points = static_cast<int>(cfg.integer("study.curve_points"));
  o.polar_points = static_cast<int>(cfg.integer("study.polar_points"));
  o.azimuth_points = static_cast<int>(cfg.integer("study.azimuth_points"));
  o.map_kA_per_m = cfg.real("study.map_kA_per_m");
  o.thresholds_deg = cfg.reals("study.thresholds_deg");
  o.search_max_mT = cfg.real("study.search_max_mT");
  o.wire_distances_mm = cfg.reals("study.wire_distances_mm");
  o.wire_currents_A = cfg.reals("study.wire_currents_A");
  o.steps = static_cast<int>(cfg.integer("study.steps"));
  return o;
}

void StrayFieldOptions::directions(std::vector<Eigen::Vector3d>& dirs, std::vector<double>& polar_deg,
                                   std::vector<double>& azimuth_deg) const {
  dirs.clear();
  polar_deg.clear();
  azimuth_deg.clear();
  for (int j = 0; j < azimuth_points; ++j) azimuth_deg.push_back(360.0 * j / azimuth_points);
  for (int i = 0; i < polar_points; ++i) {
    const double t = 180.0 * i / (polar_points - 1);
    polar_deg.push_back(t);
    const bool pole = i == 0 || i == polar_points - 1;
    for (int j = 0; j < (pole ? 1 : azimuth_points); ++j) {
      const double th = deg_to_rad(t), ph = deg_to_rad(azimuth_deg[static_cast<std::size_t>(j)]);
      dirs.emplace_back(pole ? 0.0 : std::sin(th) * std::cos(ph), pole ? 0.0 : std::sin(th) * std::sin(ph),
                        i == 0 ? 1.0 : (pole ? -1.0 : std::cos(th)));
    }
  }
}

StrayError worst_over_directions(const FieldSource& field, const ProbeSetup& setup, const Mount& mount, double b_mT,
                                 const std::vector<Eigen::Vector3d>& dirs) {
  // The directions' runs in parallel, then the worst in the directions' order (the first of equals wins).
  std::vector<Spectrum> spectra(dirs.size());
  for_each_index(static_cast<long>(dirs.size()),
                 [&](std::size_t k) { spectra[k] = run_with(field, setup, mount, uniform(b_mT * dirs[k])).spectrum; });
  StrayError w;
  w.pp_deg = -1;
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    const Eigen::Vector3d& u = dirs[k];
    const Spectrum& sp = spectra[k];
    if (sp.pp_deg > w.pp_deg) {
      w.pp_deg = sp.pp_deg;
      w.c1_deg = sp.c_deg[1];
      w.worst_dir = u;
    }
    w.max_c1_deg = std::max(w.max_c1_deg, sp.c_deg[1]);
  }
  return w;
}

StrayFieldResult run_stray_field(const FieldSource& field, const ProbeSetup& base, const Mount& mount,
                                 const StrayFieldOptions& opt) {
  StrayFieldResult r;
  r.field = field.name();
  r.mount = mount;
  std::vector<Eigen::Vector3d> dirs;
  opt.directions(dirs, r.polar_deg, r.azimuth_deg);
  for (double d : opt.wire_distances_mm)
    if (!(d > 0)) throw InputError("study.wire_distances_mm: " + num(d) + " is out of range: allowed (0, 1e5] mm");
  std::vector<PrincipleSensor> sensors;
  for (const auto& e : opt.sensors) {
    PrincipleSensor s = principle_sensor(e, base, "study.sensors");
    s.setup.steps = opt.steps;
    s.setup.env.stray = StrayField{};  // the study sets the stray field itself
    sensors.push_back(s);
  }
  // The sensor centre in the fixed frame: the conductors pass beside it.
  const MountKinematics kin(mount, base.plane_z_mm, base.magnet_height_mm);
  const Eigen::Vector3d centre = kin.fixed_position_mm(0.0, 0.0);
  for (const PrincipleSensor& sen : sensors) {
    const LastBatchField cached(field);
    StraySensorResult s;
    s.label = sen.label;
    s.principle = sen.setup.principle;
    s.base_pp_deg = run_with(cached, sen.setup, mount, StrayField{}).spectrum.pp_deg;
    for (int i = 0; i < opt.curve_points; ++i) {
      const double b = opt.curve_min_mT * std::pow(opt.curve_max_mT / opt.curve_min_mT,
                                                   static_cast<double>(i) / (opt.curve_points - 1));
      s.curve_mT.push_back(b);
      s.curve.push_back(worst_over_directions(cached, sen.setup, mount, b, dirs));
    }
    for (double h : opt.levels_kA_per_m)
      s.levels.push_back(worst_over_directions(cached, sen.setup, mount, h * kmT_per_kA_per_m, dirs));
    for (double th : opt.thresholds_deg)
      s.tolerated.push_back(
          tolerated_field(cached, sen.setup, mount, dirs, th, opt.search_max_mT, s.curve_mT, s.curve));
    for (const char* orientation : {"along y", "along z"}) {
      const Eigen::Vector3d u = orientation[6] == 'y' ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
      for (double d : opt.wire_distances_mm)
        for (double I : opt.wire_currents_A) {
          StrayField w;
          w.wire_current_A = I;
          w.wire_point_mm = centre + Eigen::Vector3d(d, 0, 0);
          w.wire_direction = u;
          WireCase c;
          c.orientation = orientation;
          c.distance_mm = d;
          c.current_A = I;
          const Spectrum sp = run_with(cached, sen.setup, mount, w).spectrum;
          c.pp_deg = sp.pp_deg;
          c.c1_deg = sp.c_deg[1];
          c.field_mT = w.B_mT(centre).norm();
          s.wires.push_back(c);
        }
    }
    const double b_map = opt.map_kA_per_m * kmT_per_kA_per_m;
    s.map_pp_deg.resize(opt.polar_points, opt.azimuth_points);
    for_each_index(static_cast<long>(opt.polar_points) * opt.azimuth_points, [&](std::size_t k) {
      const auto i = static_cast<int>(k / static_cast<std::size_t>(opt.azimuth_points));
      const auto j = static_cast<int>(k % static_cast<std::size_t>(opt.azimuth_points));
      const double th = deg_to_rad(r.polar_deg[static_cast<std::size_t>(i)]);
      const double ph = deg_to_rad(r.azimuth_deg[static_cast<std::size_t>(j)]);
      const Eigen::Vector3d u(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      s.map_pp_deg(i, j) = run_with(cached, sen.setup, mount, uniform(b_map * u)).spectrum.pp_deg;
    });
    r.sensors.push_back(std::move(s));
  }
  return r;
}

}  // namespace magenc
