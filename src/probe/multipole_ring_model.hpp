// MultipoleRingModel: the field of an ideal multipole ring around a read circle in the terms of its
// symmetry, the surrogate of the Monte Carlo engine's multipole reading (probe/multipole_pipeline.hpp;
// docs/physics.md "Multipole rings and nonius", docs/multipole.md "The Monte Carlo engine").
//
// An ideal ring of p pole pairs (axial_multipole or radial_multipole, no pole errors; a north pole centred
// on phi = 0) has Bz(rho, phi + 360/p deg, z) = Bz(rho, phi, z), Bz(rho, phi + 180/p deg, z) = -Bz and
// Bz(rho, -phi, z) = Bz (the magnetization is invariant under those rotations and the mirror, and the field
// follows it). So, exactly,
//   Bz(rho, phi, z) = sum over odd n of A_n(rho, z) cos(n p phi),
// and the azimuth costs no model at all: a displacement along the track is a phase. Only the amplitudes
// A_n are modelled, as smooth functions of (rho, z) over the box r0 +- reach_rho, z_s +- reach_z:
//  * A_n at the (rho, z) nodes of a Chebyshev grid from Q samples of Bz over a quarter of a pole pair
//    (phi_q = (2q + 1) 90 / (2 Q p) deg, q < Q): Bz(phi_q) = sum_l A_{2l+1} cos((2l+1)(2q+1) pi / (4Q)) is a
//    DCT-IV, so A_1, A_3, .., A_{2Q-1} follow exactly (up to the aliasing of n >= 2Q + 1, which alternates
//    onto them). Q doubles from 16 (up to 256) until the highest amplitude at the lowest height is below
//    tol_rel of A_1.
//  * A_n(rho, z) = exp(-s k_n (z - z_s)) sum_ij C_n,ij T_i(rho~) T_j(z~), k_n = n p / r0 (the decay of a
//    pattern of that period, s = +1 when the field decays upwards), T the Chebyshev polynomials of the
//    scaled coordinates rho~ = (rho - r0) / reach_rho, z~ = (z - z_s) / reach_z, interpolating the nodes.
//  * Harmonics are kept while their largest amplitude on the grid exceeds tol_rel of A_1's.
// Build: (rho nodes x z nodes x Q) field evaluations, plus the check below; no fits per theta node.
// misfit_T(): the largest |model - exact Bz| at check points off the grid (rho and z between the nodes and
// on the box's faces, several azimuths per point): interpolation, truncation and aliasing together, and a
// field without the ideal ring's symmetry (pole errors) shows here.
#pragma once
#include <vector>

#include <Eigen/Core>

#include "fields/field_source.hpp"
#include "fields/magnet.hpp"

namespace magenc {

class MultipoleRingModel {
 public:
  // field: the exact field of the ring, pole_pairs p >= 1; r0_mm: the read circle, plane_z_mm its height
  // (the read head's magnet frame); reach_rho_mm, reach_z_mm: the largest radial and vertical displacement
  // of a probe the model must serve (> 0); tol_rel: the harmonics' and Q's truncation (relative to A_1);
  // field_z_offset_mm: the ring's centre above the frame's origin (a nonius ring: nonius.z_offset_mm; the
  // field is evaluated at z - offset). InputError for values out of range.
  MultipoleRingModel(const FieldSource& field, int pole_pairs, double r0_mm, double plane_z_mm, double reach_rho_mm,
                     double reach_z_mm, double tol_rel = 1e-9, double field_z_offset_mm = 0.0);
  // InputError unless `magnet` is an ideal multipole ring (axial_multipole or radial_multipole, no pole
  // errors), naming the keys.
  static void check_ideal(const Magnet& magnet);

  int pole_pairs() const { return p_; }
  double r0_mm() const { return r0_mm_; }
  double plane_z_mm() const { return plane_z_mm_; }
  double reach_rho_mm() const { return reach_rho_mm_; }
  double reach_z_mm() const { return reach_z_mm_; }
  // Odd harmonics kept (n = 1, 3, .., 2 harmonics() - 1).
  int harmonics() const { return static_cast<int>(coef_.size()); }
  // Chebyshev nodes per axis (rho, z) and the quarter-period samples Q of the build.
  int rho_nodes() const { return nr_; }
  int z_nodes() const { return nz_; }
  int quarter_samples() const { return q_; }
  long field_evaluations() const { return field_evaluations_; }
  double misfit_T() const { return misfit_T_; }
  // |A_1| at (r0, z_s) (T).
  double amplitude_T() const { return amplitude_T_; }

  // The amplitudes at height z_mm as Chebyshev series in rho~: c(i, l) is the coefficient of T_i of
  // A_{2l+1} (rho_nodes() x harmonics()). InputError when z_mm is off the box.
  void amplitudes_at_z(double z_mm, Eigen::MatrixXd& c) const;
  // The model's Bz (T) at (rho, phi, z) in the box (tests; the pipeline evaluates in bulk).
  double bz_T(double rho_mm, double phi_rad, double z_mm) const;

 private:
  // The grid's samples at the nodes: A (harmonics x (rho node, z node)) from the DCT-IV of Q azimuths.
  Eigen::MatrixXd node_amplitudes(const FieldSource& field, const std::vector<double>& rho,
                                  const std::vector<double>& z, int q);
  double decay(int l, double z_mm) const;
  void check_misfit(const FieldSource& field);

  int p_ = 1;
  double r0_mm_ = 0, plane_z_mm_ = 0, reach_rho_mm_ = 0, reach_z_mm_ = 0;
  int nr_ = 10, nz_ = 8, q_ = 16;
  double sign_ = 1;                       // +1: the field decays with z
  double z_offset_mm_ = 0;                // the field's frame: the ring's centre at this z
  std::vector<Eigen::MatrixXd> coef_;     // per harmonic l: C (rho nodes x z nodes) of T_i(rho~) T_j(z~)
  long field_evaluations_ = 0;
  double misfit_T_ = 0, amplitude_T_ = 0;
};

// T_0(x) .. T_{n-1}(x) into t.
inline void chebyshev_values(double x, int n, double* t) {
  t[0] = 1.0;
  if (n > 1) t[1] = x;
  for (int i = 2; i < n; ++i) t[i] = 2.0 * x * t[i - 1] - t[i - 2];
}

}  // namespace magenc
