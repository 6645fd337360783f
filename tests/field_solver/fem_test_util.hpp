// Shared helpers of the FEM tests: small, fast domains.
#pragma once
#include "field_solver/mesh/geometry.hpp"

namespace magenc::fem::test {

// Default magnet (R 2, L 4, Br 1.2 T) with mu_r = 1, sensing plane z_s = 4.55 mm,
// a small refinement zone (|x|,|y| <= 3.5, 4.0 <= z <= 5.1) and a 40 mm sphere.
inline DomainSpec coarse_domain(double h_zone_mm, double h_magnet_mm = 1.0, int segments = 32) {
  DomainSpec d;
  d.magnet.mu_r = 1.0;
  d.mesh.segments = segments;
  d.mesh.h_magnet_mm = h_magnet_mm;
  d.mesh.h_zone_mm = h_zone_mm;
  d.mesh.h_air_mm = 15.0;
  d.mesh.outer_radius_mm = 40.0;
  d.zone.half_width_mm = 3.5;
  d.zone.z_min_mm = 4.0;
  d.zone.z_max_mm = 5.1;
  // The test meshes as they were before MeshSpec took the [mesh] keys' defaults:
  d.mesh.symmetry_order = 2;            // mirror planes x = 0, y = 0 only
  d.mesh.mesher.min_dihedral_deg = 10;  // TetGen's -q angle of the coarse meshes
  return d;
}

inline constexpr double kPlaneZ = magenc::defaults::kPlaneZ_mm;  // z_s of the default magnet (mm)

}  // namespace magenc::fem::test
