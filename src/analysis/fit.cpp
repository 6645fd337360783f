#include "analysis/fit.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/errors.hpp"

namespace magenc {

std::array<double, 4> fit_cubic(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  if (x.size() != y.size())
    throw InputError("fit_cubic: x has " + std::to_string(x.size()) + " values, y has " +
                     std::to_string(y.size()) + ": allowed equal lengths");
  if (!x.allFinite() || !y.allFinite()) throw InputError("fit_cubic: NaN or infinity in the data");
  std::vector<double> xs(x.data(), x.data() + x.size());
  std::sort(xs.begin(), xs.end());
  const auto distinct = std::unique(xs.begin(), xs.end()) - xs.begin();
  if (distinct < 4)
    throw InputError("fit_cubic: " + std::to_string(distinct) +
                     " distinct x values: allowed at least 4 for a cubic");
  // Columns x^3, x^2, x, 1; column-pivoting QR is insensitive to column scaling.
  Eigen::MatrixXd A(x.size(), 4);
  A.col(3).setOnes();
  A.col(2) = x;
  A.col(1) = x.array().square();
  A.col(0) = x.array().cube();
  const Eigen::Vector4d p = A.colPivHouseholderQr().solve(y);
  return {p[0], p[1], p[2], p[3]};
}

}  // namespace magenc
