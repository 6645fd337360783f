// The default magnet and sensing geometry (docs/physics.md, the reference encoder): one home for the
// values that the config keys' defaults (Magnet::keys(), sensor_keys(), Mount::keys()) and the default members and arguments of the
// types that carry them (Magnet, ProbeSetup, the mounting kinematics, the radius scan) share.
#pragma once

namespace magenc::defaults {

inline constexpr double kMagnetRadius_mm = 2.0;  // R
inline constexpr double kMagnetHeight_mm = 4.0;  // L (axis z, centred at 0)
inline constexpr double kMagnetBr_T = 1.2;       // remanence Br = mu0*M0
inline constexpr double kMagnetMuR = 1.05;       // recoil permeability (FEM only)
inline constexpr double kPlaneHeight_mm = 2.55;  // sensing plane height h above the magnet's top face
inline constexpr double kProbeRadius_mm = 2.4;   // nominal probe radius r0
// Sanity bound (mm) on every length key: the magnet, sensor and mount keys' allowed ranges.
inline constexpr double kMaxLength_mm = 1000.0;
// Sensing plane height in the magnet frame, z_s = L/2 + h = 4.55 mm (sensing_plane_z_mm of the defaults).
inline constexpr double kPlaneZ_mm = 0.5 * kMagnetHeight_mm + kPlaneHeight_mm;
static_assert(kPlaneZ_mm == 4.55, "z_s of the default geometry");

}  // namespace magenc::defaults
