// The rate estimate of the fem_convergence study (studies/fem_convergence/fem_convergence_engine.hpp)
// on synthetic refinement sequences with known rates.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "studies/fem_convergence/fem_convergence_engine.hpp"

using namespace magenc;

namespace {
// Runs at zone edges h with error C h^p and DOFs D h^-3 (uniform refinement in 3D).
std::vector<RefinementRun> synthetic(const std::vector<double>& hs, double p) {
  std::vector<RefinementRun> runs;
  for (double h : hs) {
    RefinementRun r;
    r.h_zone_mm = h;
    r.dofs = std::lround(1000.0 * std::pow(h, -3.0));
    r.rms_rel = 0.03 * std::pow(h, p);
    runs.push_back(r);
  }
  return runs;
}
}  // namespace

TEST_CASE("observed_rate of e = C x^-p is p", "[studies][closed-form]") {
  CHECK(observed_rate(1.0, 1.0, 2.0, 0.25) == Approx(2.0));
  CHECK(observed_rate(10.0, 0.5, 1000.0, 0.005) == Approx(1.0));
  CHECK(observed_rate(1.0, 0.1, 2.0, 0.2) == Approx(-1.0));  // error growing: negative rate
}

TEST_CASE("estimate_rates: errors ~ h^2 give rate 2 in h and 2/3 in DOFs", "[studies][closed-form]") {
  auto runs = synthetic({1.0, 0.7, 0.5, 0.35}, 2.0);
  estimate_rates(runs);
  CHECK(std::isnan(runs[0].rate_h));
  CHECK(std::isnan(runs[0].rate_dofs));
  for (size_t i = 1; i < runs.size(); ++i) {
    CAPTURE(i);
    CHECK(runs[i].rate_h == Approx(2.0).epsilon(1e-12));
    // DOFs are rounded to integers: rate 2/3 to the rounding's precision.
    CHECK(runs[i].rate_dofs == Approx(2.0 / 3.0).epsilon(1e-3));
  }
}

TEST_CASE("estimate_rates: each rate uses only the run before it", "[studies][closed-form]") {
  // h^1 on the first pair, then h^3: the rates follow the local slope.
  std::vector<RefinementRun> runs(3);
  const double hs[] = {1.0, 0.5, 0.25};
  const double es[] = {0.1, 0.05, 0.05 / 8};
  for (int i = 0; i < 3; ++i) {
    runs[i].h_zone_mm = hs[i];
    runs[i].dofs = 100 * (i + 1);
    runs[i].rms_rel = es[i];
  }
  estimate_rates(runs);
  CHECK(runs[1].rate_h == Approx(1.0));
  CHECK(runs[2].rate_h == Approx(3.0));
  CHECK(runs[2].rate_dofs == Approx(std::log(8.0) / std::log(1.5)));
}

TEST_CASE("estimate_rates: one run has no rate and an empty list is left alone", "[studies][closed-form]") {
  auto one = synthetic({0.5}, 2.0);
  estimate_rates(one);
  CHECK(std::isnan(one[0].rate_h));
  std::vector<RefinementRun> none;
  estimate_rates(none);
  CHECK(none.empty());
}
