// Exact field of the non-uniform magnetization patterns (docs/physics.md "Multipole rings and nonius"):
// magnet.pattern = radial, axial_multipole or radial_multipole, a ring (Ri > 0) or a disk (Ri = 0).
//
// The magnet is a set of sectors phi_a <= phi' < phi_b, each magnetized with the signed amplitude q
// (s = +-1 times 1 + the seeded amplitude error) along e_z (axial) or e_rho (radial). Its charges:
//   axial sector:  +q M0 on the top annular-sector face, -q M0 on the bottom one;
//   radial sector: +q M0 on the outer curved face, -q M0 on the bore's (none for a disk), and the volume
//                  charge -q M0 / rho'; the side faces carry none (M.n = 0 there).
// H = 1/(4 pi) Int sigma (x - x')/|x - x'|^3 dA (+ the volume term), B = mu0 H (+ mu0 M in the material).
//
// Per sector, everything but the azimuth phi' is integrated in closed form (lengths in mm, the point
// x = (x, y, z) at r = |(x, y)|; a node phi' has c = cos phi', s = sin phi', u = x c + y s the point's
// component along e_rho(phi'), pp = -x s + y c across it, v = rho' - u):
//   end face at z0 (t = z - z0, w^2 = pp^2 + t^2, D = sqrt(v^2 + w^2)), Int rho' (x - x')/D^3 drho':
//     K = (u v - w^2)/(w^2 D), J = ln(v + D) - v/D - u/D (rho'^2 and rho' v terms)
//     H_z += t K,  H_xy += pp K (-s, c) - J (c, s)                                    [v]_{Ri - u}^{R - u}
//   curved face of radius a (rho^2 = (a - u)^2 + pp^2, tau_{1,2} = z -+ L/2, S_i = sqrt(rho^2 + tau_i^2)):
//     H_z += a (1/S_1 - 1/S_2),  H_xy += a (x - a c, y - a s) [tau/(rho^2 S)]_{tau_1}^{tau_2}
//     (the bracket without cancellation: f_i = 1/(S_i (S_i + |tau_i|)) gives f_1 - f_2 above the slab,
//     f_2 - f_1 below, 2/rho^2 - f_1 - f_2 beside it);
//   volume (rho^2 = v^2 + pp^2, S_i as above, w_i^2 = pp^2 + tau_i^2), - Int drho' Int dz' (x - x')/D^3:
//     H_z  -= [ln(v + S_1) - ln(v + S_2)]
//     H_xy -= (-s, c) [sgn(pp) sgn(tau) atan2(|tau| v, |pp| S)]_{tau_1}^{tau_2}
//             - (c, s) [sgn(tau) (ln(rho)  - ln(S + |tau|))]_{tau_1}^{tau_2}             [v]_{Ri - u}^{R - u}
//   (ln(v + S) as ln(w^2/(S - v)) for v < 0).
// The remaining phi' integral of each sector runs by 16-point Gauss-Legendre on equal panels. Off the
// material every integrand is analytic in phi' except at phi' = phi +- i y, y >= y0 = acosh(1 + d^2 /
// (2 r R)) (d: the point's distance from the magnet's cross-section in the (rho, z) half-plane); a sector
// is split into the fewest panels whose Bernstein ellipse through the nearest such point has rho_B >= 3
// (the rule's error then below ~ 3^-32 ~ 5e-16 of the integrand's scale). Sectors far from the point's
// azimuth take one panel: a 2p-sector ring costs about 2p sector evaluations of 16 nodes, a few more
// panels only near the point. Inside the material or on its surfaces (d = 0) the panels are capped
// (kMaxPanelsPerSector) and the accuracy is lower; sensors never sit there.
#pragma once
#include <string>
#include <vector>

#include "fields/field_source.hpp"
#include "fields/magnet.hpp"

namespace magenc {

struct MagnetSector {
  double phi_a_rad = 0, phi_b_rad = 0;  // phi_a <= phi' < phi_b, phi_b - phi_a <= 2 pi
  double q = 1;                         // signed relative amplitude (M = q M0 e_z or q M0 e_rho)
};

// The sectors of a magnet's pattern with its seeded pole errors: one sector [0, 2 pi) for radial; 2p for
// the multipole patterns, sector j on [(-90 + 180 j)/p, (-90 + 180 (j + 1))/p) deg with q = (-1)^j, each
// boundary shifted by a normal draw of pole_edge_sigma_deg (boundary 2p is boundary 0), each amplitude
// times 1 + a normal draw of pole_amplitude_sigma (mt19937_64 seeded with pole_seed: the 2p edge draws
// first, then the 2p amplitude draws). Throws for the uniform pattern.
std::vector<MagnetSector> pattern_sectors(const Magnet& magnet);

class MultipoleField final : public FieldSource {
 public:
  // The pattern's sectors (pattern_sectors).
  explicit MultipoleField(const Magnet& magnet);
  // Given sectors (tests: e.g. all q = +1 is the uniform axial or radial magnet); the magnet gives the
  // body, Br and whether the sectors are axial (axial_multipole) or radial (radial, radial_multipole).
  MultipoleField(const Magnet& magnet, std::vector<MagnetSector> sectors);

  std::string name() const override { return "analytic"; }
  Vec3 B_T(const Vec3& p_mm) const override;
  // Bz alone: the same nodes without the in-plane terms (an axial pattern's logarithms are skipped).
  double Bz_T(const Vec3& p_mm) const override;
  using FieldSource::B_T;
  using FieldSource::Bz_T;
  const Magnet* exact_magnet() const override { return &magnet_; }
  const std::vector<MagnetSector>& sectors() const { return sectors_; }
  // Gauss-Legendre nodes the field at p_mm uses (all sectors; tests, benchmarks).
  int nodes_at(const Vec3& p_mm) const;

  static constexpr int kNodesPerPanel = 16;
  static constexpr int kMaxPanelsPerSector = 4096;
  static constexpr double kBernsteinRho = 3.0;

 private:
  // Panels for the sector [a, b] seen from a point at azimuth phi with singularity half-distance y0.
  static int panels_for(double a, double b, double phi, double y0);
  double singularity_distance(const Vec3& p_mm) const;
  template <bool kFull>
  void add_axial_node(const Vec3& p, double c, double s, double wq, Vec3& H) const;
  template <bool kFull>
  Vec3 H_sum(const Vec3& p_mm) const;
  void add_radial_node(const Vec3& p, double c, double s, double wq, Vec3& H) const;
  // mu0 M at p (T): zero outside the material.
  Vec3 remanence_at_T(const Vec3& p_mm) const;

  Magnet magnet_;
  std::vector<MagnetSector> sectors_;
  bool axial_ = true;
};

}  // namespace magenc
