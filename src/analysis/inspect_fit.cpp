#include "analysis/inspect_fit.hpp"

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "fields/field_at.hpp"

namespace magenc {

const std::array<InspectParameter, kInspectParams>& inspect_parameters() {
  static const std::array<InspectParameter, kInspectParams> table{{
      {"offset_x_mm", "offset", "mm", 0.1},
      {"offset_y_mm", "offset", "mm", 0.1},
      {"offset_z_mm", "offset", "mm", 0.1},
      {"rot_x_deg", "rotation", "deg", 1.0},
      {"rot_y_deg", "rotation", "deg", 1.0},
      {"rot_z_deg", "rotation", "deg", 1.0},
      {"polarization_T", "polarization", "T", 0.05},
      {"magnetization_deg", "direction", "deg", 1.0},
      {"magnetization_elevation_deg", "direction", "deg", 1.0},
  }};
  return table;
}

std::vector<std::string> parse_inspect_groups(const std::string& text, const std::string& what) {
  std::vector<std::string> groups;
  std::stringstream ss(text);
  for (std::string g; std::getline(ss, g, ',');) {
    if (g.empty()) continue;
    if (g != "offset" && g != "rotation" && g != "polarization" && g != "direction")
      throw InputError(what + " '" + g + "' is not a parameter group: allowed a comma-separated subset of "
                                         "offset, rotation, polarization, direction");
    groups.push_back(g);
  }
  if (groups.empty())
    throw InputError(what + " is empty: allowed a comma-separated subset of offset, rotation, polarization, direction");
  return groups;
}

InspectValues nominal_inspect_values(const Magnet& m) {
  return {0, 0, 0, 0, 0, 0, m.br_T, m.magnetization_deg, m.magnetization_elevation_deg};
}

Eigen::Matrix3Xd inspect_model_T(const Magnet& base, const Eigen::Matrix3Xd& p_mm, const InspectValues& v) {
  Magnet m = base;
  m.br_T = v[6];
  m.magnetization_deg = v[7];
  m.magnetization_elevation_deg = v[8];
  const AnalyticField field(m);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(deg_to_rad(v[5]), Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(deg_to_rad(v[4]), Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(deg_to_rad(v[3]), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  Eigen::Matrix3Xd q = p_mm;
  q.colwise() += Eigen::Vector3d(v[0], v[1], v[2]);
  return R.transpose() * field_at(field, q);
}

namespace {

// Residuals (mT) of the free parameters u (in typical sizes, about the start values).
struct ScanResiduals {
  const Magnet* magnet;
  const FieldScan* scan;
  InspectValues start;
  std::vector<int> free;  // parameter indices
  InspectValues values(const double* u) const {
    InspectValues v = start;
    for (std::size_t k = 0; k < free.size(); ++k) v[free[k]] += u[k] * inspect_parameters()[free[k]].scale;
    return v;
  }
  void residuals(const double* u, double* r) const {
    const Eigen::Matrix3Xd B = inspect_model_T(*magnet, scan->p_mm, values(u));
    const Eigen::Index n = B.cols();
    for (Eigen::Index j = 0; j < n; ++j)
      for (int c = 0; c < 3; ++c) r[3 * j + c] = 1e3 * (B(c, j) - scan->B_T(c, j));
  }
  bool operator()(double const* const* u, double* r) const {
    try {
      residuals(u[0], r);
    } catch (const InputError&) {
      return false;  // a trial step put a point on the magnet's surface: Ceres shortens the step
    }
    return true;
  }
};

// A fit that is no result: a polarization beyond the range of magnet.br_T, or a residual above
// kInspectMaxResidualFraction of the readings (ComputeError, one line).
void check_fit_explains_scan(const InspectResult& res, const FieldScan& scan) {
  if (!(std::abs(res.value[6]) <= kInspectMaxPolarization_T))
    throw ComputeError("inspect: the fit ends at a polarization of " + num(res.value[6]) + " T: allowed |Br| <= " +
                       num(kInspectMaxPolarization_T) + " T (as magnet.br_T); the scan is too far from the magnet " +
                       "or its readings are not of this magnet");
  const double readings_rms_mT = 1e3 * scan.B_T.norm() / std::sqrt(double(scan.B_T.size()));
  if (!(res.residual_rms_mT <= kInspectMaxResidualFraction * readings_rms_mT))
    throw ComputeError("inspect: the fit leaves a residual RMS of " + num(res.residual_rms_mT) + " mT for readings of RMS " +
                       num(readings_rms_mT) + " mT: allowed at most " + num(100 * kInspectMaxResidualFraction) +
                       " % of the readings (the model does not explain the scan: its positions, units or magnet?)");
}

}  // namespace

InspectResult inspect_scan(const Magnet& nominal, const FieldScan& scan, const InspectOptions& opts) {
  nominal.validate();
  const auto& table = inspect_parameters();
  InspectResult res;
  std::vector<int> free;
  for (int i = 0; i < kInspectParams; ++i) {
    for (const auto& g : opts.groups) res.free[i] = res.free[i] || table[i].group == g;
    if (res.free[i]) {
      free.push_back(i);
      res.free_names.push_back(table[i].name);
    }
  }
  const int k = static_cast<int>(free.size());
  const Eigen::Index N = scan.p_mm.cols();
  if (N < 1 || scan.B_T.cols() != N) throw InputError("scan: no readings: allowed one or more rows");
  if (3 * N <= k)
    throw InputError("scan: " + std::to_string(N) + " readings (" + std::to_string(3 * N) + " components) for " +
                     std::to_string(k) + " free parameters: allowed more components than free parameters");
  ScanResiduals model{&nominal, &scan, nominal_inspect_values(nominal), free};
  (void)inspect_model_T(nominal, scan.p_mm, model.start);  // a nominal point on the surface: one line, now

  // 1. Levenberg-Marquardt from the nominal values (u = 0).
  std::vector<double> u(k, 0.0);
  if (k > 0) {
    auto* cost = new ceres::DynamicNumericDiffCostFunction<ScanResiduals, ceres::CENTRAL>(
        new ScanResiduals(model), ceres::TAKE_OWNERSHIP);
    cost->AddParameterBlock(k);
    cost->SetNumResiduals(static_cast<int>(3 * N));
    ceres::Problem problem;
    problem.AddResidualBlock(cost, nullptr, u.data());
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = opts.max_iterations;
    so.function_tolerance = 1e-15;
    so.gradient_tolerance = 1e-15;
    so.parameter_tolerance = 1e-12;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary sum;
    ceres::Solve(so, &problem, &sum);
    res.iterations = static_cast<int>(sum.iterations.size());
    if (sum.termination_type == ceres::FAILURE || !sum.IsSolutionUsable())
      throw ComputeError("inspect: the fit failed (" + sum.message +
                         "): no result; check the scan's positions and units and the [magnet] keys");
  }
  res.value = model.values(u.data());
  res.fitted_T = inspect_model_T(nominal, scan.p_mm, res.value);
  const Eigen::Matrix3Xd resid_mT = 1e3 * (res.fitted_T - scan.B_T);
  const double rss = resid_mT.squaredNorm();
  res.residual_rms_mT = std::sqrt(rss / double(3 * N));
  check_fit_explains_scan(res, scan);

  // 2. Covariance: central-difference Jacobian in typical sizes, column-normalised SVD.
  res.sigma.fill(0.0);
  if (k == 0) return res;
  Eigen::MatrixXd J(3 * N, k);
  std::vector<double> up = u, rp(3 * N), rm(3 * N);
  for (int c = 0; c < k; ++c) {
    up = u;
    up[c] += opts.fd_step;
    model.residuals(up.data(), rp.data());
    up[c] = u[c] - opts.fd_step;
    model.residuals(up.data(), rm.data());
    for (Eigen::Index r = 0; r < 3 * N; ++r) J(r, c) = (rp[r] - rm[r]) / (2 * opts.fd_step);
  }
  Eigen::VectorXd norms = J.colwise().norm();
  for (int c = 0; c < k; ++c)
    if (!(norms[c] > 0)) norms[c] = 1.0;  // a parameter with no effect: its singular value is 0 below
  const Eigen::MatrixXd Jn = J * norms.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Jn, Eigen::ComputeThinV);
  res.singular_values = svd.singularValues();
  const double smax = res.singular_values[0];
  res.condition = smax / res.singular_values[k - 1];
  const double s2 = 3 * N > k ? rss / double(3 * N - k) : 0.0;  // residual variance (mT^2)
  const Eigen::MatrixXd& V = svd.matrixV();
  std::vector<bool> unidentified(k, false);
  Eigen::MatrixXd cov_n = Eigen::MatrixXd::Zero(k, k);  // covariance of the normalised variables
  for (int i = 0; i < k; ++i) {
    const double s = res.singular_values[i];
    if (s < smax / opts.cond_limit) {
      for (int c = 0; c < k; ++c)
        if (std::abs(V(c, i)) > 0.1) unidentified[c] = true;
    } else {
      cov_n += V.col(i) * V.col(i).transpose() / (s * s);
    }
  }
  cov_n *= s2;
  res.correlation = Eigen::MatrixXd::Constant(k, k, std::numeric_limits<double>::quiet_NaN());
  for (int c = 0; c < k; ++c) {
    const double sd_u = std::sqrt(cov_n(c, c)) / norms[c];  // in typical sizes
    res.sigma[free[c]] = unidentified[c] ? std::numeric_limits<double>::infinity() : sd_u * table[free[c]].scale;
    if (unidentified[c]) res.not_identifiable.push_back(table[free[c]].name);
  }
  for (int a = 0; a < k; ++a)
    for (int b = 0; b < k; ++b)
      if (!unidentified[a] && !unidentified[b])
        res.correlation(a, b) = cov_n(a, b) / std::sqrt(cov_n(a, a) * cov_n(b, b));
  return res;
}

}  // namespace magenc
