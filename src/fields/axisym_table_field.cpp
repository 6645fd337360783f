#include "fields/axisym_table_field.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "fields/magnet.hpp"

namespace magenc {

// The five components, in this order: Fxx, Fxz (B_x), Fyy (B_y), Fzx, Fzz (B_z).
struct AxisymmetricTableField::Patch {
  bool direct = true;
  double rc = 0, zc = 0, half = 0;        // centre and half side (mm)
  std::array<std::vector<double>, 5> coef;  // Chebyshev coefficients, order x order, row i (r) major
};

namespace {

constexpr int kComponents = 5;

// Chebyshev points of the first kind on [-1, 1].
double cheb_node(int j, int n) { return std::cos(kPi * (j + 0.5) / n); }

// T_0..T_{n-1} at u.
void cheb_values(double u, int n, double* t) {
  t[0] = 1.0;
  if (n > 1) t[1] = u;
  for (int k = 2; k < n; ++k) t[k] = 2.0 * u * t[k - 1] - t[k - 2];
}

// Node values (r index, z index) of the five components from the three parts' batch readings.
void component_values(const Eigen::Matrix3Xd& bx, const Eigen::Matrix3Xd& by, const Eigen::Matrix3Xd* bz, int n,
                      std::array<Eigen::MatrixXd, kComponents>& v) {
  for (auto& m : v) m.setZero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Eigen::Index c = i * n + j;
      v[0](i, j) = bx(0, c);
      v[1](i, j) = bx(2, c);
      v[2](i, j) = by(1, c);
      if (bz) {
        v[3](i, j) = (*bz)(0, c);
        v[4](i, j) = (*bz)(2, c);
      }
    }
}

}  // namespace

AxisymmetricTableField::AxisymmetricTableField(FieldSourcePtr source, double patch_mm, int order, double tol_rel)
    : source_(std::move(source)), patch_mm_(patch_mm), tol_rel_(tol_rel), order_(order) {
  static std::atomic<std::uint64_t> next_id{1};
  id_ = next_id++;
  if (!source_) throw InputError("AxisymmetricTableField: no field source");
  const auto parts = source_->axisymmetric_parts();
  const Magnet* mag = source_->exact_magnet();
  if (!parts || !mag)
    throw InputError("field '" + source_->name() + "' declares no axisymmetric parts or magnet: allowed the exact field");
  if (!(patch_mm > 0) || order < 2 || order > 32 || !(tol_rel > 0))
    throw InputError("AxisymmetricTableField: patch_mm " + num(patch_mm) + ", order " + std::to_string(order) +
                     ", tol_rel " + num(tol_rel) + ": allowed patch_mm > 0, order 2..32, tol_rel > 0");
  parts_ = *parts;
  axial_ = parts_.m.z() != 0.0;
  mag_R_ = mag->radius_mm;
  mag_half_ = mag->top_z_mm();
  far_mm_ = AnalyticField::kFarFieldRadius * std::max(mag_R_, mag_half_);
}

long AxisymmetricTableField::patches() const {
  std::shared_lock lock(mutex_);
  return static_cast<long>(table_.size());
}

long AxisymmetricTableField::direct_patches() const {
  std::shared_lock lock(mutex_);
  return static_cast<long>(std::count_if(table_.begin(), table_.end(), [](const auto& kv) { return kv.second->direct; }));
}

std::shared_ptr<const AxisymmetricTableField::Patch> AxisymmetricTableField::build(std::int64_t i, std::int64_t j) const {
  auto pa = std::make_shared<Patch>();
  const double h = patch_mm_, r0 = static_cast<double>(i) * h, z0 = static_cast<double>(j) * h;
  pa->half = 0.5 * h;
  pa->rc = r0 + pa->half;
  pa->zc = z0 + pa->half;
  // Near the body (closer than one side to its r, z rectangle) or in the far field: served directly.
  const double gap_r = std::max(0.0, r0 - mag_R_);
  const double gap_z = std::max({0.0, z0 - mag_half_, -mag_half_ - (z0 + h)});
  if (std::hypot(gap_r, gap_z) < h || std::hypot(r0 + h, std::max(std::abs(z0), std::abs(z0 + h))) >= far_mm_) return pa;
  const int n = order_;
  const auto at = [&](const std::vector<std::pair<double, double>>& rz) {
    Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(rz.size()));
    for (std::size_t k = 0; k < rz.size(); ++k) p.col(static_cast<Eigen::Index>(k)) = Vec3(rz[k].first, 0.0, rz[k].second);
    return p;
  };
  std::vector<std::pair<double, double>> nodes;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) nodes.push_back({pa->rc + pa->half * cheb_node(a, n), pa->zc + pa->half * cheb_node(b, n)});
  const Eigen::Matrix3Xd pn = at(nodes);
  const Eigen::Matrix3Xd bx = parts_.along_axis[0]->B_T(pn), by = parts_.along_axis[1]->B_T(pn);
  Eigen::Matrix3Xd bz;
  if (axial_) bz = parts_.along_axis[2]->B_T(pn);
  std::array<Eigen::MatrixXd, kComponents> v;
  component_values(bx, by, axial_ ? &bz : nullptr, n, v);
  // Coefficients C = A V A^T, A(k, j) = w_k T_k(x_j), w_0 = 1/n, w_k = 2/n.
  Eigen::MatrixXd A(n, n);
  for (int k = 0; k < n; ++k)
    for (int q = 0; q < n; ++q) A(k, q) = (k == 0 ? 1.0 : 2.0) / n * std::cos(k * kPi * (q + 0.5) / n);
  double scale = 0;
  for (int c = 0; c < kComponents; ++c) {
    const Eigen::MatrixXd C = A * v[static_cast<std::size_t>(c)] * A.transpose();
    auto& dst = pa->coef[static_cast<std::size_t>(c)];
    dst.resize(static_cast<std::size_t>(n) * n);
    for (int a = 0; a < n; ++a)
      for (int q = 0; q < n; ++q) dst[static_cast<std::size_t>(a * n + q)] = C(a, q);
    scale = std::max(scale, v[static_cast<std::size_t>(c)].cwiseAbs().maxCoeff());
  }
  // The check: four points off the nodes.
  const std::array<std::pair<double, double>, 4> uv{{{0.31, -0.47}, {-0.73, 0.22}, {0.58, 0.81}, {-0.12, -0.9}}};
  std::vector<std::pair<double, double>> chk;
  for (const auto& [u, w] : uv) chk.push_back({pa->rc + pa->half * u, pa->zc + pa->half * w});
  const Eigen::Matrix3Xd pc = at(chk);
  const Eigen::Matrix3Xd cx = parts_.along_axis[0]->B_T(pc), cy = parts_.along_axis[1]->B_T(pc);
  Eigen::Matrix3Xd cz;
  if (axial_) cz = parts_.along_axis[2]->B_T(pc);
  pa->direct = false;
  for (std::size_t k = 0; k < chk.size(); ++k) {
    double f[kComponents];
    components(*pa, chk[k].first, chk[k].second, f, false);
    const auto col = static_cast<Eigen::Index>(k);
    const double want[kComponents] = {cx(0, col), cx(2, col), cy(1, col), axial_ ? cz(0, col) : 0.0,
                                      axial_ ? cz(2, col) : 0.0};
    for (int c = 0; c < kComponents; ++c)
      if (!(std::abs(f[c] - want[c]) <= tol_rel_ * scale)) pa->direct = true;
  }
  return pa;
}

const AxisymmetricTableField::Patch* AxisymmetricTableField::patch_at(double r_mm, double z_mm) const {
  const auto i = static_cast<std::int64_t>(std::floor(r_mm / patch_mm_));
  const auto j = static_cast<std::int64_t>(std::floor(z_mm / patch_mm_));
  const std::int64_t key = (i << 32) ^ (j & 0xffffffffLL);
  // A small per-thread cache in front of the shared table (no lock on a hit): (table id, key) -> patch.
  struct Entry {
    std::uint64_t owner = 0;
    std::int64_t key = 0;
    const Patch* patch = nullptr;
  };
  thread_local std::array<Entry, 16> cache;
  Entry& e = cache[static_cast<std::size_t>((i * 7 + j) & 15)];
  if (e.owner == id_ && e.key == key) return e.patch->direct ? nullptr : e.patch;
  const Patch* found = nullptr;
  {
    std::shared_lock lock(mutex_);
    const auto it = table_.find(key);
    if (it != table_.end()) found = it->second.get();
  }
  if (!found) {
    auto built = build(i, j);  // outside the lock: another thread may build the same patch (same content)
    std::unique_lock lock(mutex_);
    found = table_.emplace(key, std::move(built)).first->second.get();
  }
  e = {id_, key, found};
  return found->direct ? nullptr : found;
}

void AxisymmetricTableField::components(const Patch& pa, double r_mm, double z_mm, double* f, bool bz_only) const {
  const int n = order_;
  double tu[32], tv[32];
  cheb_values((r_mm - pa.rc) / pa.half, n, tu);
  cheb_values((z_mm - pa.zc) / pa.half, n, tv);
  for (int c = 0; c < kComponents; ++c) {
    const bool needed = (bz_only ? (c == 1 || c == 4) : true) && (axial_ || c < 3);
    f[c] = 0.0;
    if (!needed) continue;
    const double* C = pa.coef[static_cast<std::size_t>(c)].data();
    double acc = 0.0;
    for (int i = 0; i < n; ++i) {
      double row = 0.0;
#pragma omp simd reduction(+ : row)
      for (int q = 0; q < n; ++q) row += C[i * n + q] * tv[q];
      acc += tu[i] * row;
    }
    f[c] = acc;
  }
}

Vec3 AxisymmetricTableField::B_T(const Vec3& p) const {
  const double r = std::sqrt(p.x() * p.x() + p.y() * p.y());
  if (!std::isfinite(r) || !std::isfinite(p.z())) return source_->B_T(p);
  const Patch* pa = patch_at(r, p.z());
  if (!pa) return source_->B_T(p);
  double f[kComponents];
  components(*pa, r, p.z(), f, false);
  const double c = r > 0 ? p.x() / r : 1.0, s = r > 0 ? p.y() / r : 0.0;
  const Vec3& m = parts_.m;
  const double mx = c * m.x() + s * m.y(), my = -s * m.x() + c * m.y();  // Rz(-phi) m
  const double bx = mx * f[0] + m.z() * f[3], by = my * f[2], bz = mx * f[1] + m.z() * f[4];
  return {c * bx - s * by, s * bx + c * by, bz};
}

double AxisymmetricTableField::Bz_T(const Vec3& p) const {
  const double r = std::sqrt(p.x() * p.x() + p.y() * p.y());
  if (!std::isfinite(r) || !std::isfinite(p.z())) return source_->Bz_T(p);
  const Patch* pa = patch_at(r, p.z());
  if (!pa) return source_->Bz_T(p);
  double f[kComponents];
  components(*pa, r, p.z(), f, true);
  const double c = r > 0 ? p.x() / r : 1.0, s = r > 0 ? p.y() / r : 0.0;
  const Vec3& m = parts_.m;
  return (c * m.x() + s * m.y()) * f[1] + m.z() * f[4];
}

}  // namespace magenc
