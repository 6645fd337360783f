#include "probe/environment.hpp"

#include <cmath>

#include "core/errors.hpp"

namespace magenc {

namespace {

Eigen::Vector3d vector3(const Config& cfg, const std::string& key) {
  const std::vector<double> v = cfg.reals(key);
  if (v.size() != 3)
    throw InputError(key + " has " + std::to_string(v.size()) + " elements: allowed 3 ([x, y, z])");
  return {v[0], v[1], v[2]};
}

std::string vec_text(const Eigen::Vector3d& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]";
}

void require_finite(const Eigen::Vector3d& v, const std::string& key, const std::string& unit) {
  if (!v.allFinite())
    throw InputError(key + " = " + vec_text(v) + " is not finite: allowed three finite values in " + unit);
}

// The declared default of a real key (a key the schema lacks: NaN).
double default_real(const Config& cfg, const std::string& key) {
  const KeySpec* s = cfg.find(key);
  return s ? std::stod(s->default_value) : std::nan("");
}

}  // namespace

StrayField StrayField::from_config(const Config& cfg) {
  StrayField s;
  s.uniform_mT = vector3(cfg, "stray.uniform_mT");
  s.wire_current_A = cfg.real("stray.wire_current_A");
  s.wire_point_mm = vector3(cfg, "stray.wire_point_mm");
  s.wire_direction = vector3(cfg, "stray.wire_direction");
  s.validate();
  return s;
}

void StrayField::validate() const {
  require_finite(uniform_mT, "stray.uniform_mT", "mT");
  if (!std::isfinite(wire_current_A))
    throw InputError("stray.wire_current_A = " + num(wire_current_A) + " is not finite: allowed a finite current in A");
  require_finite(wire_point_mm, "stray.wire_point_mm", "mm");
  require_finite(wire_direction, "stray.wire_direction", "(any unit)");
  if (!(wire_direction.norm() > 0))
    throw InputError("stray.wire_direction = " + vec_text(wire_direction) +
                     " is the zero vector: allowed a non-zero direction of the conductor");
}

Eigen::Vector3d wire_field_mT(double current_A, const Eigen::Vector3d& point_mm, const Eigen::Vector3d& u,
                              const Eigen::Vector3d& p_mm) {
  const Eigen::Vector3d r = p_mm - point_mm;
  const Eigen::Vector3d r_perp = r - u.dot(r) * u;
  return kMu0Over2Pi_mTmm_per_A * current_A * u.cross(r_perp) / r_perp.squaredNorm();
}

Eigen::Vector3d StrayField::B_mT(const Eigen::Vector3d& p_fixed_mm) const {
  Eigen::Vector3d B = uniform_mT;
  if (wire_current_A == 0) return B;
  const Eigen::Vector3d u = wire_direction.normalized();
  const Eigen::Vector3d r = p_fixed_mm - wire_point_mm;
  const double dist_mm = (r - u.dot(r) * u).norm();
  if (!(dist_mm > kWireClearance_mm))
    throw InputError("stray.wire_point_mm = " + vec_text(wire_point_mm) + " with stray.wire_direction = " +
                     vec_text(wire_direction) + " passes " + num(dist_mm) + " mm from the probe point " +
                     vec_text(p_fixed_mm) + " mm: allowed a conductor farther than " + num(kWireClearance_mm) +
                     " mm from every probe point");
  return B + wire_field_mT(wire_current_A, wire_point_mm, u, p_fixed_mm);
}

const std::vector<MagnetMaterial>& magnet_materials() {
  // Reversible temperature coefficients of Br near room temperature. Each is the typical value of its
  // class in the manufacturers' datasheets named (grades differ by a few 0.01 %/K).
  static const std::vector<MagnetMaterial> all = {
      {"ndfeb_sintered", "sintered NdFeB", -0.0012,
       "Arnold Magnetic Technologies, sintered Neodymium-Iron-Boron magnets, grade N42 datasheet: "
       "reversible temperature coefficient of Br -0.12 %/C"},
      {"smco", "sintered SmCo (Sm2Co17)", -0.00035,
       "Arnold Magnetic Technologies, RECOMA 28 (Sm2Co17) datasheet: reversible temperature "
       "coefficient of Br -0.035 %/C"},
      {"ferrite_hard", "hard ferrite (sintered Sr/Ba ferrite)", -0.002,
       "TDK, ferrite magnets FB series catalogue: temperature coefficient of Br -0.18 to -0.20 %/C "
       "(-0.20 %/C taken)"},
      {"ndfeb_bonded", "bonded NdFeB (MQP-B powder)", -0.0013,
       "Magnequench (Neo Performance Materials), MQP-B powder datasheet: reversible temperature "
       "coefficient of Br -0.13 %/C"},
  };
  return all;
}

const MagnetMaterial& magnet_material(const std::string& name) {
  std::string allowed;
  for (const auto& m : magnet_materials()) {
    if (m.name == name) return m;
    allowed += (allowed.empty() ? "" : ", ") + m.name;
  }
  throw InputError("magnet.material = '" + name + "' is not a material of the library: allowed none, " + allowed);
}

Environment Environment::from_config(const Config& cfg) {
  Environment e;
  e.stray = StrayField::from_config(cfg);
  e.temperature_C = cfg.real("environment.temperature_C");
  e.br_tc_per_K = cfg.real("magnet.br_tc_per_K");
  const std::string material = cfg.str("magnet.material");
  if (material != "none" && e.br_tc_per_K == default_real(cfg, "magnet.br_tc_per_K"))
    e.br_tc_per_K = magnet_material(material).br_tc_per_K;
  else if (material != "none")
    (void)magnet_material(material);  // named, even when the explicit coefficient wins
  e.offset_cos_tc_uT_per_K = cfg.real("sensor.offset_cos_tc_uT_per_K");
  e.offset_sin_tc_uT_per_K = cfg.real("sensor.offset_sin_tc_uT_per_K");
  e.dz_tc_um_per_K = cfg.real("mount.dz_tc_um_per_K");
  return e;
}

void Environment::validate_for(SensorPrinciple p) const {
  stray.validate();
  if (!(std::isfinite(temperature_C) && temperature_C >= -273.15 && temperature_C <= 1000))
    throw InputError("environment.temperature_C = " + num(temperature_C) + " is out of range: allowed [-273.15, 1000] C");
  if (!std::isfinite(br_tc_per_K))
    throw InputError("magnet.br_tc_per_K = " + num(br_tc_per_K) + " is not finite: allowed [-0.01, 0.01] 1/K");
  if (!(br_scale() > 0))
    throw InputError("magnet.br_tc_per_K = " + num(br_tc_per_K) + " at environment.temperature_C = " +
                     num(temperature_C) + " gives Br(T)/Br = " + num(br_scale()) +
                     ": allowed a coefficient and temperature with Br(T) > 0");
  const std::pair<const char*, double> drifts[] = {{"sensor.offset_cos_tc_uT_per_K", offset_cos_tc_uT_per_K},
                                                   {"sensor.offset_sin_tc_uT_per_K", offset_sin_tc_uT_per_K},
                                                   {"mount.dz_tc_um_per_K", dz_tc_um_per_K}};
  for (const auto& [key, v] : drifts)
    if (!std::isfinite(v)) throw InputError(std::string(key) + " = " + num(v) + " is not finite: allowed a finite drift");
  if (relative_offsets(p))
    for (std::size_t i = 0; i < 2; ++i)
      if (drifts[i].second != 0)
        throw InputError(std::string(drifts[i].first) + " = " + num(drifts[i].second) +
                         " does not apply to sensor.principle = " + principle_name(p) +
                         ": allowed 0 (xmr/amr channels have unit amplitude; their offsets are relative)");
}

Mount Environment::mount_at_temperature(const Mount& m) const {
  Mount out = m;
  if (dz_tc_um_per_K != 0) out.dz_mm += 1e-3 * dz_tc_um_per_K * delta_T_K();
  return out;
}

SignalChain Environment::chain_at_temperature(const SignalChain& c) const {
  SignalChain out = c;
  if (offset_cos_tc_uT_per_K != 0) out.offset_cos_mT += 1e-3 * offset_cos_tc_uT_per_K * delta_T_K();
  if (offset_sin_tc_uT_per_K != 0) out.offset_sin_mT += 1e-3 * offset_sin_tc_uT_per_K * delta_T_K();
  return out;
}

std::vector<double> stray_readings_T(const StrayField& stray, const MountKinematics& kin,
                                     const std::vector<Eigen::Vector2d>& probes_xy_mm, const SensingArea& area,
                                     bool in_plane) {
  std::vector<double> u, v, w;
  area.nodes(u, v, w);
  std::vector<double> out;
  for (const Eigen::Vector2d& c : probes_xy_mm) {
    Eigen::Vector3d mean_mT = Eigen::Vector3d::Zero();
    for (std::size_t q = 0; q < w.size(); ++q)
      mean_mT += w[q] * stray.B_mT(kin.fixed_position_mm(c.x() + u[q], c.y() + v[q]));
    if (in_plane) {
      out.push_back(1e-3 * kin.Rs.col(0).dot(mean_mT));
      out.push_back(1e-3 * kin.Rs.col(1).dot(mean_mT));
    } else {
      out.push_back(1e-3 * kin.n_fixed.dot(mean_mT));
    }
  }
  return out;
}

std::vector<KeySpec> StrayField::keys() {
  return {
      // Environment: stray fields and temperature (docs/physics.md "Environment"; probe/environment.hpp).
      real_list_key("stray.uniform_mT", {0, 0, 0}, -1e4, 1e4, "mT",
                    "uniform stray field [Bx, By, Bz] in the fixed frame, added at every probe (1 kA/m = 1.257 mT)",
                    false, 3),
      real_key("stray.wire_current_A", 0.0, -1e6, 1e6, "A",
               "current of an infinite straight conductor (0 = none): B = 0.2 mT mm/A I (u x r)/|r|^2"),
      real_list_key("stray.wire_point_mm", {0, 0, 0}, -1e6, 1e6, "mm",
                    "a point [x, y, z] of the conductor, fixed frame (magnet frame at rest)", false, 3),
      real_list_key("stray.wire_direction", {0, 1, 0}, -1e6, 1e6, "",
                    "direction [ux, uy, uz] of the conductor (and of its current); any non-zero length", false, 3),
  };
}

std::vector<KeySpec> Environment::keys() {
  return {
      real_key("environment.temperature_C", 20.0, -273.15, 1000, "C",
               "temperature: Br(T) = Br (1 + magnet.br_tc_per_K (T - 20)), offset and air-gap drifts from 20 C"),
      real_key("magnet.br_tc_per_K", -0.0012, -0.01, 0.01, "1/K",
               "reversible temperature coefficient of Br (set by magnet.material unless changed from its default)"),
      string_key("magnet.material", "none", {"none", "ndfeb_sintered", "smco", "ferrite_hard", "ndfeb_bonded"},
                 "magnet material of the library (docs/physics.md): sets magnet.br_tc_per_K; none = the key's value"),
      real_key("sensor.offset_cos_tc_uT_per_K", 0.0, -1e4, 1e4, "uT/K",
               "drift of the cos channel offset with temperature (bz, inplane), from 20 C"),
      real_key("sensor.offset_sin_tc_uT_per_K", 0.0, -1e4, 1e4, "uT/K",
               "drift of the sin channel offset with temperature (bz, inplane), from 20 C"),
      real_key("mount.dz_tc_um_per_K", 0.0, -1e3, 1e3, "um/K",
               "air-gap drift with temperature (thermal growth of shaft and housing), from 20 C; + = farther"),
  };
}

}  // namespace magenc
