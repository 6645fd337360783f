// Exact field of a uniformly, diametrically magnetized cylinder (physics.md):
// surface charge sigma = M0*cos(phi' - alpha) on the curved face, z' integrated
// in closed form, the remaining periodic phi' integral by the midpoint rule,
// whose node count adapts to the point's distance from the magnet's rims so
// that the quadrature error stays below ~1e-12 relative. Inside the magnet B
// includes mu0*M0 (B = mu0*(H + M0)).
#pragma once
#include "field_source.hpp"
#include "magnet.hpp"

namespace magenc {

class AnalyticField final : public FieldSource {
 public:
  explicit AnalyticField(const Magnet& magnet);
  std::string name() const override { return "analytic"; }
  Vec3 B_T(const Vec3& p_mm) const override;
  double Bz_T(const Vec3& p_mm) const override;
  using FieldSource::B_T;
  using FieldSource::Bz_T;
  const Magnet& magnet() const { return magnet_; }

 private:
  Magnet magnet_;
};

// Linear model of the study: Bz = k*x (k = 1 T/mm; it cancels in atan2),
// Bx = By = 0.
class LinearField final : public FieldSource {
 public:
  explicit LinearField(double k_T_per_mm = 1.0) : k_(k_T_per_mm) {}
  std::string name() const override { return "linear"; }
  Vec3 B_T(const Vec3& p_mm) const override { return {0.0, 0.0, k_ * p_mm.x()}; }
  double Bz_T(const Vec3& p_mm) const override { return k_ * p_mm.x(); }
  using FieldSource::B_T;
  using FieldSource::Bz_T;

 private:
  double k_;
};

}  // namespace magenc
