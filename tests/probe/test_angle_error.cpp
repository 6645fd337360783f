// Probe-path pipeline (src/probe/mounting.*, probe_array.*, angle_error.*) on the
// exact field: ideal mounts give no error, magnetization direction gives a
// constant offset (including the wrap at +-180), symmetries of docs/physics.md,
// and input validation.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

ProbeSetup setup_for(const std::string& array, double r0_mm = 2.4, int steps = 3600) {
  return test::probe_setup(array, steps, r0_mm);
}

Mount mount(double sx, double sy, double dx, double dy, double dz = 0) { return Mount{sx, sy, dx, dy, dz}; }

}  // namespace

TEST_CASE("probe positions follow q = Rot(-theta)(p + s) - d", "[probe][closed-form]") {
  const Mount m = mount(0.1, -0.2, 0.05, 0.07, 0.3);
  const double th = deg_to_rad(30.0);
  const Eigen::Vector3d q = probe_position_mm(m, 2.4, 0.0, th, 4.55);
  CHECK(q.x() == Approx(std::cos(th) * 2.5 + std::sin(th) * (-0.2) - 0.05).epsilon(1e-15));
  CHECK(q.y() == Approx(-std::sin(th) * 2.5 + std::cos(th) * (-0.2) - 0.07).epsilon(1e-15));
  CHECK(q.z() == Approx(4.85).epsilon(1e-15));
  // probe_paths_mm: column m*K + k is probe k at theta_m.
  const ProbeSetup s = setup_for("diff4", 2.4, 16);
  const Eigen::Matrix3Xd P = probe_paths_mm(s, m);
  REQUIRE(P.cols() == 64);
  const Eigen::Vector3d q32 = probe_position_mm(m, 0.0, -2.4, 2.0 * kPi * 3 / 16, 4.55);
  CHECK((P.col(3 * 4 + 3) - q32).norm() < 1e-14);
}

TEST_CASE("probe arrays parse with the documented weights", "[probe][contract]") {
  const ProbeArray two = ProbeArray::parse("two"), d4 = ProbeArray::parse("diff4"), r8 = ProbeArray::parse("ring:8");
  CHECK(two.size() == 2);
  CHECK(d4.w_cos == std::vector<double>{1, 0, -1, 0});
  REQUIRE(r8.size() == 8);
  CHECK(r8.angle_deg[3] == 135.0);
  CHECK(r8.w_sin[2] == Approx(1.0));
  for (const char* bad : {"three", "ring:", "ring:2", "ring:1025", "ring:8x", "ring:-4", "Two", ""})
    CHECK_THROWS_AS(ProbeArray::parse(bad), InputError);
}

TEST_CASE("ideal mount on the exact field: no error", "[probe][physics]") {
  // Bz on a circle about the axis is exactly proportional to cos(angle), so
  // the only error left is quadrature/round-off (~1e-12 relative -> ~1e-10 deg).
  const AnalyticField f{Magnet{}};
  for (const char* arr : {"two", "diff4", "ring:8"}) {
    const Spectrum s = error_spectrum(f, setup_for(arr), Mount{});
    CAPTURE(arr, s.pp_deg);
    CHECK(std::abs(s.a0_deg) < 1e-9);
    for (int n = 1; n <= kHarmonics; ++n) CHECK(s.c_deg[n] < 1e-9);
    CHECK(s.pp_deg < 1e-9);
  }
}

TEST_CASE("magnetization direction gives a constant offset wrapped to -180 < eps <= 180", "[probe][physics]") {
  // M0 rotated by alpha: Bz at magnet-frame azimuth psi ~ cos(psi - alpha); probe k
  // sits at psi = b_k - theta, so phi = theta + alpha and eps = wrap(alpha).
  for (double alpha : {30.0, -100.0, 180.0, 200.0}) {
    Magnet m;
    m.magnetization_deg = alpha;
    const AnalyticField f(m);
    const Spectrum s = error_spectrum(f, setup_for("ring:8", 2.4, 360), Mount{});
    CAPTURE(alpha, s.a0_deg, s.pp_deg);
    CHECK(s.a0_deg == Approx(wrap_deg(alpha)).margin(1e-9));
    CHECK(s.pp_deg < 1e-9);
  }
}

TEST_CASE("exact field: sy mirrors sx, and docs/physics.md's harmonic signatures", "[probe][physics]") {
  const AnalyticField f{Magnet{}};
  const ProbeSetup two = setup_for("two");
  SECTION("static y mirrors static x: a0 flips, a2 same, b2 flips") {
    const Spectrum x = error_spectrum(f, two, mount(0.1, 0, 0, 0)), y = error_spectrum(f, two, mount(0, 0.1, 0, 0));
    CAPTURE(x.a0_deg, x.a_deg[2], x.b_deg[2], y.a0_deg, y.a_deg[2], y.b_deg[2]);
    CHECK(y.a0_deg == Approx(-x.a0_deg).epsilon(1e-9));
    CHECK(y.a_deg[2] == Approx(x.a_deg[2]).epsilon(1e-9));
    CHECK(y.b_deg[2] == Approx(-x.b_deg[2]).epsilon(1e-9));
    CHECK(x.c_deg[2] > 10 * x.c_deg[4]);  // DC and 2nd dominate, a little 4th
    CHECK(x.c_deg[1] < 1e-9);
  }
  SECTION("dynamic x with `two`: 1st harmonic and a 3rd of similar size") {
    const Spectrum s = error_spectrum(f, two, mount(0, 0, 0.1, 0));
    CAPTURE(s.c_deg[1], s.c_deg[3]);
    CHECK(s.c_deg[3] > 0.1 * s.c_deg[1]);
    CHECK(s.c_deg[3] < s.c_deg[1]);
  }
  SECTION("dynamic x with diff4: 1st harmonic cancels, 4th appears") {
    const Spectrum s = error_spectrum(f, setup_for("diff4"), mount(0, 0, 0.1, 0));
    CAPTURE(s.c_deg[1], s.c_deg[4]);
    CHECK(s.c_deg[1] < 1e-9);
    CHECK(s.c_deg[4] > 1e-4);
  }
  SECTION("dz alone changes nothing") {
    const Spectrum s = error_spectrum(f, two, mount(0, 0, 0, 0, 0.3));
    CHECK(s.pp_deg < 1e-9);
  }
}

TEST_CASE("angle_error rejects invalid setups", "[probe][bad-input]") {
  const AnalyticField f{Magnet{}};
  const LinearField lin;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(angle_error(lin, setup_for("two", 0.0), Mount{}), InputError);
  CHECK_THROWS_AS(angle_error(lin, setup_for("two", -1.0), Mount{}), InputError);
  CHECK_THROWS_AS(angle_error(lin, setup_for("two", nan), Mount{}), InputError);
  CHECK_THROWS_AS(angle_error(lin, setup_for("two", 2.4, 15), Mount{}), InputError);
  CHECK_THROWS_AS(angle_error(lin, setup_for("two"), mount(nan, 0, 0, 0)), InputError);
  CHECK_THROWS_AS(angle_error(lin, setup_for("two"), mount(0, 0, 0, 0, nan)), InputError);
  // |s| + |d| >= r0: the probe circle no longer surrounds the axis (degenerate).
  CHECK_THROWS_AS(angle_error(lin, setup_for("two"), mount(1.5, 0, 0, 0.9)), InputError);
  CHECK_NOTHROW(angle_error(lin, setup_for("two"), mount(1.2, 0, 0, 0.9)));
  // A tilt needs the full field vector: the linear model (Bz only) refuses it (test_beyond_offsets).
  Mount tilted;
  tilted.tilt_x_deg = 1.0;
  CHECK_THROWS_AS(angle_error(lin, setup_for("two"), tilted), InputError);
  // Exact field: a path inside the magnet's volume is rejected. dz = -3 puts the
  // plane at z = 1.55 mm, within the magnet's height; r0 = 2.4 stays outside R = 2 ...
  CHECK_NOTHROW(angle_error(f, setup_for("two", 2.4, 64), mount(0, 0, 0, 0, -3.0)));
  // ... but with 0.5 mm dynamic eccentricity a probe comes within 1.9 mm of the axis.
  CHECK_THROWS_AS(angle_error(f, setup_for("two", 2.4, 64), mount(0, 0, 0.5, 0, -3.0)), InputError);
  CHECK_THROWS_AS(angle_error(f, setup_for("two", 1.5, 64), mount(0, 0, 0, 0, -3.0)), InputError);
  // The same geometry with the plane above the magnet is fine.
  CHECK_NOTHROW(angle_error(f, setup_for("two", 1.5, 64), Mount{}));
}

TEST_CASE("angle_error_at: arbitrary rotor angles give the same error as the uniform pipeline", "[probe][cross-check]") {
  const AnalyticField field(Magnet{});
  const ProbeSetup s = setup_for("two", 2.4, 360);
  const Mount m = mount(0.1, -0.05, 0.08, 0.02, 0.1);
  const AngleErrorResult uniform = angle_error(field, s, m);
  // The uniform angles in a shuffled order, plus angles between the samples.
  Eigen::VectorXd theta_deg(4);
  theta_deg << 270.0, 1.0, 0.0, 123.25;
  const AngleErrorResult at = angle_error_at(field, s, m, theta_deg);
  REQUIRE(at.eps_deg.size() == 4);
  CHECK(at.eps_deg[0] == Approx(uniform.eps_deg[270]).margin(1e-12));
  CHECK(at.eps_deg[1] == Approx(uniform.eps_deg[1]).margin(1e-12));
  CHECK(at.eps_deg[2] == Approx(uniform.eps_deg[0]).margin(1e-12));
  // Between samples (1 deg apart) the smooth curve lies near the linear interpolation of its neighbours:
  // error <= h^2/8 * max|eps''| with h = 0.0175 rad and |eps''| <~ n^2 c_n ~ 10 deg/rad^2 here: ~4e-4 deg.
  const double between = 0.75 * uniform.eps_deg[123] + 0.25 * uniform.eps_deg[124];
  CHECK(at.eps_deg[3] == Approx(between).margin(1e-3));
  CHECK(at.eps_deg[3] != Approx(uniform.eps_deg[123]).margin(1e-6));
}
