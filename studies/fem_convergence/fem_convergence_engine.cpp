#include "studies/fem_convergence/fem_convergence_engine.hpp"

#include <cmath>

namespace magenc {

double observed_rate(double x_a, double e_a, double x_b, double e_b) {
  return std::log(e_a / e_b) / std::log(x_b / x_a);
}

void estimate_rates(std::vector<RefinementRun>& runs) {
  for (size_t i = 0; i < runs.size(); ++i) {
    RefinementRun& r = runs[i];
    if (i == 0) {
      r.rate_h = r.rate_dofs = NAN;
      continue;
    }
    const RefinementRun& p = runs[i - 1];
    r.rate_h = observed_rate(1.0 / p.h_zone_mm, p.rms_rel, 1.0 / r.h_zone_mm, r.rms_rel);
    r.rate_dofs = observed_rate(double(p.dofs), p.rms_rel, double(r.dofs), r.rms_rel);
  }
}

}  // namespace magenc
