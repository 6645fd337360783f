#include "validation.hpp"

#include <cmath>

namespace magenc::fem {

BzErrorStats bz_error_on_grid(const FieldEvaluator& fem, const FieldSource& ref, const GridSpec& grid) {
  const Eigen::Matrix3Xd p = grid.points();
  const Eigen::Matrix3Xd B = fem.B_T(p);
  const Eigen::VectorXd bz_ref = ref.Bz_T(p);
  BzErrorStats s;
  s.points = p.cols();
  double sum2 = 0;
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    const double e = B(2, i) - bz_ref[i];
    s.peak_T = std::max(s.peak_T, std::abs(bz_ref[i]));
    s.max_abs_T = std::max(s.max_abs_T, std::abs(e));
    sum2 += e * e;
  }
  s.rms_T = std::sqrt(sum2 / static_cast<double>(std::max<long>(1, s.points)));
  return s;
}

}  // namespace magenc::fem
