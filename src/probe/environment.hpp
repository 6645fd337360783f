// The world around the encoder (docs/physics.md "Environment: stray fields and temperature").
//   * Stray fields live in the fixed (machine) frame and do not turn with the rotor: a uniform
//     vector (stray.uniform_mT) and an infinite straight conductor (stray.wire_current_A through
//     stray.wire_point_mm along stray.wire_direction):
//       B = (mu0 I / 2 pi) (u x r_perp) / |r_perp|^2,  mu0 / 2 pi = 0.2 mT mm / A,
//     r_perp the part of (p - point) normal to u. They add to the magnet's field at every probe
//     point before the sensor reads it. The sensor is fixed, so each probe (or the in-plane spot)
//     sees the same stray field at every rotor angle: its reading gains a constant.
//   * Temperature T (environment.temperature_C, reference 20 C): the magnet's field scales with
//     Br(T) = Br (1 + magnet.br_tc_per_K (T - 20)) (any field source: its field is scaled); the
//     channel offsets drift by sensor.offset_cos_tc_uT_per_K, sensor.offset_sin_tc_uT_per_K (T - 20)
//     (bz, inplane: offsets in mT); the air gap by mount.dz_tc_um_per_K (T - 20).
//   * magnet.material names a material of the library below; it sets the coefficient unless
//     magnet.br_tc_per_K differs from its default (a key at its default is not "set").
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/config.hpp"
#include "probe/mounting.hpp"
#include "probe/sensor.hpp"
#include "probe/signal_chain.hpp"

namespace magenc {

inline constexpr double kReferenceTemperature_C = 20.0;  // Br, offsets and the gap are given at 20 C
inline constexpr double kMu0Over2Pi_mTmm_per_A = 0.2;    // mu0 / 2 pi in mT mm / A
inline constexpr double kWireClearance_mm = 1e-6;        // a conductor may not pass closer to a probe point

struct StrayField {
  Eigen::Vector3d uniform_mT = Eigen::Vector3d::Zero();        // homogeneous field, fixed frame
  double wire_current_A = 0;                                   // conductor current (0: no conductor)
  Eigen::Vector3d wire_point_mm = Eigen::Vector3d::Zero();     // a point of the conductor, fixed frame
  Eigen::Vector3d wire_direction = Eigen::Vector3d::UnitY();   // its direction (any length > 0)

  // Reads stray.uniform_mT, stray.wire_current_A, stray.wire_point_mm, stray.wire_direction.
  static StrayField from_config(const Config& cfg);
  // The [stray] keys from_config reads.
  static std::vector<KeySpec> keys();
  bool active() const { return uniform_mT.squaredNorm() > 0 || wire_current_A != 0; }
  // Finite vectors and current, a non-zero direction (InputError naming the key).
  void validate() const;
  // The stray field (mT, fixed frame) at a fixed-frame point (mm). InputError when the point lies
  // within kWireClearance_mm of the conductor (a conductor through a probe point).
  Eigen::Vector3d B_mT(const Eigen::Vector3d& p_fixed_mm) const;
};

// The field of an infinite straight conductor (mT) at p (mm): current I (A) through `point` along
// the unit vector u. No clearance check (the caller's).
Eigen::Vector3d wire_field_mT(double current_A, const Eigen::Vector3d& point_mm, const Eigen::Vector3d& u,
                              const Eigen::Vector3d& p_mm);

// A permanent-magnet material of the library: the reversible temperature coefficient of Br and
// where the number comes from.
struct MagnetMaterial {
  std::string name;       // magnet.material value
  std::string label;      // readable name
  double br_tc_per_K = 0; // alpha(Br), 1/K
  std::string source;     // where the coefficient comes from
};
// The library (sintered NdFeB, SmCo, hard ferrite, bonded NdFeB).
const std::vector<MagnetMaterial>& magnet_materials();
// The material named `name`; InputError naming magnet.material and the allowed names otherwise.
const MagnetMaterial& magnet_material(const std::string& name);

struct Environment {
  StrayField stray;
  double temperature_C = kReferenceTemperature_C;  // environment.temperature_C
  double br_tc_per_K = -0.0012;                     // magnet.br_tc_per_K (or the material's)
  double offset_cos_tc_uT_per_K = 0;                // sensor.offset_cos_tc_uT_per_K
  double offset_sin_tc_uT_per_K = 0;                // sensor.offset_sin_tc_uT_per_K
  double dz_tc_um_per_K = 0;                        // mount.dz_tc_um_per_K

  // Reads the keys above; magnet.material sets br_tc_per_K unless magnet.br_tc_per_K is changed.
  static Environment from_config(const Config& cfg);
  // The temperature keys from_config reads (environment.temperature_C and the drifts of Br, the
  // channel offsets and the air gap); the stray field's are StrayField::keys().
  static std::vector<KeySpec> keys();
  // Finite values, temperature in [-273.15, 1000] C, Br(T) > 0, the stray field valid; the offset
  // drifts only on principles with offsets in mT (InputError naming the key).
  void validate_for(SensorPrinciple p) const;
  double delta_T_K() const { return temperature_C - kReferenceTemperature_C; }
  // Br(T) / Br(20 C) = 1 + tc (T - 20).
  double br_scale() const { return 1.0 + br_tc_per_K * delta_T_K(); }
  // Nothing to do: no stray field and the reference temperature (outputs as without environment).
  bool neutral() const { return !stray.active() && delta_T_K() == 0.0; }
  // The mount at T: dz + dz_tc (T - 20).
  Mount mount_at_temperature(const Mount& m) const;
  // The signal chain at T: offsets + tc (T - 20) (uT -> mT).
  SignalChain chain_at_temperature(const SignalChain& c) const;
};

// What the stray field adds to the readings of a fixed sensor (the same at every rotor angle), tesla:
// bz: one value per probe, n.B_stray averaged over the probe's sensing area (n = Rs z); in-plane
// principles: two values, x'.B_stray and y'.B_stray averaged over the spot's area (x' = Rs x,
// y' = Rs y). probes_xy_mm: the nominal sensor-frame probe positions (the die centre for the spot).
std::vector<double> stray_readings_T(const StrayField& stray, const MountKinematics& kin,
                                     const std::vector<Eigen::Vector2d>& probes_xy_mm, const SensingArea& area,
                                     bool in_plane);

}  // namespace magenc
