#include "probe/inplane_ellipse.hpp"

#include <cmath>

#include "core/units.hpp"

namespace magenc {

double inplane_ellipse_k(const AngleErrorResult& r) {
  double ac = 0, as = 0;
  const Eigen::Index M = r.inplane_B_T.rows();
  for (Eigen::Index m = 0; m < M; ++m) {
    const double t = 2.0 * kPi * static_cast<double>(m) / static_cast<double>(M);
    ac += r.inplane_B_T(m, 0) * std::cos(t);
    as += r.inplane_B_T(m, 1) * std::sin(t);
  }
  return std::abs(ac / as);
}

}  // namespace magenc
