// The study's linear field model Bz = k*x through the full pipeline
// (mounting -> `two` array -> atan2 -> spectrum): docs/physics.md's sanity values,
// the first-order closed forms, and the symmetries they imply.
//
// First-order closed form (derived here). With the `two` array and Bz = x the
// channels are, for s = (sx, sy), d = (dx, dy):
//   cos = r0 cos(theta) + u,  sin = r0 sin(theta) + u,
//   u   = sx cos(theta) + sy sin(theta) - dx       (the same u in both!)
// and atan2(r0 sin + dS, r0 cos + dC) = theta + (cos*dS - sin*dC)/r0 + O((u/r0)^2), so
//   eps = (cos(theta) - sin(theta)) * u / r0 + O(((|s|+|d|)/r0)^2)
//       = [ (sx - sy)/2 + (sx + sy)/2 cos 2theta + (sy - sx)/2 sin 2theta
//           - dx cos theta + dx sin theta ] / r0            (radians)
// i.e. a0 = (sx-sy)/(2 r0), a1 = -dx/r0, b1 = +dx/r0, a2 = (sx+sy)/(2 r0),
// b2 = (sy-sx)/(2 r0), all other harmonics zero at first order; dy and dz do
// not appear at all (Bz does not depend on y; a common scale cancels).
#include <catch2/catch.hpp>

#include <cmath>

#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "core/units.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

ProbeSetup two_setup(double r0_mm = 2.4) { return test::probe_setup("two", 3600, r0_mm); }

Spectrum linear_spectrum(double sx, double sy, double dx, double dy, double dz = 0.0) {
  return error_spectrum(LinearField(), two_setup(), Mount{sx, sy, dx, dy, dz});
}

// First-order prediction of the coefficients (degrees), see the file comment.
struct FirstOrder {
  double a0, a1, b1, a2, b2;
};
FirstOrder first_order_deg(double sx, double sy, double dx, double r0) {
  const double k = rad_to_deg(1.0) / r0;
  return {k * (sx - sy) / 2, -k * dx, k * dx, k * (sx + sy) / 2, k * (sy - sx) / 2};
}

}  // namespace

// docs/physics.md gives the values to 3 decimals; 1e-3 deg accepts their rounding
// (the printed digit is within 5e-4 of the true value) and nothing more.
TEST_CASE("linear model reproduces the study's sanity values", "[probe][physics][regression]") {
  const double tol = 1e-3;
  SECTION("static x = 0.1 mm") {
    const Spectrum s = linear_spectrum(0.1, 0, 0, 0);
    CHECK(s.a0_deg == Approx(1.169).margin(tol));
    CHECK(s.a_deg[2] == Approx(1.145).margin(tol));
    CHECK(s.b_deg[2] == Approx(-1.193).margin(tol));
    CHECK(s.c_deg[2] == Approx(1.653).margin(tol));
    CHECK(s.c_deg[4] == Approx(0.024).margin(tol));
    CHECK(s.c_deg[1] < 1e-9);  // no odd harmonics from static eccentricity
    CHECK(s.c_deg[3] < 1e-9);
  }
  SECTION("static y = 0.1 mm") {
    const Spectrum s = linear_spectrum(0, 0.1, 0, 0);
    CHECK(s.a0_deg == Approx(-1.169).margin(tol));
    CHECK(s.a_deg[2] == Approx(1.145).margin(tol));
    CHECK(s.b_deg[2] == Approx(1.193).margin(tol));
  }
  SECTION("dynamic x = 0.1 mm") {
    const Spectrum s = linear_spectrum(0, 0, 0.1, 0);
    CHECK(s.a_deg[1] == Approx(-2.387).margin(tol));
    CHECK(s.b_deg[1] == Approx(2.387).margin(tol));
    CHECK(s.c_deg[1] == Approx(3.376).margin(tol));
    CHECK(s.a_deg[2] == Approx(-0.099).margin(tol));
  }
  SECTION("dynamic y and air gap: no error at all") {
    for (const Spectrum& s : {linear_spectrum(0, 0, 0, 0.1), linear_spectrum(0, 0, 0, 0, 0.3)}) {
      CHECK(std::abs(s.a0_deg) < 1e-12);
      CHECK(s.pp_deg < 1e-12);
      for (int n = 1; n <= kHarmonics; ++n) CHECK(s.c_deg[n] < 1e-12);
    }
  }
}

TEST_CASE("linear model agrees with the first-order closed form within O((offset/r0)^2)",
          "[probe][closed-form]") {
  const double r0 = 2.4;
  struct Case {
    double sx, sy, dx;
  };
  for (const Case c : {Case{0.1, 0, 0}, Case{0, 0.1, 0}, Case{0, 0, 0.1}, Case{0.02, -0.03, 0.015},
                       Case{-0.05, 0.04, -0.03}}) {
    const FirstOrder p = first_order_deg(c.sx, c.sy, c.dx, r0);
    const Spectrum s = linear_spectrum(c.sx, c.sy, c.dx, 0.0);
    // The channel perturbation has |(dC, dS)| <= sqrt(2)(|s| + |d|) = sqrt(2) eps, so the
    // second-order remainder of atan2 is <= 2 (eps/r0)^2 rad pointwise and any
    // Fourier coefficient (2/M sum ...) is <= 4 (eps/r0)^2 rad.
    const double eps = std::hypot(c.sx, c.sy) + std::abs(c.dx);
    const double tol = rad_to_deg(4.0 * (eps / r0) * (eps / r0));
    CAPTURE(c.sx, c.sy, c.dx, tol);
    CHECK(std::abs(s.a0_deg - p.a0) < tol);
    CHECK(std::abs(s.a_deg[1] - p.a1) < tol);
    CHECK(std::abs(s.b_deg[1] - p.b1) < tol);
    CHECK(std::abs(s.a_deg[2] - p.a2) < tol);
    CHECK(std::abs(s.b_deg[2] - p.b2) < tol);
    for (int n = 3; n <= kHarmonics; ++n) CHECK(s.c_deg[n] < tol);
  }
  SECTION("the remainder really is second order: offsets / 10 -> remainder / 100") {
    const Spectrum big = linear_spectrum(0.1, 0, 0, 0), small = linear_spectrum(0.01, 0, 0, 0);
    const double rb = big.a0_deg - first_order_deg(0.1, 0, 0, r0).a0;
    const double rs = small.a0_deg - first_order_deg(0.01, 0, 0, r0).a0;
    CAPTURE(rb, rs);
    CHECK(rb / rs == Approx(100.0).epsilon(0.05));
  }
}

TEST_CASE("linear model symmetries: sy mirrors sx, dy has no effect", "[probe][physics]") {
  for (double off : {0.05, 0.1, 0.2}) {
    const Spectrum x = linear_spectrum(off, 0, 0, 0), y = linear_spectrum(0, off, 0, 0);
    CAPTURE(off);
    CHECK(y.a0_deg == Approx(-x.a0_deg).epsilon(1e-12));
    CHECK(y.a_deg[2] == Approx(x.a_deg[2]).epsilon(1e-12));
    CHECK(y.b_deg[2] == Approx(-x.b_deg[2]).epsilon(1e-12));
    for (int n = 1; n <= kHarmonics; ++n) CHECK(y.c_deg[n] == Approx(x.c_deg[n]).epsilon(1e-10).margin(1e-13));
    const Spectrum dy = linear_spectrum(0.03, 0, 0.02, off), nody = linear_spectrum(0.03, 0, 0.02, 0);
    for (const auto& col : spectrum_columns()) CHECK(dy.column(col) == nody.column(col));
  }
}
