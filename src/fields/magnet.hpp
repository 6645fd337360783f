// The diametrically magnetized cylindrical magnet (or ring: inner radius Ri > 0) and the sensing plane
// (docs/physics.md). Magnet frame: axis z, centre at the origin, top face z = +L/2.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/defaults.hpp"

namespace magenc {

// magnet.pattern (docs/physics.md "Multipole rings and nonius"): the uniform magnet of the azimuth and
// elevation keys; M = M0 e_rho everywhere (radial); s(phi) M0 e_z or s(phi) M0 e_rho with s = +-1 on the
// 2p sectors of p pole pairs (a north pole centred on phi = 0).
enum class MagnetPattern { Uniform, Radial, AxialMultipole, RadialMultipole };
std::string pattern_name(MagnetPattern p);

struct Magnet {
  double radius_mm = defaults::kMagnetRadius_mm;  // R (outer radius of a ring)
  double inner_radius_mm = 0.0;                   // Ri: a ring (bore of air) when > 0; 0 <= Ri < R
  double height_mm = defaults::kMagnetHeight_mm;  // L
  double br_T = defaults::kMagnetBr_T;            // remanence Br = mu0*M0 (tesla)
  double mu_r = defaults::kMagnetMuR;             // recoil permeability (FEM only)
  double magnetization_deg = 0.0;  // azimuth beta of M0 (direction in the xy plane)
  // Elevation al of M0 out of the xy plane (docs/physics.md, "Beyond the five offsets"):
  // M = M0 (cos al cos beta, cos al sin beta, sin al).
  double magnetization_elevation_deg = 0.0;
  MagnetPattern pattern = MagnetPattern::Uniform;
  int pole_pairs = 1;                 // p of the multipole patterns (>= 1)
  double pole_edge_sigma_deg = 0.0;   // each sector boundary shifted by a seeded normal draw (deg)
  double pole_amplitude_sigma = 0.0;  // relative M0 of each sector: 1 + a seeded normal draw
  long pole_seed = 1;                 // seed of the pole errors

  bool is_uniform() const { return pattern == MagnetPattern::Uniform; }
  bool is_multipole() const {
    return pattern == MagnetPattern::AxialMultipole || pattern == MagnetPattern::RadialMultipole;
  }

  double top_z_mm() const { return 0.5 * height_mm; }
  bool is_ring() const { return inner_radius_mm > 0.0; }
  // The magnet's material holds p (surface included): Ri <= r <= R and |z| <= L/2.
  bool contains_mm(double x_mm, double y_mm, double z_mm) const;
  // The remanence vector Br = mu0*M0 (T) inside the magnet: br_T (cos al cos beta, cos al sin beta, sin al),
  // with cos al, sin al exactly 1, 0 at al = 0.
  Eigen::Vector3d remanence_T() const;
  // Throws InputError for non-positive sizes / Br, Ri outside [0, R), mu_r < 1, |elevation| > 90, NaN; for a
  // non-uniform pattern: pole_pairs < 1 (multipole), a magnetization azimuth or elevation other than 0,
  // negative pole-error sigmas or an amplitude sigma >= 1.
  void validate() const;
  static Magnet from_config(const Config& cfg);
  // The [magnet] keys from_config reads: geometry, remanence, mu_r, magnetization direction.
  static std::vector<KeySpec> keys();
};

// Height of the sensing plane in the magnet frame: z_s = L/2 + h.
double sensing_plane_z_mm(const Config& cfg);

}  // namespace magenc
