#include "probe/multipole_ring_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {
constexpr int kMaxQuarterSamples = 256;

// Chebyshev points of the first kind on [-1, 1] (n of them), and the matrix V(k, i) = T_i(x_k) whose
// inverse maps values at them to coefficients.
std::vector<double> chebyshev_points(int n) {
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) x[std::size_t(k)] = std::cos(kPi * (2.0 * k + 1.0) / (2.0 * n));
  return x;
}
Eigen::MatrixXd chebyshev_matrix(const std::vector<double>& x, int n) {
  Eigen::MatrixXd V(static_cast<Eigen::Index>(x.size()), n);
  std::vector<double> t(static_cast<std::size_t>(n));
  for (std::size_t k = 0; k < x.size(); ++k) {
    chebyshev_values(x[k], n, t.data());
    for (int i = 0; i < n; ++i) V(static_cast<Eigen::Index>(k), i) = t[std::size_t(i)];
  }
  return V;
}
}  // namespace

void MultipoleRingModel::check_ideal(const Magnet& magnet) {
  if (!magnet.is_multipole())
    throw InputError("magnet.pattern = " + pattern_name(magnet.pattern) +
                     ": the multipole engine reads a multipole ring: allowed axial_multipole, radial_multipole");
  if (magnet.pole_edge_sigma_deg != 0.0 || magnet.pole_amplitude_sigma != 0.0)
    throw InputError("magnet.pole_edge_sigma_deg = " + num(magnet.pole_edge_sigma_deg) +
                     ", magnet.pole_amplitude_sigma = " + num(magnet.pole_amplitude_sigma) +
                     ": the multipole engine models an ideal ring: allowed 0 (pole errors need the exact field)");
}

MultipoleRingModel::MultipoleRingModel(const FieldSource& field, int pole_pairs, double r0_mm, double plane_z_mm,
                                       double reach_rho_mm, double reach_z_mm, double tol_rel, double field_z_offset_mm)
    : p_(pole_pairs), r0_mm_(r0_mm), plane_z_mm_(plane_z_mm), reach_rho_mm_(reach_rho_mm), reach_z_mm_(reach_z_mm),
      z_offset_mm_(field_z_offset_mm) {
  if (pole_pairs < 1) throw InputError("pole_pairs = " + std::to_string(pole_pairs) + " is out of range: allowed >= 1");
  if (!(reach_rho_mm > 0) || !(reach_z_mm > 0) || !(reach_rho_mm < r0_mm))
    throw InputError("multipole model reach rho " + num(reach_rho_mm) + " mm, z " + num(reach_z_mm) +
                     " mm is out of range: allowed 0 < reach, reach rho < r0 = " + num(r0_mm) + " mm");
  if (!(tol_rel > 0) || !(tol_rel < 1e-3))
    throw InputError("multipole model tolerance " + num(tol_rel) + " is out of range: allowed (0, 1e-3)");
  const std::vector<double> xr = chebyshev_points(nr_), xz = chebyshev_points(nz_);
  std::vector<double> rho(xr.size()), z(xz.size());
  for (std::size_t i = 0; i < xr.size(); ++i) rho[i] = r0_mm + reach_rho_mm * xr[i];
  for (std::size_t j = 0; j < xz.size(); ++j) z[j] = plane_z_mm + reach_z_mm * xz[j];
  // 1. Q: the quarter-period samples that resolve the harmonics at the box's lower and upper faces.
  const std::vector<double> faces = {plane_z_mm - reach_z_mm, plane_z_mm + reach_z_mm};
  for (;;) {
    const Eigen::MatrixXd a = node_amplitudes(field, {r0_mm}, faces, q_);
    const double a1 = std::max(std::abs(a(0, 0)), std::abs(a(0, 1)));
    const double top = std::max(a.row(q_ - 1).cwiseAbs().maxCoeff(), a.row(q_ - 2).cwiseAbs().maxCoeff());
    if (!(a1 > 0)) throw ComputeError("multipole model: the field's first harmonic at r0 = " + num(r0_mm) + " mm is 0");
    sign_ = std::abs(a(0, 0)) >= std::abs(a(0, 1)) ? 1.0 : -1.0;  // (the lower face's A_1 larger: decays upwards)
    if (top <= tol_rel * a1 || q_ >= kMaxQuarterSamples) break;
    q_ *= 2;
  }
  // 2. The amplitudes at every node of the (rho, z) grid (column i + nr j).
  const Eigen::MatrixXd A = node_amplitudes(field, rho, z, q_);
  // 3. Harmonics kept, the decay taken out, the Chebyshev coefficients of each.
  const double a1max = A.row(0).cwiseAbs().maxCoeff();
  int H = 1;
  for (int l = 0; l < q_; ++l)
    if (A.row(l).cwiseAbs().maxCoeff() > tol_rel * a1max) H = l + 1;
  const Eigen::MatrixXd Vr_inv = chebyshev_matrix(xr, nr_).inverse(), Vz_inv = chebyshev_matrix(xz, nz_).inverse();
  coef_.resize(std::size_t(H));
  for (int l = 0; l < H; ++l) {
    Eigen::MatrixXd G(nr_, nz_);
    for (int j = 0; j < nz_; ++j)
      for (int i = 0; i < nr_; ++i) G(i, j) = A(l, i + nr_ * j) / decay(l, z[std::size_t(j)]);
    coef_[std::size_t(l)] = Vr_inv * G * Vz_inv.transpose();
  }
  Eigen::MatrixXd c;
  amplitudes_at_z(plane_z_mm, c);
  std::vector<double> t(static_cast<std::size_t>(nr_));
  chebyshev_values(0.0, nr_, t.data());
  amplitude_T_ = std::abs(Eigen::Map<const Eigen::VectorXd>(t.data(), nr_).dot(c.col(0)));
  check_misfit(field);
}

double MultipoleRingModel::decay(int l, double z_mm) const {
  return std::exp(-sign_ * (2 * l + 1) * p_ / r0_mm_ * (z_mm - plane_z_mm_));
}

Eigen::MatrixXd MultipoleRingModel::node_amplitudes(const FieldSource& field, const std::vector<double>& rho,
                                                    const std::vector<double>& z, int q) {
  const auto nr = static_cast<Eigen::Index>(rho.size()), nz = static_cast<Eigen::Index>(z.size());
  Eigen::Matrix3Xd pts(3, nr * nz * q);
  for (Eigen::Index j = 0; j < nz; ++j)
    for (Eigen::Index i = 0; i < nr; ++i)
      for (int k = 0; k < q; ++k) {
        const double phi = kPi * (2.0 * k + 1.0) / (4.0 * q * p_);
        pts.col((i + nr * j) * q + k) << rho[std::size_t(i)] * std::cos(phi), rho[std::size_t(i)] * std::sin(phi),
            z[std::size_t(j)] - z_offset_mm_;
      }
  const Eigen::VectorXd b = field.Bz_T(pts);
  field_evaluations_ += static_cast<long>(pts.cols());
  if (!b.allFinite()) throw ComputeError("multipole model: field " + field.name() + " returned a non-finite Bz near r0 = " + num(r0_mm_) + " mm");
  // DCT-IV: A_{2l+1} = (2/Q) sum_k b_k cos((2l+1)(2k+1) pi / (4Q)).
  Eigen::MatrixXd D(q, q);
  for (int l = 0; l < q; ++l)
    for (int k = 0; k < q; ++k) D(l, k) = 2.0 / q * std::cos(kPi * (2.0 * l + 1.0) * (2.0 * k + 1.0) / (4.0 * q));
  const Eigen::Map<const Eigen::MatrixXd> B(b.data(), q, nr * nz);
  return D * B;
}

void MultipoleRingModel::check_misfit(const FieldSource& field) {
  // rho and z between the nodes and on the faces; azimuths spread over a pole pair (not the samples').
  std::vector<double> xr = {-1.0, 1.0}, xz = {-1.0, 1.0};
  const std::vector<double> cr = chebyshev_points(nr_), cz = chebyshev_points(nz_);
  for (int k = 0; k + 1 < nr_; ++k) xr.push_back(0.5 * (cr[std::size_t(k)] + cr[std::size_t(k + 1)]));
  for (int k = 0; k + 1 < nz_; ++k) xz.push_back(0.5 * (cz[std::size_t(k)] + cz[std::size_t(k + 1)]));
  const double az[3] = {0.137, 0.389, 0.871};  // fractions of a pole pair
  Eigen::Matrix3Xd pts(3, static_cast<Eigen::Index>(xr.size() * xz.size() * 3));
  Eigen::Index c = 0;
  for (double u : xr)
    for (double v : xz)
      for (double f : az) {
        const double rho = r0_mm_ + reach_rho_mm_ * u, phi = 2.0 * kPi * (f + 0.05 * u * v) / p_ + 2.0 * kPi * double(c % 7) / 7;
        pts.col(c++) << rho * std::cos(phi), rho * std::sin(phi), plane_z_mm_ + reach_z_mm_ * v - z_offset_mm_;
      }
  const Eigen::VectorXd b = field.Bz_T(pts);
  field_evaluations_ += static_cast<long>(pts.cols());
  misfit_T_ = 0;
  for (Eigen::Index k = 0; k < pts.cols(); ++k) {
    const double rho = std::hypot(pts(0, k), pts(1, k)), phi = std::atan2(pts(1, k), pts(0, k));
    misfit_T_ = std::max(misfit_T_, std::abs(bz_T(rho, phi, pts(2, k) + z_offset_mm_) - b[k]));
  }
}

void MultipoleRingModel::amplitudes_at_z(double z_mm, Eigen::MatrixXd& c) const {
  const double v = (z_mm - plane_z_mm_) / reach_z_mm_;
  if (!(std::abs(v) <= 1.0 + 1e-9))
    throw InputError("a probe height " + num(z_mm) + " mm is off the multipole model's reach z_s +- " +
                     num(reach_z_mm_) + " mm (z_s = " + num(plane_z_mm_) + " mm): allowed |mount.dz_mm| <= the reach");
  std::vector<double> t(static_cast<std::size_t>(nz_));
  chebyshev_values(std::clamp(v, -1.0, 1.0), nz_, t.data());
  const Eigen::Map<const Eigen::VectorXd> tz(t.data(), nz_);
  c.resize(nr_, harmonics());
  for (int l = 0; l < harmonics(); ++l) c.col(l) = decay(l, z_mm) * (coef_[std::size_t(l)] * tz);
}

double MultipoleRingModel::bz_T(double rho_mm, double phi_rad, double z_mm) const {
  Eigen::MatrixXd c;
  amplitudes_at_z(z_mm, c);
  std::vector<double> t(static_cast<std::size_t>(nr_));
  chebyshev_values((rho_mm - r0_mm_) / reach_rho_mm_, nr_, t.data());
  const Eigen::Map<const Eigen::VectorXd> tr(t.data(), nr_);
  double b = 0;
  for (int l = 0; l < harmonics(); ++l) b += tr.dot(c.col(l)) * std::cos((2.0 * l + 1.0) * p_ * phi_rad);
  return b;
}

}  // namespace magenc
