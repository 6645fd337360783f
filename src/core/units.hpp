// magenc units policy (stated once, here).
//
// * Lengths are millimetres everywhere in the library and at every interface
//   (configs, CLI flags, CSV, VTK coordinates). Names carry the unit: r0_mm.
// * Angles are degrees at interfaces (configs, CSV, plots) and radians inside
//   numerical kernels; names carry the unit (theta_deg, theta_rad).
// * Flux density B is tesla (B_T, Bz_T); Br (remanence) is tesla: Br = mu0*M0.
// * The FEM works with the reduced scalar potential in "tesla-millimetre"
//   scaled units: psi_Tmm = mu0*phi_m [T*mm], so H*mu0 = -grad psi in tesla
//   when the gradient is taken in 1/mm. mu0 never appears numerically.
#pragma once
#include <numbers>

namespace magenc {
inline constexpr double kPi = std::numbers::pi;
inline constexpr double deg_to_rad(double deg) { return deg * kPi / 180.0; }
inline constexpr double rad_to_deg(double rad) { return rad * 180.0 / kPi; }
}  // namespace magenc
