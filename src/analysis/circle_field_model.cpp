#include "analysis/circle_field_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {
constexpr int kStencil = 5;  // points per axis of the fit stencil
}  // namespace


CircleFieldModel::CircleFieldModel(const FieldSource& field, double r0_mm, double plane_z_mm, int nodes,
                                   double reach_xy_mm, double reach_z_mm, int order, bool full_vector)
    : nodes_(nodes), r0_mm_(r0_mm), plane_z_mm_(plane_z_mm), reach_xy_mm_(std::max(reach_xy_mm, 0.01)),
      reach_z_mm_(std::max(reach_z_mm, 0.01)) {
  if (nodes < 16) throw InputError("radius.fast_steps = " + std::to_string(nodes) + " is out of range: allowed >= 16");
  if (order < 2 || order > 4)
    throw InputError("radius.surrogate_order = " + std::to_string(order) + " is out of range: allowed [2, 4]");
  // 1. Monomials of total degree <= order in the scaled displacement u = e/reach.
  for (int a = 0; a <= order; ++a)
    for (int b = 0; a + b <= order; ++b)
      for (int c = 0; a + b + c <= order; ++c) exps_.push_back({a, b, c});
  const int T = terms();

  // 2. Stencil in scaled units: 5 x 5 x 5 points over [-1, 1]^3 (the centre
  //    is a stencil point, so the exact node value comes for free).
  std::vector<Eigen::Vector3d> stencil;
  int centre = -1;
  for (int i = 0; i < kStencil; ++i)
    for (int j = 0; j < kStencil; ++j)
      for (int k = 0; k < kStencil; ++k) {
        const double h = 2.0 / (kStencil - 1);
        if (i == 2 && j == 2 && k == 2) centre = static_cast<int>(stencil.size());
        stencil.emplace_back(-1 + h * i, -1 + h * j, -1 + h * k);
      }
  const int P = static_cast<int>(stencil.size());

  // 3. Least-squares operator for the non-constant terms: the constant is the
  //    exact node value (so an ideal mount reproduces the field exactly) and
  //    coef[1..T-1] = pinv(V) * (samples - centre), V = P x (T-1) monomials.
  Eigen::MatrixXd V(P, T - 1);
  for (int p = 0; p < P; ++p) {
    std::vector<double> u(T);
    monomials(stencil[p].x() * reach_xy_mm_, stencil[p].y() * reach_xy_mm_, stencil[p].z() * reach_z_mm_,
              u.data());
    for (int t = 1; t < T; ++t) V(p, t - 1) = u[t];
  }
  const Eigen::MatrixXd pinv = V.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(P, P));  // (T-1) x P

  // 4. Sample the field: 3 x (P*N) points, one batch call (OpenMP inside).
  Eigen::Matrix3Xd pts(3, static_cast<Eigen::Index>(P) * nodes_);
  for (int j = 0; j < nodes_; ++j) {
    const double phi = 2.0 * kPi * j / nodes_;
    const double x0 = r0_mm * std::cos(phi), y0 = r0_mm * std::sin(phi);
    for (int p = 0; p < P; ++p)
      pts.col(static_cast<Eigen::Index>(j) * P + p) =
          Eigen::Vector3d(x0 + stencil[p].x() * reach_xy_mm_, y0 + stencil[p].y() * reach_xy_mm_,
                          plane_z_mm + stencil[p].z() * reach_z_mm_);
  }
  Eigen::Matrix3Xd B;
  if (full_vector) {
    if (!field.gives_full_vector())
      throw InputError("field " + field.name() + " gives only Bz on a plane: tilts in the tolerance box "
                       "(radius.tol_tilt_x_deg, tol_tilt_y_deg, tol_magnet_tilt_deg) need the full field vector: "
                       "allowed 0 for this field");
    B = field.B_T(pts);
    if (!B.allFinite()) throw ComputeError("field " + field.name() + " returned a non-finite B near r0 = " + num(r0_mm) + " mm");
  }
  const Eigen::VectorXd bz = full_vector ? Eigen::VectorXd(B.row(2).transpose()) : field.Bz_T(pts);
  if (!bz.allFinite()) throw ComputeError("field " + field.name() + " returned a non-finite Bz near r0 = " + num(r0_mm) + " mm");
  const Eigen::Map<const Eigen::MatrixXd> samples(bz.data(), P, nodes_);  // column j = node j

  // 5. Fit, residual, exact node values and the first angular harmonic.
  center_T_ = samples.row(centre).transpose();
  const Eigen::MatrixXd rel = samples - Eigen::VectorXd::Ones(P) * center_T_.transpose();
  coef_.resize(T, nodes_);
  coef_.row(0) = center_T_.transpose();
  coef_.bottomRows(T - 1) = pinv * rel;
  fit_residual_T_ = (V * coef_.bottomRows(T - 1) - rel).cwiseAbs().maxCoeff();
  if (full_vector) {
    // Bx and By: the same least-squares operator, constant term = the exact node value.
    for (int c = 0; c < 2; ++c) {
      const Eigen::VectorXd bc = B.row(c).transpose();
      const Eigen::Map<const Eigen::MatrixXd> sc(bc.data(), P, nodes_);
      const Eigen::VectorXd centre_c = sc.row(centre).transpose();
      const Eigen::MatrixXd rel_c = sc - Eigen::VectorXd::Ones(P) * centre_c.transpose();
      Eigen::MatrixXd& coef = c == 0 ? coef_x_ : coef_y_;
      coef.resize(T, nodes_);
      coef.row(0) = centre_c.transpose();
      coef.bottomRows(T - 1) = pinv * rel_c;
      fit_residual_T_ = std::max(fit_residual_T_, (V * coef.bottomRows(T - 1) - rel_c).cwiseAbs().maxCoeff());
    }
  }
  double re = 0, im = 0;
  for (int j = 0; j < nodes_; ++j) {
    const double phi = 2.0 * kPi * j / nodes_;
    re += center_T_[j] * std::cos(phi);
    im += center_T_[j] * std::sin(phi);
  }
  amplitude_T_ = 2.0 / nodes_ * std::hypot(re, im);
}

void CircleFieldModel::monomials(double ex_mm, double ey_mm, double ez_mm, double* u) const {
  double px[5] = {1, 0, 0, 0, 0}, py[5] = {1, 0, 0, 0, 0}, pz[5] = {1, 0, 0, 0, 0};
  const double ux = ex_mm / reach_xy_mm_, uy = ey_mm / reach_xy_mm_, uz = ez_mm / reach_z_mm_;
  for (int i = 1; i < 5; ++i) {
    px[i] = px[i - 1] * ux;
    py[i] = py[i - 1] * uy;
    pz[i] = pz[i - 1] * uz;
  }
  for (std::size_t t = 0; t < exps_.size(); ++t) u[t] = px[exps_[t][0]] * py[exps_[t][1]] * pz[exps_[t][2]];
}

}  // namespace magenc
