#include "analysis/circle_field_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <Eigen/Dense>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc {

namespace {
constexpr int kStencil = 5;  // points per axis of the fit stencil
}  // namespace

// The constrained least-squares fit on the stencil: the constant is the exact node value (the
// stencil's centre point) and coef[1..T-1] = pinv(V) * (samples - centre), V = P x (T-1) monomials.
struct CircleFieldModel::StencilFit {
  Eigen::MatrixXd V, pinv;  // P x (T-1) and (T-1) x P
  int centre = -1;
  // samples: P x n (column = one node or one source); T x n coefficients; resid_abs: fit - sample.
  Eigen::MatrixXd operator()(const Eigen::MatrixXd& samples, Eigen::MatrixXd& resid_abs) const {
    const Eigen::Index P = samples.rows(), T = V.cols() + 1;
    const Eigen::RowVectorXd centre_v = samples.row(centre);
    const Eigen::MatrixXd rel = samples - Eigen::VectorXd::Ones(P) * centre_v;
    Eigen::MatrixXd coef(T, samples.cols());
    coef.row(0) = centre_v;
    coef.bottomRows(T - 1) = pinv * rel;
    resid_abs = V * coef.bottomRows(T - 1) - rel;
    return coef;
  }
};

Eigen::MatrixXd CircleFieldModel::stencil_monomials(const std::vector<Eigen::Vector3d>& stencil, double c,
                                                    double s) const {
  const int T = terms();
  Eigen::MatrixXd V(static_cast<Eigen::Index>(stencil.size()), T);
  std::vector<double> u(static_cast<std::size_t>(T));
  for (std::size_t p = 0; p < stencil.size(); ++p) {
    const double ux = stencil[p].x(), uy = stencil[p].y();
    monomials((c * ux + s * uy) * reach_xy_mm_, (-s * ux + c * uy) * reach_xy_mm_, stencil[p].z() * reach_z_mm_, u.data());
    for (int t = 0; t < T; ++t) V(static_cast<Eigen::Index>(p), t) = u[std::size_t(t)];
  }
  return V;
}

Eigen::MatrixXd CircleFieldModel::sample(const FieldSource& src, const Eigen::Matrix3Xd& pts, bool full_vector,
                                         const std::string& field_name) {
  Eigen::MatrixXd out(full_vector ? 3 : 1, pts.cols());  // rows Bz, then Bx, By
  if (full_vector) {
    const Eigen::Matrix3Xd B = src.B_T(pts);
    out.row(0) = B.row(2);
    out.row(1) = B.row(0);
    out.row(2) = B.row(1);
  } else {
    out.row(0) = src.Bz_T(pts).transpose();
  }
  if (!out.allFinite())
    throw ComputeError("field " + field_name + " returned a non-finite B near r0 = " + num(r0_mm_) + " mm");
  field_evaluations_ += static_cast<long>(pts.cols());
  return out;
}

CircleFieldModel::Construction CircleFieldModel::construction_named(const std::string& name) {
  if (name == "automatic") return Construction::automatic;
  if (name == "axis_aligned") return Construction::axis_aligned;
  if (name == "rotated") return Construction::rotated;
  if (name == "symmetry") return Construction::symmetry;
  if (name == "symmetrized") return Construction::symmetrized;
  throw InputError("surrogate build '" + name + "': allowed automatic, axis_aligned, rotated, symmetry, symmetrized");
}

std::string CircleFieldModel::construction_name(Construction how) {
  switch (how) {
    case Construction::automatic: return "automatic";
    case Construction::axis_aligned: return "axis_aligned";
    case Construction::rotated: return "rotated";
    case Construction::symmetry: return "symmetry";
    case Construction::symmetrized: return "symmetrized";
  }
  return "?";
}

CircleFieldModel::CircleFieldModel(const FieldSource& field, double r0_mm, double plane_z_mm, int nodes,
                                   double reach_xy_mm, double reach_z_mm, int order, bool full_vector,
                                   Construction how)
    : nodes_(nodes), r0_mm_(r0_mm), plane_z_mm_(plane_z_mm), reach_xy_mm_(std::max(reach_xy_mm, 0.01)),
      reach_z_mm_(std::max(reach_z_mm, 0.01)) {
  if (nodes < 16) throw InputError("radius.fast_steps = " + std::to_string(nodes) + " is out of range: allowed >= 16");
  if (order < 2 || order > 4)
    throw InputError("radius.surrogate_order = " + std::to_string(order) + " is out of range: allowed [2, 4]");
  if (full_vector && !field.gives_full_vector())
    throw InputError("field " + field.name() + " gives only Bz on a plane: tilts in the tolerance box "
                     "(radius.tol_tilt_x_deg, tol_tilt_y_deg, tol_magnet_tilt_deg) need the full field vector: "
                     "allowed 0 for this field");
  const std::optional<FieldSource::AxisymmetricParts> parts = field.axisymmetric_parts();
  const bool automatic = how == Construction::automatic;
  if (automatic) how = parts ? Construction::symmetry : Construction::symmetrized;
  if (how == Construction::symmetry && !parts)
    throw InputError("field " + field.name() + " declares no rotational symmetry: CircleFieldModel::Construction::symmetry "
                     "needs the exact field of an axisymmetric magnet");
  order_ = order;
  build(field, parts, full_vector, how);
  // automatic: the symmetrized models only where the field's symmetric part explains it at every node.
  if (automatic && how == Construction::symmetrized && !(node_residual_max_T_ <= kSymmetrizedMaxResidual * amplitude_T_))
    build(field, parts, full_vector, Construction::axis_aligned);
}

void CircleFieldModel::build(const FieldSource& field, const std::optional<FieldSource::AxisymmetricParts>& parts,
                             bool full_vector, Construction how) {
  construction_ = how;
  exps_.clear();
  coef_x_.resize(0, 0);
  coef_y_.resize(0, 0);
  node_residual_.resize(0, 0);
  node_residual_max_T_ = 0;
  const int order = order_;
  // 1. Monomials of total degree <= order in the scaled displacement u = e/reach.
  for (int a = 0; a <= order; ++a)
    for (int b = 0; a + b <= order; ++b)
      for (int c = 0; a + b + c <= order; ++c) exps_.push_back({a, b, c});
  const int T = terms();
  const int C = full_vector ? 3 : 1;  // fitted components: Bz (and Bx, By)

  // 2. Stencil in scaled units: 5 x 5 x 5 points over [-1, 1]^3 (the centre
  //    is a stencil point, so the exact node value comes for free).
  std::vector<Eigen::Vector3d> stencil;
  StencilFit fit;
  for (int i = 0; i < kStencil; ++i)
    for (int j = 0; j < kStencil; ++j)
      for (int k = 0; k < kStencil; ++k) {
        const double h = 2.0 / (kStencil - 1);
        if (i == 2 && j == 2 && k == 2) fit.centre = static_cast<int>(stencil.size());
        stencil.emplace_back(-1 + h * i, -1 + h * j, -1 + h * k);
      }
  const int P = static_cast<int>(stencil.size());

  // 3. Least-squares operator for the non-constant terms (StencilFit).
  fit.V = stencil_monomials(stencil, 1.0, 0.0).rightCols(T - 1);
  fit.pinv = fit.V.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(P, P));  // (T-1) x P

  // Node angles; stencil points of node j: its position plus the stencil, along the frame's
  // axes (axis_aligned) or turned with the node (rotated, symmetry: node 0's stencil rotated by phi_j).
  std::vector<double> cphi(static_cast<std::size_t>(nodes_)), sphi(static_cast<std::size_t>(nodes_));
  for (int j = 0; j < nodes_; ++j) {
    const double phi = 2.0 * kPi * j / nodes_;
    cphi[std::size_t(j)] = std::cos(phi);
    sphi[std::size_t(j)] = std::sin(phi);
  }
  const bool turned = how != Construction::axis_aligned;
  // Stencil point p turned by (c, s) about the node at (cn, sn) on the circle.
  auto turned_point = [&](double cn, double sn, double c, double s, int p) {
    const double ex = stencil[std::size_t(p)].x() * reach_xy_mm_, ey = stencil[std::size_t(p)].y() * reach_xy_mm_;
    return Eigen::Vector3d(r0_mm_ * cn + c * ex - s * ey, r0_mm_ * sn + s * ex + c * ey,
                           plane_z_mm_ + stencil[std::size_t(p)].z() * reach_z_mm_);
  };
  auto stencil_point = [&](int j, int p) {
    const double c = turned ? cphi[std::size_t(j)] : 1.0, s = turned ? sphi[std::size_t(j)] : 0.0;
    return turned_point(cphi[std::size_t(j)], sphi[std::size_t(j)], c, s, p);
  };

  // 4. Local fits G[c] (T x nodes, in the stencil's coordinates) of every component c.
  std::vector<Eigen::MatrixXd> G(static_cast<std::size_t>(C));
  fit_residual_T_ = 0;
  if (how == Construction::symmetry) {
    Eigen::Matrix3Xd pts(3, P);
    for (int p = 0; p < P; ++p) pts.col(p) = stencil_point(0, p);
    G = symmetry_fits(*parts, pts, fit, full_vector, field.name(), cphi, sphi);
  } else if (how == Construction::symmetrized) {
    Eigen::Matrix3Xd pts(3, static_cast<Eigen::Index>(P) * kSymmetrizedAzimuths);
    for (int l = 0; l < kSymmetrizedAzimuths; ++l) {
      const double a = 2.0 * kPi * l / kSymmetrizedAzimuths, ca = std::cos(a), sa = std::sin(a);
      for (int p = 0; p < P; ++p) pts.col(static_cast<Eigen::Index>(l) * P + p) = turned_point(ca, sa, ca, sa, p);
    }
    G = symmetrized_fits(sample(field, pts, full_vector, field.name()), fit, full_vector, cphi, sphi);
  } else {
    Eigen::Matrix3Xd pts(3, static_cast<Eigen::Index>(P) * nodes_);
    for (int j = 0; j < nodes_; ++j)
      for (int p = 0; p < P; ++p) pts.col(static_cast<Eigen::Index>(j) * P + p) = stencil_point(j, p);
    const Eigen::MatrixXd S = sample(field, pts, full_vector, field.name());
    for (int c = 0; c < C; ++c) {
      const Eigen::RowVectorXd row = S.row(c);
      const Eigen::Map<const Eigen::MatrixXd> samples(row.data(), P, nodes_);
      Eigen::MatrixXd resid;
      G[std::size_t(c)] = fit(samples, resid);
      fit_residual_T_ = std::max(fit_residual_T_, resid.cwiseAbs().maxCoeff());
    }
  }

  // 5. Coefficients in the frame's displacement (turned stencils), 6. exact node values.
  std::vector<Eigen::MatrixXd*> out = {&coef_, &coef_x_, &coef_y_};
  for (int c = 0; c < C; ++c) *out[std::size_t(c)] = G[std::size_t(c)];
  if (turned) to_frame_coefficients(stencil, G, cphi, sphi);
  center_T_ = coef_.row(0).transpose();
  if (how == Construction::symmetrized) node_residuals(field, full_vector, cphi, sphi);
  double re = 0, im = 0;
  for (int j = 0; j < nodes_; ++j) {
    re += center_T_[j] * cphi[std::size_t(j)];
    im += center_T_[j] * sphi[std::size_t(j)];
  }
  amplitude_T_ = 2.0 / nodes_ * std::hypot(re, im);
}

// The field at every node minus the model's (symmetric part's) value there; center_T_ the field's own Bz.
void CircleFieldModel::node_residuals(const FieldSource& field, bool full_vector, const std::vector<double>& cphi,
                                      const std::vector<double>& sphi) {
  const int C = full_vector ? 3 : 1;
  Eigen::Matrix3Xd pts(3, nodes_);
  for (int j = 0; j < nodes_; ++j) pts.col(j) = Eigen::Vector3d(r0_mm_ * cphi[std::size_t(j)], r0_mm_ * sphi[std::size_t(j)], plane_z_mm_);
  const Eigen::MatrixXd S = sample(field, pts, full_vector, field.name());  // rows Bz (, Bx, By)
  const Eigen::MatrixXd* coef[3] = {&coef_, &coef_x_, &coef_y_};
  node_residual_.resize(C, nodes_);
  for (int c = 0; c < C; ++c) node_residual_.row(c) = S.row(c) - coef[c]->row(0);
  node_residual_max_T_ = node_residual_.cwiseAbs().maxCoeff();
  center_T_ = S.row(0).transpose();
}

// The symmetric part of any field from its samples on node 0's turned stencil turned to K azimuths a_l:
// D_l = Rz(-a_l) B(Rz(a_l) (node 0 + e)) is, for a field of the form B(Rz(a) p) = Rz(a) B(p; Rz(-a) M),
// cos(a_l) P + sin(a_l) Q + Z (B linear in M); P, Q, Z are its least-squares parts over the azimuths
// (their first angular harmonic and mean), fitted once, and node j takes cos(phi_j) P + sin(phi_j) Q + Z
// turned by phi_j (as symmetry_fits).
std::vector<Eigen::MatrixXd> CircleFieldModel::symmetrized_fits(const Eigen::MatrixXd& S, const StencilFit& fit,
                                                                bool full_vector, const std::vector<double>& cphi,
                                                                const std::vector<double>& sphi) {
  const int T = terms(), C = full_vector ? 3 : 1, K = kSymmetrizedAzimuths;
  const Eigen::Index P = S.cols() / K;
  std::array<Eigen::MatrixXd, 3> part;  // P x C each: the samples of P, Q, Z (components Bz, Bx, By)
  for (auto& q : part) q = Eigen::MatrixXd::Zero(P, C);
  for (int l = 0; l < K; ++l) {
    const double a = 2.0 * kPi * l / K, ca = std::cos(a), sa = std::sin(a);
    Eigen::MatrixXd D = S.middleCols(static_cast<Eigen::Index>(l) * P, P).transpose();  // P x C
    if (full_vector) {  // turn the in-plane components back by -a
      const Eigen::VectorXd bx = D.col(1);
      D.col(1) = ca * bx + sa * D.col(2);
      D.col(2) = -sa * bx + ca * D.col(2);
    }
    part[0] += (2.0 / K) * ca * D;
    part[1] += (2.0 / K) * sa * D;
    part[2] += (1.0 / K) * D;
  }
  std::array<Eigen::MatrixXd, 3> F, R;
  for (int k = 0; k < 3; ++k) {
    F[std::size_t(k)].resize(T, C);
    R[std::size_t(k)].resize(P, C);
    for (int c = 0; c < C; ++c) {
      const Eigen::VectorXd col = part[std::size_t(k)].col(c);
      Eigen::MatrixXd resid;
      F[std::size_t(k)].col(c) = fit(col, resid);
      R[std::size_t(k)].col(c) = resid;
    }
  }
  return combine_parts(F, R, full_vector, cphi, sphi, [&](int j, double* w) {
    w[0] = cphi[std::size_t(j)];
    w[1] = sphi[std::size_t(j)];
    w[2] = 1.0;
  });
}

// B(Rz(a) p; M) = Rz(a) B(p; Rz(-a) M) and B = sum_k m_k B_k: node 0's stencil, sampled once per
// magnetization axis k the field needs, gives every node: with c = Rz(-phi_j) m,
//   B(node j + Rz(phi_j) e) = Rz(phi_j) sum_k c_k B_k(node 0 + e).
std::vector<Eigen::MatrixXd> CircleFieldModel::symmetry_fits(const FieldSource::AxisymmetricParts& parts,
                                                             const Eigen::Matrix3Xd& pts0, const StencilFit& fit,
                                                             bool full_vector, const std::string& field_name,
                                                             const std::vector<double>& cphi,
                                                             const std::vector<double>& sphi) {
  const int T = terms(), C = full_vector ? 3 : 1;
  const Eigen::Index P = pts0.cols();
  const Vec3 m = parts.m;
  const bool inplane = m.x() != 0.0 || m.y() != 0.0, axial = m.z() != 0.0;
  // Fits F[k] (T x C) and residuals R[k] (P x C) of B_k at node 0; components Bz, Bx, By.
  std::array<Eigen::MatrixXd, 3> F, R;
  for (int k = 0; k < 3; ++k) {
    F[std::size_t(k)] = Eigen::MatrixXd::Zero(T, C);
    R[std::size_t(k)] = Eigen::MatrixXd::Zero(P, C);
    if (k < 2 ? !inplane : !axial) continue;
    const Eigen::MatrixXd S = sample(*parts.along_axis[std::size_t(k)], pts0, full_vector, field_name);
    for (int c = 0; c < C; ++c) {
      const Eigen::VectorXd col = S.row(c).transpose();
      Eigen::MatrixXd resid;
      F[std::size_t(k)].col(c) = fit(col, resid);
      R[std::size_t(k)].col(c) = resid;
    }
  }
  return combine_parts(F, R, full_vector, cphi, sphi, [&](int j, double* w) {
    const double cj = cphi[std::size_t(j)], sj = sphi[std::size_t(j)];
    w[0] = cj * m.x() + sj * m.y();  // Rz(-phi_j) m
    w[1] = -sj * m.x() + cj * m.y();
    w[2] = m.z();
  });
}

std::vector<Eigen::MatrixXd> CircleFieldModel::combine_parts(const std::array<Eigen::MatrixXd, 3>& F,
                                                             const std::array<Eigen::MatrixXd, 3>& R, bool full_vector,
                                                             const std::vector<double>& cphi,
                                                             const std::vector<double>& sphi,
                                                             const std::function<void(int, double*)>& weights) {
  const int T = terms(), C = full_vector ? 3 : 1;
  const Eigen::Index P = R[0].rows();
  std::vector<Eigen::MatrixXd> G(static_cast<std::size_t>(C));
  for (int c = 0; c < C; ++c) G[std::size_t(c)].resize(T, nodes_);
  for (int j = 0; j < nodes_; ++j) {
    const double cj = cphi[std::size_t(j)], sj = sphi[std::size_t(j)];
    double w[3];
    weights(j, w);
    Eigen::MatrixXd Fj = Eigen::MatrixXd::Zero(T, C), Rj = Eigen::MatrixXd::Zero(P, C);
    for (int k = 0; k < 3; ++k) {
      if (w[k] == 0.0) continue;
      Fj += w[k] * F[std::size_t(k)];
      Rj += w[k] * R[std::size_t(k)];
    }
    if (full_vector) {  // rotate the in-plane components (columns Bx = 1, By = 2) by phi_j
      const Eigen::VectorXd fx = Fj.col(1), rx = Rj.col(1);
      Fj.col(1) = cj * fx - sj * Fj.col(2);
      Fj.col(2) = sj * fx + cj * Fj.col(2);
      Rj.col(1) = cj * rx - sj * Rj.col(2);
      Rj.col(2) = sj * rx + cj * Rj.col(2);
    }
    for (int c = 0; c < C; ++c) G[std::size_t(c)].col(j) = Fj.col(c);
    fit_residual_T_ = std::max(fit_residual_T_, Rj.cwiseAbs().maxCoeff());
  }
  return G;
}

// A turned stencil's fit G_j(s) is a polynomial of s = Rz(-phi_j) u, so P_j(u) = G_j(Rz(-phi_j) u),
// again of degree <= order. Its coefficients are the unconstrained least-squares fit of
// G_j(Rz(-phi_j) u_p) on the stencil (exact: the polynomial lies in the fitted space); the constant
// term stays the exact node value.
void CircleFieldModel::to_frame_coefficients(const std::vector<Eigen::Vector3d>& stencil,
                                             const std::vector<Eigen::MatrixXd>& G, const std::vector<double>& cphi,
                                             const std::vector<double>& sphi) {
  // W_j (T x T) depends on the node count and the order only (the stencil is in scaled units): computed
  // once per process for each (nodes, order), every node in parallel, and shared by every later model.
  static std::mutex mtx;
  static std::map<std::pair<int, int>, std::shared_ptr<const std::vector<Eigen::MatrixXd>>> cache;
  std::shared_ptr<const std::vector<Eigen::MatrixXd>> maps;
  {
    const std::lock_guard<std::mutex> lock(mtx);
    auto& entry = cache[{nodes_, order_}];
    if (!entry) {
      const Eigen::Index P = static_cast<Eigen::Index>(stencil.size());
      // The stencil's monomials turned by -phi, in scaled units (so that W depends on nothing else).
      const auto turned = [&](double c, double s) {
        Eigen::MatrixXd V(P, terms());
        std::vector<double> u(static_cast<std::size_t>(terms()));
        for (Eigen::Index p = 0; p < P; ++p) {
          const Eigen::Vector3d& q = stencil[std::size_t(p)];
          scaled_monomials(c * q.x() + s * q.y(), -s * q.x() + c * q.y(), q.z(), u.data());
          for (int t = 0; t < terms(); ++t) V(p, t) = u[std::size_t(t)];
        }
        return V;
      };
      const Eigen::MatrixXd pinv_full = turned(1.0, 0.0).colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(P, P));  // T x P
      auto W = std::make_shared<std::vector<Eigen::MatrixXd>>(static_cast<std::size_t>(nodes_));
#pragma omp parallel for schedule(static)
      for (int j = 0; j < nodes_; ++j)
        (*W)[std::size_t(j)] = pinv_full * turned(cphi[std::size_t(j)], sphi[std::size_t(j)]);
      entry = W;
    }
    maps = entry;
  }
  std::vector<Eigen::MatrixXd*> out = {&coef_, &coef_x_, &coef_y_};
  for (int j = 0; j < nodes_; ++j) {
    const Eigen::MatrixXd& W = (*maps)[std::size_t(j)];
    for (std::size_t c = 0; c < G.size(); ++c) {
      Eigen::MatrixXd& coef = *out[c];
      const double constant = coef(0, j);
      coef.col(j) = W * G[c].col(j);
      coef(0, j) = constant;
    }
  }
}

namespace {
// Monomials of total degree <= order of a scaled displacement, in the order of exps_ (a, then b, then c),
// without its table: (px[a] py[b]) pz[c].
inline void monomials_of(int order, double ux, double uy, double uz, double* u) {
  double px[5] = {1, 0, 0, 0, 0}, py[5] = {1, 0, 0, 0, 0}, pz[5] = {1, 0, 0, 0, 0};
  for (int i = 1; i < 5; ++i) {
    px[i] = px[i - 1] * ux;
    py[i] = py[i - 1] * uy;
    pz[i] = pz[i - 1] * uz;
  }
  int t = 0;
  for (int a = 0; a <= order; ++a)
    for (int b = 0; a + b <= order; ++b) {
      const double pab = px[a] * py[b];
      for (int c = 0; a + b + c <= order; ++c) u[t++] = pab * pz[c];
    }
}
}  // namespace

void CircleFieldModel::monomials(double ex_mm, double ey_mm, double ez_mm, double* u) const {
  monomials_of(order_, ex_mm / reach_xy_mm_, ey_mm / reach_xy_mm_, ez_mm / reach_z_mm_, u);
}

void CircleFieldModel::scaled_monomials(double ux, double uy, double uz, double* u) const {
  monomials_of(order_, ux, uy, uz, u);
}

}  // namespace magenc
