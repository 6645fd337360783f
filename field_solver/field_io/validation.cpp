#include "field_solver/field_io/validation.hpp"

#include <cmath>

#include "fields/analytic_field.hpp"
#include "fields/multipole_field.hpp"
#include "field_solver/field_io/field_outputs.hpp"

namespace magenc::fem {

BzErrorStats bz_error_on_grid(const FieldEvaluator& fem, const FieldSource& ref, const GridData& grid) {
  const Eigen::Matrix3Xd p = grid.points_mm();
  const Eigen::Matrix3Xd B = fem.B_T(p);
  const Eigen::Matrix3Xd B_ref = ref.B_T(p);
  const Eigen::VectorXd bz_ref = B_ref.row(2).transpose();
  BzErrorStats s;
  s.points = p.cols();
  double sum2 = 0, sumv = 0;
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    const double e = B(2, i) - bz_ref[i];
    s.peak_T = std::max(s.peak_T, std::abs(bz_ref[i]));
    s.max_abs_T = std::max(s.max_abs_T, std::abs(e));
    sum2 += e * e;
    sumv += (B.col(i) - B_ref.col(i)).squaredNorm();
    s.peak_B_T = std::max(s.peak_B_T, B_ref.col(i).norm());
  }
  s.rms_vec_T = std::sqrt(sumv / static_cast<double>(std::max<long>(1, s.points)));
  s.rms_T = std::sqrt(sum2 / static_cast<double>(std::max<long>(1, s.points)));
  return s;
}

std::shared_ptr<const FieldSource> exact_field_of(const Magnet& magnet) {
  if (!magnet.is_uniform()) return std::make_shared<MultipoleField>(magnet);
  return std::make_shared<AnalyticField>(magnet);
}

ExactComparison solve_and_compare_with_exact(const DomainSpec& domain, const SolverOptions& options, const GridData& grid) {
  MagnetostaticSolver solver(domain, options);
  solver.run();
  const std::shared_ptr<const FieldSource> exact = exact_field_of(domain.magnet);
  ExactComparison c;
  c.stats = solver.stats();
  c.error = bz_error_on_grid(solver.evaluator(), *exact, grid);
  c.peak_rss_mib = peak_rss_mib();
  return c;
}

}  // namespace magenc::fem
