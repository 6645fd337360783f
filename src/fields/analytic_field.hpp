// Exact field of a uniformly, diametrically magnetized cylinder (docs/physics.md):
// surface charge sigma = M0*cos(phi' - alpha) on the curved face, z' integrated
// in closed form, the remaining periodic phi' integral by the midpoint rule,
// whose node count adapts to the point's distance from the magnet's rims so
// that the quadrature error stays below ~1e-12 relative. Inside the magnet B
// includes mu0*M0 (B = mu0*(H + M0)).
//
// Kernel (magnet frame, magnetization rotated onto +x, lengths in mm):
//   B(x) = Br*R/(4*pi) * Int_0^{2pi} cos(phi') * K(x, phi') dphi'
//   Kz  = 1/s1 - 1/s2 = 2*z*L / (s1*s2*(s1+s2))            (cancellation free)
//   Kxy = (x - R cos phi', y - R sin phi') * g,
//   g   = [t/(rho^2*sqrt(rho^2+t^2))]_{t1}^{t2},  t1 = z - L/2, t2 = z + L/2,
//   s_i = sqrt(rho^2 + t_i^2), rho^2 = (x - R cos phi')^2 + (y - R sin phi')^2.
// g is evaluated without cancellation: for t1*t2 >= 0 (point above or below
// the magnet's slab) g = L*N/D with N = a1+a2+s2+a1*(a1+a2)/(s1+s2),
// D = s1*s2*(s1+a1)*(s2+a2), a_i = |t_i|. Beside the magnet (t1 < 0 < t2)
// g = (a1/s1 + a2/s2)/rho^2 has a pole on the curved face (rho = 0); it is
// split as g = 2/rho^2 + gr, gr = -[1/(s1(s1+a1)) + 1/(s2(s2+a2))] regular,
// and the 2/rho^2 part is integrated in closed form (2-D field of a
// cos-charged circle: -pi/R x_hat inside, pi R/r^2 (2 (x_hat.r_hat) r_hat - x_hat)
// outside).
//
// Node count: after that split every integrand is analytic in phi' in a strip
// of half-width a = acosh((r^2 + R^2 + t_min^2)/(2 r R)) about the real axis,
// set by the nearest complex zero of rho^2 + t_i^2 (t_min = distance in z to
// the nearer face plane, r = the point's distance from the axis). The
// midpoint rule then errs like exp(-N*a); N is the smallest tabulated count
// with N*a >= kQuadratureExponent (+ log(r/R) for the far-field
// cancellation), capped at kMaxNodes: only points within ~36 R / kMaxNodes
// ~ 1 um of a rim circle (where a -> 0) get less than ~1e-12 relative accuracy.
//
// Far away (beyond kFarFieldRadius = 500 magnet sizes) B is the exterior multipole expansion of the body, dipole
// and quadrupole (finite for any finite point; the quadrature cancels to ~R/r of its integrand's size).
//
// Ring magnets (magnet.inner_radius_mm = Ri > 0): B_ring = B_cyl(R) - B_cyl(Ri), two exact cylinder fields
// of the same polarization (the bore's cylinder is a second AnalyticField). Inside the material the
// first adds mu0*M0 and the second does not; in the bore both add it and it cancels. Ri = 0 evaluates the
// cylinder alone, the same operations as before rings existed.
//
// Magnetization elevation el (magnet.magnetization_elevation_deg): M = M0 (cos el
// cos beta, cos el sin beta, sin el). The diametric part is the kernel above
// scaled by cos el; the axial part M0 sin el (charges +-M0 sin el on the top and
// bottom faces, equivalently a surface current M0 sin el phi_hat on the curved
// face) is integrated over z' in closed form too, leaving phi' integrals on the
// same nodes (B_aligned_parts_T); an independent closed form with complete
// elliptic integrals (B_axial_closed_form_T) cross-checks it in the tests.
#pragma once
#include <memory>
#include <vector>

#include "fields/field_source.hpp"
#include "fields/magnet.hpp"

namespace magenc {

class AnalyticField final : public FieldSource {
 public:
  explicit AnalyticField(const Magnet& magnet);
  std::string name() const override { return "analytic"; }
  Vec3 B_T(const Vec3& p_mm) const override;
  double Bz_T(const Vec3& p_mm) const override;
  // Batch versions: p_mm 3xN (mm) -> 3xN / N (T); OpenMP parallel.
  Eigen::Matrix3Xd B_T(const Eigen::Matrix3Xd& p_mm) const override;
  Eigen::VectorXd Bz_T(const Eigen::Matrix3Xd& p_mm) const override;
  const Magnet& magnet() const { return magnet_; }
  const Magnet* exact_magnet() const override { return &magnet_; }
  // The cylinder is axisymmetric and B is linear in M: m = the remanence direction, B_k = the field
  // of this magnet magnetized along x (azimuth 0), y (azimuth 90 deg), z (elevation 90 deg).
  std::optional<AxisymmetricParts> axisymmetric_parts() const override;

  // True when p_mm lies inside the magnet's material or on its surface (Ri <= r <= R, |z| <= L/2).
  bool inside_or_on_magnet(const Vec3& p_mm) const;
  // Number of midpoint nodes the quadrature uses at p_mm for the outer cylinder (tests, benchmarks; a
  // ring evaluates the bore's cylinder too, with its own count).
  int nodes_at(const Vec3& p_mm) const;
  // Field of the axial magnetization alone with |M| = M0 (elevation 90 deg), total B
  // (inside too), by an independent closed form: the finite solenoid with complete
  // elliptic integrals (Bulirsch's cel). A cross-check of the quadrature (tests); the
  // field itself uses the quadrature, which shares its nodes with the diametric part.
  // For a ring, the outer cylinder's closed form minus the bore's.
  Vec3 B_axial_closed_form_T(const Vec3& p_mm) const;
  double Bz_axial_closed_form_T(const Vec3& p_mm) const { return B_axial_closed_form_T(p_mm).z(); }

  static constexpr double kQuadratureExponent = 36.0;  // exp(-36) ~ 2e-16
  // Beyond kFarFieldRadius times the magnet's larger size a = max(R, L/2) from its centre, B is the
  // exterior multipole expansion (dipole and quadrupole terms), finite at any finite distance. Measured
  // (tests/fields/test_field_at.cpp) the two differ by the omitted ~(a/r)^4 term, 4.4e-8 at 100 a falling
  // as r^-4, until the quadrature's own cancellation error takes over (1.2e-10 at 600 a, 8.7e-10 at
  // 1000 a); at 500 a both are ~1e-10.
  static constexpr double kFarFieldRadius = 500.0;
  // True beyond that radius; the expansion itself (tests compare it with the quadrature).
  bool in_far_field(const Vec3& p_mm) const;
  Vec3 multipole_B_T(const Vec3& p_mm) const;
  static constexpr int kMinNodes = 16;
  static constexpr int kMaxNodes = 65536;

 private:
  // Midpoint nodes phi'_j = (j + 1/2)*2*pi/N: cos and sin tables (unit circle).
  struct NodeTable {
    int n = 0;
    std::vector<double> cos_phi, sin_phi;
  };
  // Node table for a point at distance r_mm from the axis and height z_mm.
  const NodeTable& table_for(double r_mm, double z_mm) const;
  // The node ladder 16, 24, 32, 48, ..., kMaxNodes (multiples of 8), built once
  // per process (immutable; shared by all instances, thread-safe initialization).
  static const std::vector<NodeTable>& node_tables();
  // The solid cylinder of radius R (the ring's outer cylinder), total B.
  Vec3 cylinder_B_T(const Vec3& p_mm) const;
  double cylinder_Bz_T(const Vec3& p_mm) const;
  // Field in the frame where M0 is along +x (no interior Br term).
  Vec3 B_aligned_T(double x_mm, double y_mm, double z_mm) const;
  double Bz_aligned_T(double x_mm, double y_mm, double z_mm) const;
  Vec3 B_axial_closed_form_T(double x_mm, double y_mm, double z_mm) const;
  double Bz_axial_closed_form_T(double x_mm, double y_mm, double z_mm) const;
  // Diametric part (M0 along +x, no interior term) and, with kAxial, the axial
  // part (unit M0 along +z, total B) from the same quadrature nodes.
  template <bool kAxial>
  void B_aligned_parts_T(double x_mm, double y_mm, double z_mm, Vec3& B_diametric, Vec3& B_axial) const;
  void Bz_aligned_parts_T(double x_mm, double y_mm, double z_mm, double& bz_diametric, double& bz_axial) const;

  Magnet magnet_;
  double cos_alpha_ = 1, sin_alpha_ = 0;  // azimuth of M0 in the magnet frame
  double cos_el_ = 1, sin_el_ = 0;        // elevation of M0 (exactly 1, 0 when it is 0)
  Vec3 br_inside_T_ = Vec3::Zero();       // Magnet::remanence_T()
  const std::vector<NodeTable>* tables_;   // node_tables(), increasing node counts
  std::shared_ptr<const AnalyticField> bore_;  // the cylinder of radius Ri (rings only), subtracted
};

// Linear model of the study: Bz = k*x (k = 1 T/mm; it cancels in atan2),
// Bx = By = 0. It models Bz on the sensing plane only (Bx = By = 0 and no z
// dependence are not a magnetic field: curl B != 0), so it does not serve
// tilted probes (gives_full_vector() is false).
class LinearField final : public FieldSource {
 public:
  explicit LinearField(double k_T_per_mm = 1.0) : k_(k_T_per_mm) {}
  std::string name() const override { return "linear"; }
  bool gives_full_vector() const override { return false; }
  Vec3 B_T(const Vec3& p_mm) const override { return {0.0, 0.0, k_ * p_mm.x()}; }
  double Bz_T(const Vec3& p_mm) const override { return k_ * p_mm.x(); }
  using FieldSource::B_T;
  using FieldSource::Bz_T;

 private:
  double k_;
};

}  // namespace magenc
