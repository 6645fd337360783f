// AxisymmetricTableField: an axisymmetric field source (FieldSource::axisymmetric_parts(), the exact
// cylinder or ring) served from tables in (r, z) instead of its own quadrature at every point.
//
// Why it is exact to the table's tolerance: for a body axisymmetric about z with B linear in M,
//   B(Rz(phi) q; M) = Rz(phi) B(q; Rz(-phi) M),   q = (r, 0, z),
// so B anywhere follows from the parts B_x, B_y, B_z (magnetized along x, y, z) on the half plane
// y = 0, r >= 0. There the mirror y -> -y leaves only five components: B_x = (Fxx, 0, Fxz),
// B_y = (0, Fyy, 0), B_z = (Fzx, 0, Fzz) (the others vanish by symmetry; the quadrature gives them as
// ~1e-17 T round-off). Each is an analytic function of (r, z) outside the magnet, tabulated here on
// square patches of side patch_mm as tensor Chebyshev interpolants of `order` points per side.
//
// Patches are built when a point first needs them (thread-safe; the content does not depend on which
// thread builds it, so results are reproducible). Every patch is checked when it is built: the
// interpolant against the parts at four points off the nodes; if any component differs by more than
// tol_rel times the patch's largest component, or the patch comes within one patch side of the magnet's
// body (r, z rectangle) or lies in the far field, the patch is marked direct and its points are evaluated
// by the source itself. So the table differs from the source by at most ~tol_rel (measured in
// tests/fields/test_axisym_table_field.cpp against direct evaluation; the check points are a sample, not a
// bound).
#pragma once
#include <cstdint>
#include <memory>
#include <shared_mutex>
#include <unordered_map>

#include "fields/field_source.hpp"

namespace magenc {

class AxisymmetricTableField final : public FieldSource {
 public:
  // source: must declare axisymmetric_parts() and exact_magnet() (InputError otherwise).
  explicit AxisymmetricTableField(FieldSourcePtr source, double patch_mm = 0.02, int order = 7,
                                  double tol_rel = 1e-12);
  std::string name() const override { return source_->name(); }
  Vec3 B_T(const Vec3& p_mm) const override;
  double Bz_T(const Vec3& p_mm) const override;
  using FieldSource::B_T;
  using FieldSource::Bz_T;
  bool gives_full_vector() const override { return source_->gives_full_vector(); }
  const Magnet* exact_magnet() const override { return source_->exact_magnet(); }
  std::optional<AxisymmetricParts> axisymmetric_parts() const override { return source_->axisymmetric_parts(); }

  // Patches built so far, and how many of them serve their points directly (failed the check or too near
  // the magnet).
  long patches() const;
  long direct_patches() const;

 private:
  struct Patch;
  // The patch holding (r, z), built on first use; nullptr when the point is served directly.
  const Patch* patch_at(double r_mm, double z_mm) const;
  std::shared_ptr<const Patch> build(std::int64_t i, std::int64_t j) const;
  // The five components at (r, 0, z) from the patch (Fxx, Fxz, Fyy, Fzx, Fzz).
  void components(const Patch& pa, double r_mm, double z_mm, double* f, bool bz_only) const;

  FieldSourcePtr source_;
  AxisymmetricParts parts_;
  bool axial_ = false;  // m has a z component: B_z is needed
  double patch_mm_, tol_rel_;
  int order_;
  double mag_R_ = 0, mag_half_ = 0, far_mm_ = 0;
  std::uint64_t id_ = 0;  // unique per instance (the per-thread patch cache's key)
  mutable std::shared_mutex mutex_;
  mutable std::unordered_map<std::int64_t, std::shared_ptr<const Patch>> table_;
};

}  // namespace magenc
