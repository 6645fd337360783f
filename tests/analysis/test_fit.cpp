// Cubic least-squares fit (src/analysis/fit.*).
#include <catch2/catch.hpp>

#include "core/errors.hpp"
#include "analysis/fit.hpp"

using namespace magenc;

TEST_CASE("fit_cubic recovers a known cubic exactly", "[probe][fit]") {
  // Offsets in mm over [-0.3, 0.3] as the sweeps use; exact data, so only
  // round-off remains (condition number of the scaled Vandermonde ~1e3: 1e-10).
  const double p3 = 12.5, p2 = -3.25, p1 = 2.387, p0 = 0.041;
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(13, -0.3, 0.3), y(13);
  for (int i = 0; i < 13; ++i) y[i] = ((p3 * x[i] + p2) * x[i] + p1) * x[i] + p0;
  const auto p = fit_cubic(x, y);
  CHECK(p[0] == Approx(p3).epsilon(1e-10));
  CHECK(p[1] == Approx(p2).epsilon(1e-10));
  CHECK(p[2] == Approx(p1).epsilon(1e-10));
  CHECK(p[3] == Approx(p0).epsilon(1e-10));
}

TEST_CASE("fit_cubic is least squares for noisy data", "[probe][fit]") {
  // y = x^3 + alternating +-0.01: the residual is orthogonal to 1, x, x^2, x^3.
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(9, -1, 1), y(9);
  for (int i = 0; i < 9; ++i) y[i] = x[i] * x[i] * x[i] + (i % 2 ? 0.01 : -0.01);
  const auto p = fit_cubic(x, y);
  Eigen::VectorXd r(9);
  for (int i = 0; i < 9; ++i) r[i] = y[i] - (((p[0] * x[i] + p[1]) * x[i] + p[2]) * x[i] + p[3]);
  for (int k = 0; k < 4; ++k) CHECK(std::abs(r.dot(x.array().pow(k).matrix())) < 1e-12);
}

TEST_CASE("fit_cubic rejects too few distinct points and NaN", "[probe][fit]") {
  Eigen::VectorXd x(5), y(5);
  x << 0, 0.1, 0.1, 0.2, 0.2;
  y << 1, 2, 3, 4, 5;
  CHECK_THROWS_AS(fit_cubic(x, y), InputError);
  x << 0, 0.1, 0.2, 0.3, 0.4;
  y[2] = std::nan("");
  CHECK_THROWS_AS(fit_cubic(x, y), InputError);
}
