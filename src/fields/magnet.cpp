#include "fields/magnet.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

std::string pattern_name(MagnetPattern p) {
  switch (p) {
    case MagnetPattern::Radial: return "radial";
    case MagnetPattern::AxialMultipole: return "axial_multipole";
    case MagnetPattern::RadialMultipole: return "radial_multipole";
    case MagnetPattern::Uniform: break;
  }
  return "uniform";
}

namespace {

MagnetPattern parse_pattern(const std::string& text) {
  for (MagnetPattern p : {MagnetPattern::Uniform, MagnetPattern::Radial, MagnetPattern::AxialMultipole,
                          MagnetPattern::RadialMultipole})
    if (pattern_name(p) == text) return p;
  throw InputError("magnet.pattern = '" + text +
                   "' is not a pattern: allowed uniform, radial, axial_multipole, radial_multipole");
}

void validate_pattern(const Magnet& m) {
  if (m.is_uniform()) return;
  const std::string name = "magnet.pattern = " + pattern_name(m.pattern);
  if (m.is_multipole() && m.pole_pairs < 1)
    throw InputError(name + " with magnet.pole_pairs = " + std::to_string(m.pole_pairs) +
                     " is out of range: allowed pole_pairs >= 1 for a multipole pattern");
  if (m.magnetization_deg != 0.0 || m.magnetization_elevation_deg != 0.0)
    throw InputError(name + " with magnet.magnetization_deg = " + num(m.magnetization_deg) +
                     ", magnet.magnetization_elevation_deg = " + num(m.magnetization_elevation_deg) +
                     ": the direction keys apply to the uniform pattern only: allowed 0 and 0");
  if (!(std::isfinite(m.pole_edge_sigma_deg) && m.pole_edge_sigma_deg >= 0 &&
        m.pole_edge_sigma_deg * std::max(1, m.pole_pairs) < 30.0))
    throw InputError("magnet.pole_edge_sigma_deg = " + num(m.pole_edge_sigma_deg) +
                     " is out of range: allowed 0 <= sigma < 30/pole_pairs deg (a sixth of a pole)");
  if (!(std::isfinite(m.pole_amplitude_sigma) && m.pole_amplitude_sigma >= 0 && m.pole_amplitude_sigma < 0.3))
    throw InputError("magnet.pole_amplitude_sigma = " + num(m.pole_amplitude_sigma) +
                     " is out of range: allowed [0, 0.3)");
}

}  // namespace

void Magnet::validate() const {
  auto positive = [](const char* name, double v, const char* unit) {
    if (!(std::isfinite(v) && v > 0))
      throw InputError(std::string(name) + " = " + num(v) + " is out of range: allowed (0, 1000] " + unit);
  };
  positive("magnet.radius_mm", radius_mm, "mm");
  positive("magnet.height_mm", height_mm, "mm");
  positive("magnet.br_T", br_T, "T");
  if (!(std::isfinite(inner_radius_mm) && inner_radius_mm >= 0 && inner_radius_mm < radius_mm))
    throw InputError("magnet.inner_radius_mm = " + num(inner_radius_mm) + " with magnet.radius_mm = " + num(radius_mm) +
                     " is out of range: allowed 0 <= inner_radius_mm < radius_mm (mm)");
  if (!(std::isfinite(mu_r) && mu_r >= 1))
    throw InputError("magnet.mu_r = " + num(mu_r) + " is out of range: allowed [1, 1e6]");
  if (!std::isfinite(magnetization_deg))
    throw InputError("magnet.magnetization_deg is NaN: allowed [-360, 360] deg");
  if (!(std::isfinite(magnetization_elevation_deg) && std::abs(magnetization_elevation_deg) <= 90.0))
    throw InputError("magnet.magnetization_elevation_deg = " + num(magnetization_elevation_deg) +
                     " is out of range: allowed [-90, 90] deg");
  validate_pattern(*this);
}

bool Magnet::contains_mm(double x_mm, double y_mm, double z_mm) const {
  const double r = std::hypot(x_mm, y_mm);
  return r <= radius_mm && r >= inner_radius_mm && std::abs(z_mm) <= top_z_mm();
}

Eigen::Vector3d Magnet::remanence_T() const {
  const double a = deg_to_rad(magnetization_deg), el = deg_to_rad(magnetization_elevation_deg);
  const double ce = magnetization_elevation_deg == 0.0 ? 1.0 : std::cos(el);
  const double se = magnetization_elevation_deg == 0.0 ? 0.0 : std::sin(el);
  return br_T * Eigen::Vector3d(ce * std::cos(a), ce * std::sin(a), se);
}

Magnet Magnet::from_config(const Config& cfg) {
  Magnet m;
  m.radius_mm = cfg.real("magnet.radius_mm");
  m.inner_radius_mm = cfg.real("magnet.inner_radius_mm");
  m.height_mm = cfg.real("magnet.height_mm");
  m.br_T = cfg.real("magnet.br_T");
  m.mu_r = cfg.real("magnet.mu_r");
  m.magnetization_deg = cfg.real("magnet.magnetization_deg");
  m.magnetization_elevation_deg = cfg.real("magnet.magnetization_elevation_deg");
  m.pattern = parse_pattern(cfg.str("magnet.pattern"));
  m.pole_pairs = static_cast<int>(cfg.integer("magnet.pole_pairs"));
  m.pole_edge_sigma_deg = cfg.real("magnet.pole_edge_sigma_deg");
  m.pole_amplitude_sigma = cfg.real("magnet.pole_amplitude_sigma");
  m.pole_seed = cfg.integer("magnet.pole_seed");
  m.validate();
  return m;
}

double sensing_plane_z_mm(const Config& cfg) {
  return 0.5 * cfg.real("magnet.height_mm") + cfg.real("sensor.plane_height_mm");
}

std::vector<KeySpec> Magnet::keys() {
  const double big = defaults::kMaxLength_mm;
  return {
      real_key("magnet.radius_mm", defaults::kMagnetRadius_mm, 0, big, "mm", "magnet radius R", true),
      real_key("magnet.inner_radius_mm", 0.0, 0, big, "mm",
               "inner radius Ri of a ring magnet (bore of air); 0 = a solid cylinder; allowed 0 <= Ri < radius_mm"),
      real_key("magnet.height_mm", defaults::kMagnetHeight_mm, 0, big, "mm", "magnet height L (axis z, centred at 0)", true),
      real_key("magnet.br_T", defaults::kMagnetBr_T, 0, 10, "T", "remanence Br = mu0*M0", true),
      real_key("magnet.mu_r", defaults::kMagnetMuR, 1, 1e6, "", "recoil permeability of the magnet (FEM only)"),
      real_key("magnet.magnetization_deg", 0.0, -360, 360, "deg",
               "direction of M in the xy plane of the magnet frame"),
      real_key("magnet.magnetization_elevation_deg", 0.0, -90, 90, "deg",
               "elevation of M out of the xy plane: M = M0 (cos el cos az, cos el sin az, sin el)"),
      string_key("magnet.pattern", "uniform", {"uniform", "radial", "axial_multipole", "radial_multipole"},
                 "magnetization pattern: uniform (the direction keys), radial (M0 e_rho), axial_multipole or "
                 "radial_multipole (+-M0 e_z or e_rho on 2 pole_pairs sectors, a north pole centred on phi = 0)"),
      int_key("magnet.pole_pairs", 1, 0, 100000, "pole pairs p of a multipole pattern (>= 1 with one)"),
      real_key("magnet.pole_edge_sigma_deg", 0.0, 0, 30, "deg",
               "pole errors: each sector boundary of a multipole pattern shifted by a normal draw of this sigma"),
      real_key("magnet.pole_amplitude_sigma", 0.0, 0, 0.3, "",
               "pole errors: relative M0 of each sector of a multipole pattern, 1 + a normal draw of this sigma"),
      int_key("magnet.pole_seed", 1, 0, 2147483647, "seed of the pole errors"),
  };
}

}  // namespace magenc
