#include "probe/sensor.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "core/defaults.hpp"
#include "core/errors.hpp"

namespace magenc {

namespace {
KeySpec center_key(double big) {
  KeySpec k = real_list_key("sensor.center_mm", {0.0, 0.0}, -big, big, "mm",
                            "nominal die centre [x, y] in the fixed frame: the probe circle or spot is centred "
                            "there, the static offsets add",
                            false, 2);
  // [x, y]: two numbers, checked by its readers (a fixed-length key would refuse the "x,y" text that
  // config.toml echoes).
  return k;
}

const char* const kAllowedPrinciples = "allowed bz, inplane, xmr, amr";

// The declared default of a key (its text, as the schema holds it).
std::string default_text(const Config& cfg, const std::string& key) {
  const KeySpec* s = cfg.find(key);
  return s ? s->default_value : "";
}

// A real key differs from its declared default (a key the schema lacks never does).
bool real_changed(const Config& cfg, const std::string& key) {
  if (!cfg.has(key)) return false;
  return cfg.real(key) != std::stod(default_text(cfg, key));
}
}  // namespace

SensorPrinciple parse_principle(const std::string& text, const std::string& what) {
  for (SensorPrinciple p : all_principles())
    if (principle_name(p) == text) return p;
  throw InputError(what + " = '" + text + "' is not a sensing principle: " + kAllowedPrinciples);
}

std::string principle_name(SensorPrinciple p) {
  switch (p) {
    case SensorPrinciple::Bz: return "bz";
    case SensorPrinciple::InPlane: return "inplane";
    case SensorPrinciple::Xmr: return "xmr";
    case SensorPrinciple::Amr: return "amr";
  }
  return "bz";
}

const std::vector<SensorPrinciple>& all_principles() {
  static const std::vector<SensorPrinciple> all = {SensorPrinciple::Bz, SensorPrinciple::InPlane,
                                                   SensorPrinciple::Xmr, SensorPrinciple::Amr};
  return all;
}

void FieldWindow::validate() const {
  if (!(std::isfinite(min_mT) && min_mT >= 0))
    throw InputError("sensor.field_min_mT = " + num(min_mT) + " is out of range: allowed [0, 1e+06] mT");
  if (!(max_mT > 0))  // NaN fails too; +inf is allowed (no upper limit)
    throw InputError("sensor.field_max_mT = " + num(max_mT) + " is out of range: allowed (0, inf] mT");
  if (min_mT > max_mT)
    throw InputError("sensor.field_min_mT = " + num(min_mT) + " exceeds sensor.field_max_mT = " + num(max_mT) +
                     ": allowed field_min_mT <= field_max_mT");
}

void SensingArea::validate() const {
  if (!(std::isfinite(plate_mm) && plate_mm >= 0 && plate_mm <= kMaxPlate_mm))
    throw InputError("sensor.plate_mm = " + num(plate_mm) + " is out of range: allowed [0, " + num(kMaxPlate_mm) +
                     "] mm");
  if (plate_points < 1 || plate_points > kMaxPoints)
    throw InputError("sensor.plate_points = " + std::to_string(plate_points) +
                     " is out of range: allowed integer in [1, " + std::to_string(kMaxPoints) + "]");
}

void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  if (n == 1) {
    w[0] = 2.0;
    return;
  }
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, n);
  for (int k = 1; k < n; ++k) {
    const double b = k / std::sqrt(4.0 * k * k - 1.0);
    J(k - 1, k) = b;
    J(k, k - 1) = b;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(J);
  for (int i = 0; i < n; ++i) {
    x[static_cast<std::size_t>(i)] = es.eigenvalues()[i];
    const double v0 = es.eigenvectors()(0, i);
    w[static_cast<std::size_t>(i)] = 2.0 * v0 * v0;
  }
  // Symmetrize (the rule is symmetric about 0; removes eigen-solver round-off asymmetry).
  for (int i = 0; i < n / 2; ++i) {
    const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(n - 1 - i);
    const double xs = 0.5 * (x[b] - x[a]), ws = 0.5 * (w[a] + w[b]);
    x[a] = -xs;
    x[b] = xs;
    w[a] = w[b] = ws;
  }
  if (n % 2 == 1) x[static_cast<std::size_t>(n / 2)] = 0.0;
}

void SensingArea::nodes(std::vector<double>& u_mm, std::vector<double>& v_mm, std::vector<double>& w) const {
  u_mm.clear();
  v_mm.clear();
  w.clear();
  if (point()) {
    u_mm = {0.0};
    v_mm = {0.0};
    w = {1.0};
    return;
  }
  std::vector<double> x, wx;
  gauss_legendre(plate_points, x, wx);
  const double h = 0.5 * plate_mm;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < x.size(); ++j) {
      u_mm.push_back(h * x[i]);
      v_mm.push_back(h * x[j]);
      w.push_back(0.25 * wx[i] * wx[j]);  // weights of [-1, 1]^2 sum to 4: the mean over the square
    }
}

void check_principle_keys(const Config& cfg) {
  const std::string pname = cfg.str("sensor.principle");
  const SensorPrinciple p = parse_principle(pname);
  auto refuse = [&](const std::string& key, const std::string& shown, const std::string& allowed) {
    throw InputError(key + " = " + shown + " does not apply to sensor.principle = " + pname + ": allowed " + allowed);
  };
  const std::string array = cfg.str("sensor.array");
  if (reads_in_plane(p)) {
    if (array != "point" && array != default_text(cfg, "sensor.array"))
      refuse("sensor.array", "'" + array + "'", "point (one sensing spot at the die centre)");
    if (real_changed(cfg, "sensor.r0_mm"))
      refuse("sensor.r0_mm", num(cfg.real("sensor.r0_mm")), "its default (r0 is not used by the point array)");
  } else if (array == "point") {
    refuse("sensor.array", "'point'", "two, diff4, ring:N (or another sensor.principle: inplane, xmr, amr)");
  }
  const char* const mT[] = {"sensor.offset_cos_mT", "sensor.offset_sin_mT"};
  const char* const rel[] = {"sensor.offset_cos_rel", "sensor.offset_sin_rel"};
  for (const char* key : relative_offsets(p) ? mT : rel)
    if (real_changed(cfg, key))
      refuse(key, num(cfg.real(key)),
             relative_offsets(p) ? "0 (xmr/amr offsets are relative: sensor.offset_cos_rel, sensor.offset_sin_rel)"
                                 : "0 (bz/inplane offsets are in mT: sensor.offset_cos_mT, sensor.offset_sin_mT)");
  const FieldWindow window{cfg.real("sensor.field_min_mT"), cfg.real("sensor.field_max_mT")};
  window.validate();
}

ChipOrientation ChipOrientation::from_config(const Config& cfg) {
  ChipOrientation o;
  const std::string dir = cfg.str("sensor.direction");
  o.direction_auto = dir == "auto";
  o.direction = dir == "-1" ? -1 : 1;
  const std::string zero = cfg.str("sensor.zero_deg");
  o.zero_auto = zero == "auto";
  if (!o.zero_auto) {
    std::size_t pos = 0;
    double z = std::numeric_limits<double>::quiet_NaN();
    try {
      z = std::stod(zero, &pos);
    } catch (...) {
      pos = 0;
    }
    if (pos == 0 || pos != zero.size() || !std::isfinite(z) || std::abs(z) > 360.0)
      throw InputError("sensor.zero_deg = '" + zero + "' is out of range: allowed a number in [-360, 360] deg or auto");
    o.zero_deg = z;
  }
  o.gain_auto = cfg.str("sensor.gain_trim") == "auto";
  return o;
}

void require_on_axis_layout(const Config& cfg, const std::string& who) {
  const std::string tail = ": " + who + " assumes a solid magnet and an array centred on the axis: allowed ";
  if (cfg.has("magnet.inner_radius_mm") && cfg.real("magnet.inner_radius_mm") != 0.0)
    throw InputError("magnet.inner_radius_mm = " + num(cfg.real("magnet.inner_radius_mm")) + tail + "0");
  if (cfg.has("sensor.plane_height_mm") && !(cfg.real("sensor.plane_height_mm") > 0))
    throw InputError("sensor.plane_height_mm = " + num(cfg.real("sensor.plane_height_mm")) + tail +
                     "a plane above the top face (> 0 mm)");
  if (!cfg.has("sensor.center_mm")) return;
  const std::vector<double> c = cfg.reals("sensor.center_mm");
  if (c.size() != 2 || c[0] != 0.0 || c[1] != 0.0)
    throw InputError("sensor.center_mm = " + cfg.str("sensor.center_mm") + tail + "[0, 0]");
  if (!ChipOrientation::from_config(cfg).identity())
    throw InputError("sensor.direction = " + cfg.str("sensor.direction") + ", sensor.zero_deg = " +
                     cfg.str("sensor.zero_deg") + ", sensor.gain_trim = " + cfg.str("sensor.gain_trim") + tail +
                     "1, 0 and none");
}

std::vector<KeySpec> sensor_keys() {
  const double big = defaults::kMaxLength_mm;
  const double inf = std::numeric_limits<double>::infinity();
  return {
      real_key("sensor.plane_height_mm", defaults::kPlaneHeight_mm, -big, big, "mm",
               "sensing plane height h above the top face (negative: below it; -L/2 is the magnet's mid-plane); no "
               "sensing point may lie in the magnet at the nominal mount"),
      center_key(big),
      number_or_word_key("sensor.direction", "1", {"1", "-1", "auto"},
                         "the chip's counting direction: phi = wrap(direction atan2(u_s, u_c) + zero); auto = the "
                         "sign of the angle's winding at the nominal mount"),
      number_or_word_key("sensor.zero_deg", "0", {},
                         "the chip's zero added to the angle, deg in [-360, 360], or auto = minus the circular mean "
                         "error at the nominal mount"),
      string_key("sensor.gain_trim", "none", {"none", "auto"},
                 "gain trim of the sin channel (BCT): auto = scaled by the ratio of the channels' first-harmonic "
                 "amplitudes at the nominal mount, on top of sensor.gain_mismatch; none = no trim"),
      real_key("sensor.r0_mm", defaults::kProbeRadius_mm, 0, big, "mm", "nominal probe radius r0", true),
      string_key("sensor.array", "two", {}, "probe array: two, diff4 or ring:N (N >= 3) for principle bz; point for the others"),
      int_key("sensor.steps", 3600, 16, 10000000, "samples M of theta over one turn"),
      real_key("sensor.offset_cos_mT", 0.0, -1000, 1000, "mT", "offset added to the cos channel (signal chain)"),
      real_key("sensor.offset_sin_mT", 0.0, -1000, 1000, "mT", "offset added to the sin channel (signal chain)"),
      real_key("sensor.gain_mismatch", 0.0, -1, 10, "",
               "gain mismatch g: sin channel scaled by 1 + g (signal chain)", true),
      real_key("sensor.phase_error_deg", 0.0, -90, 90, "deg",
               "phase error delta of the sin channel: u_s' = (1+g)(u_s cos delta + u_c sin delta) + os", true, true),
      // Sensing principles, field window, sensing area (docs/physics.md "Sensor principles"; probe/sensor.hpp).
      string_key("sensor.principle", "bz", {"bz", "inplane", "xmr", "amr"},
                 "sensing principle: bz (Hall plates on r0), inplane (3-D Hall at one spot), xmr (saturated "
                 "GMR/TMR), amr (anisotropic MR, twice the field angle); arrays: bz two|diff4|ring:N, others point"),
      real_key("sensor.field_min_mT", 0.0, 0, 1e6, "mT",
               "field window: least field magnitude the chip needs (bz: each probe's peak |reading|; in-plane "
               "principles: hypot(b1, b2)); 0 = no lower limit"),
      real_key("sensor.field_max_mT", inf, 0, inf, "mT",
               "field window: largest field magnitude the chip allows; inf = no upper limit", true),
      real_key("sensor.plate_mm", 0.0, 0, 10.0, "mm",
               "side of the square sensing area centred on each probe or spot in the die plane (0 = a point)"),
      int_key("sensor.plate_points", 4, 1, 32,
              "n of the n x n Gauss-Legendre rule over the sensing area (sensor.plate_mm > 0)"),
      real_key("sensor.offset_cos_rel", 0.0, -1, 1, "",
               "xmr/amr: offset of the cos channel as a fraction of the unit amplitude (signal chain)"),
      real_key("sensor.offset_sin_rel", 0.0, -1, 1, "",
               "xmr/amr: offset of the sin channel as a fraction of the unit amplitude (signal chain)"),
  };
}

}  // namespace magenc
