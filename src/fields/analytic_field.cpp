#include "fields/analytic_field.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

const std::vector<AnalyticField::NodeTable>& AnalyticField::node_tables() {
  static const std::vector<NodeTable> tables = [] {
    std::vector<NodeTable> all;
    for (int base = kMinNodes; base <= kMaxNodes; base *= 2) {
      for (int n : {base, base + base / 2}) {
        if (n > kMaxNodes) break;
        NodeTable t;
        t.n = n;
        t.cos_phi.resize(n);
        t.sin_phi.resize(n);
        for (int j = 0; j < n; ++j) {  // midpoint nodes phi'_j = (j + 1/2) 2 pi / n
          const double phi = (j + 0.5) * 2.0 * kPi / n;
          t.cos_phi[j] = std::cos(phi);
          t.sin_phi[j] = std::sin(phi);
        }
        all.push_back(std::move(t));
      }
    }
    return all;
  }();
  return tables;
}

AnalyticField::AnalyticField(const Magnet& magnet) : magnet_(magnet), tables_(&node_tables()) {
  magnet_.validate();
  const double alpha_rad = deg_to_rad(magnet_.magnetization_deg);
  cos_alpha_ = std::cos(alpha_rad);
  sin_alpha_ = std::sin(alpha_rad);
}

bool AnalyticField::inside_or_on_magnet(const Vec3& p) const {
  return std::hypot(p.x(), p.y()) <= magnet_.radius_mm && std::abs(p.z()) <= magnet_.top_z_mm();
}

const AnalyticField::NodeTable& AnalyticField::table_for(double r_mm, double z_mm) const {
  const double R = magnet_.radius_mm, half = magnet_.top_z_mm();
  // Distance (in z) to the nearer face plane: the integrands (with the rho = 0
  // pole removed beside the magnet) are singular only where rho^2 = -t_i^2.
  const double tmin = std::min(std::abs(z_mm - half), std::abs(z_mm + half));
  if (!(r_mm > 0)) return tables_->front();  // on the axis: integrand ~ constant * cos(phi')
  const double c = (r_mm * r_mm + R * R + tmin * tmin) / (2.0 * r_mm * R);
  const double a = std::acosh(std::max(c, 1.0));
  // The phi' integral cancels to ~R/r of its integrand's size far away: ask for more.
  const double need = kQuadratureExponent + std::max(0.0, std::log(r_mm / R));
  for (const auto& t : *tables_)
    if (t.n * a >= need) return t;
  return tables_->back();
}

int AnalyticField::nodes_at(const Vec3& p) const {
  return table_for(std::hypot(p.x(), p.y()), p.z()).n;
}

namespace {
// I(x, y) = Int_0^{2pi} cos(phi') (x - R cos phi', y - R sin phi') / rho^2 dphi'
// (1/mm), the field of a cos(phi')-charged circle in 2-D (a uniformly
// polarized infinite cylinder): inside (r < R) I = -pi/R x_hat, outside
// I = pi R / r^2 (2 (x_hat . r_hat) r_hat - x_hat).
Eigen::Vector2d two_d_dipole_integral(double x, double y, double R) {
  const double r2 = x * x + y * y;
  if (r2 < R * R) return {-kPi / R, 0.0};
  const double k = kPi * R / r2;
  return {k * (2.0 * x * x / r2 - 1.0), k * (2.0 * x * y / r2)};
}
}  // namespace

double AnalyticField::Bz_aligned_T(double x, double y, double z) const {
  const double R = magnet_.radius_mm, L = magnet_.height_mm;
  const double t1 = z - 0.5 * L, t2 = z + 0.5 * L;
  const double t1sq = t1 * t1, t2sq = t2 * t2;
  const NodeTable& tab = table_for(std::hypot(x, y), z);
  const double* __restrict cphi = tab.cos_phi.data();
  const double* __restrict sphi = tab.sin_phi.data();
  const int n = tab.n;
  double acc = 0.0;
#pragma omp simd reduction(+ : acc)
  for (int j = 0; j < n; ++j) {
    const double dx = x - R * cphi[j], dy = y - R * sphi[j];
    const double rho2 = dx * dx + dy * dy;
    const double s1 = std::sqrt(rho2 + t1sq), s2 = std::sqrt(rho2 + t2sq);
    // 1/s1 - 1/s2 = (t2^2 - t1^2)/(s1 s2 (s1 + s2)) = 2 z L/(s1 s2 (s1 + s2))
    acc += cphi[j] / (s1 * s2 * (s1 + s2));
  }
  const double weight = 2.0 * kPi / n;
  return magnet_.br_T * R / (4.0 * kPi) * weight * (2.0 * z * L) * acc;
}

Vec3 AnalyticField::B_aligned_T(double x, double y, double z) const {
  const double R = magnet_.radius_mm, L = magnet_.height_mm;
  const double t1 = z - 0.5 * L, t2 = z + 0.5 * L;
  const double a1 = std::abs(t1), a2 = std::abs(t2);
  const double t1sq = t1 * t1, t2sq = t2 * t2;
  const NodeTable& tab = table_for(std::hypot(x, y), z);
  const double* __restrict cphi = tab.cos_phi.data();
  const double* __restrict sphi = tab.sin_phi.data();
  const int n = tab.n;
  double acc_x = 0.0, acc_y = 0.0, acc_z = 0.0;
  if (t1 * t2 >= 0) {
    // Above or below the magnet's slab: g = L*N/D without cancellation.
#pragma omp simd reduction(+ : acc_x, acc_y, acc_z)
    for (int j = 0; j < n; ++j) {
      const double dx = x - R * cphi[j], dy = y - R * sphi[j];
      const double rho2 = dx * dx + dy * dy;
      const double s1 = std::sqrt(rho2 + t1sq), s2 = std::sqrt(rho2 + t2sq);
      const double inv12 = 1.0 / (s1 + s2);
      const double num = a1 + a2 + s2 + a1 * (a1 + a2) * inv12;
      const double g = num / (s1 * s2 * (s1 + a1) * (s2 + a2));  // times L below
      acc_x += cphi[j] * dx * g;
      acc_y += cphi[j] * dy * g;
      acc_z += cphi[j] / (s1 * s2) * inv12;
    }
    acc_x *= L;
    acc_y *= L;
  } else {
    // Beside the magnet (|z| < L/2): g = (a1/s1 + a2/s2)/rho^2 has a pole at
    // rho = 0 (the curved face). Split g = 2/rho^2 + gr with the regular part
    // gr = -[1/(s1 (s1 + a1)) + 1/(s2 (s2 + a2))]; the pole part integrates in
    // closed form (2-D field of a cos-charged circle, see two_d_dipole_integral).
#pragma omp simd reduction(+ : acc_x, acc_y, acc_z)
    for (int j = 0; j < n; ++j) {
      const double dx = x - R * cphi[j], dy = y - R * sphi[j];
      const double rho2 = dx * dx + dy * dy;
      const double s1 = std::sqrt(rho2 + t1sq), s2 = std::sqrt(rho2 + t2sq);
      const double gr = -(1.0 / (s1 * (s1 + a1)) + 1.0 / (s2 * (s2 + a2)));
      acc_x += cphi[j] * dx * gr;
      acc_y += cphi[j] * dy * gr;
      acc_z += cphi[j] / (s1 * s2 * (s1 + s2));
    }
    const double weight = 2.0 * kPi / n;
    const Eigen::Vector2d I = two_d_dipole_integral(x, y, R);
    acc_x += 2.0 * I.x() / weight;  // the sums below are multiplied by the weight
    acc_y += 2.0 * I.y() / weight;
  }
  const double pref = magnet_.br_T * R / (4.0 * kPi) * (2.0 * kPi / n);
  return {pref * acc_x, pref * acc_y, pref * (2.0 * z * L) * acc_z};
}

Vec3 AnalyticField::B_T(const Vec3& p) const {
  // Rotate the point into the frame where M0 is along +x, evaluate, rotate back.
  const double xa = cos_alpha_ * p.x() + sin_alpha_ * p.y();
  const double ya = -sin_alpha_ * p.x() + cos_alpha_ * p.y();
  const Vec3 Ba = B_aligned_T(xa, ya, p.z());
  Vec3 B(cos_alpha_ * Ba.x() - sin_alpha_ * Ba.y(), sin_alpha_ * Ba.x() + cos_alpha_ * Ba.y(), Ba.z());
  if (std::hypot(p.x(), p.y()) < magnet_.radius_mm && std::abs(p.z()) < magnet_.top_z_mm()) {
    B.x() += magnet_.br_T * cos_alpha_;  // B = mu0 (H + M0) inside
    B.y() += magnet_.br_T * sin_alpha_;
  }
  return B;
}

double AnalyticField::Bz_T(const Vec3& p) const {
  const double xa = cos_alpha_ * p.x() + sin_alpha_ * p.y();
  const double ya = -sin_alpha_ * p.x() + cos_alpha_ * p.y();
  return Bz_aligned_T(xa, ya, p.z());
}

Eigen::Matrix3Xd AnalyticField::B_T(const Eigen::Matrix3Xd& p_mm) const {
  Eigen::Matrix3Xd out(3, p_mm.cols());
  const Eigen::Index n = p_mm.cols();
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index i = 0; i < n; ++i) out.col(i) = B_T(Vec3(p_mm.col(i)));
  return out;
}

Eigen::VectorXd AnalyticField::Bz_T(const Eigen::Matrix3Xd& p_mm) const {
  Eigen::VectorXd out(p_mm.cols());
  const Eigen::Index n = p_mm.cols();
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index i = 0; i < n; ++i) out[i] = Bz_T(Vec3(p_mm.col(i)));
  return out;
}

}  // namespace magenc
