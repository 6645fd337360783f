#include "grids.hpp"

#include <cmath>

namespace magenc::fem {

Eigen::Matrix3Xd GridSpec::points() const {
  Eigen::Matrix3Xd p(3, num_points());
  long n = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        p.col(n++) = origin_mm + Eigen::Vector3d(i * step_mm[0], j * step_mm[1], k * step_mm[2]);
  return p;
}

GridSpec GridSpec::from_range(const Eigen::Vector3d& min_mm, const Eigen::Vector3d& max_mm, const Eigen::Vector3d& step_mm) {
  GridSpec g;
  g.origin_mm = min_mm;
  g.step_mm = step_mm;
  for (int d = 0; d < 3; ++d)
    g.dims[d] = 1 + static_cast<int>(std::floor((max_mm[d] - min_mm[d]) / step_mm[d] + 1e-9));
  return g;
}

}  // namespace magenc::fem
