// Sensing principles (docs/physics.md "Sensor principles"): in-plane Hall, saturated
// xMR and AMR reading one spot, against docs/physics.md's reference values, closed
// forms derived here, the ideal mount, the AMR bookkeeping, the field window,
// finite sensing areas and the sources that cannot serve an in-plane principle.
//
// Closed form, small static eccentricity of an in-plane spot. Above a
// cylinder magnetized along +x the in-plane field obeys the two mirror
// symmetries of the magnet (x -> -x and y -> -y): Bx is even in x and in y,
// By odd in both. So on the axis Bx = -b0, By = 0 and every first derivative
// of (Bx, By) in x, y vanishes: to second order
//     Bx = -b0 + A x^2 + C y^2,   By = E x y,
// and curl_z B = dBy/dx - dBx/dy = (E - 2C) y = 0 gives E = 2C. The spot at
// sensor-frame offset s = |s| (cos sigma, sin sigma) sits in the magnet frame
// at q = Rot(-theta) s; the sensor sees the magnet-frame field turned by
// theta, so phi = theta + angle(-B(q)) and
//     eps(theta) = 2C x y / b0 = -(C |s|^2 / b0) sin(2 (sigma - theta))   (rad)
// to O(|s|^4): a pure 2nd harmonic of amplitude c2 = |C| |s|^2 / b0 and
// pp = 2 c2, no DC (A only changes the magnitude). C = (1/2) d2Bx/dy2 on the
// axis, taken from the exact field by a central difference.
//
// Closed forms of the signal chain on unit channels (the AMR bookkeeping):
// with x = 2 theta the electrical angle and phi = x'/2,
//   offset o on the cos channel: arg(e^{ix} + o) = x - sum_n (-o)^n/n sin(n x)... i.e.
//     eps = -(o/2) sin 2theta + (o^2/4) sin 4theta - ...: c2 = o/2, c4 = o^2/4 rad exactly;
//   gain 1 + g on the sin channel: cos x + i (1+g) sin x = (1+g/2) e^{ix} (1 - k e^{-2ix}),
//     k = g/(2+g): eps = (1/2) sum_n k^n/n sin(4 n theta): c4 = k/2 = g/(2(2+g)) ~ g/4, c8 = k^2/4 rad.
// The same algebra gives the in-plane spot under a sensor tilt a about x on the
// ideal mount: the die's y' axis sees cos(a) of the turning field (Bz = 0 on the
// axis), a gain of cos a - 1 on the sin channel: c2 = |k| = tan^2(a/2) rad.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "fields/grid_field.hpp"
#include "probe/angle_error.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

ProbeSetup point_setup(SensorPrinciple p, int steps = 3600) {
  ProbeSetup s = test::probe_setup("point", steps);
  s.principle = p;
  return s;
}

const AnalyticField& exact_field() {
  static const AnalyticField f{Magnet{}};
  return f;
}

const SensorPrinciple kInPlane[] = {SensorPrinciple::InPlane, SensorPrinciple::Xmr, SensorPrinciple::Amr};

double rad(double deg) { return deg_to_rad(deg); }

}  // namespace

TEST_CASE("in-plane principles: docs/physics.md reference values", "[probe][physics][regression]") {
  for (SensorPrinciple p : kInPlane) {
    CAPTURE(principle_name(p));
    const ProbeSetup s = point_setup(p);
    Mount m;
    m.sx_mm = 0.1;
    const AngleErrorResult sx = angle_error(exact_field(), s, m);
    CHECK(sx.spectrum.c_deg[2] == Approx(0.0340).margin(0.00005));
    CHECK(sx.spectrum.pp_deg == Approx(0.0680).margin(0.00005));
    // dx: a point on the axis sees a field turning rigidly with the rotor: only a constant.
    Mount d;
    d.dx_mm = 0.1;
    const AngleErrorResult dx = angle_error(exact_field(), s, d);
    CHECK(dx.spectrum.pp_deg < 1e-10);
    for (int n = 1; n <= kHarmonics; ++n) CHECK(dx.spectrum.c_deg[n] < 1e-10);
    // |b| of the ideal mount.
    const AngleErrorResult ideal = angle_error(exact_field(), s, Mount{});
    CHECK(ideal.field_min_mT == Approx(50.866).margin(0.0005));
    CHECK(ideal.field_max_mT == Approx(50.866).margin(0.0005));
    CHECK(ideal.field_max_mT - ideal.field_min_mT < 1e-9);
  }
}

TEST_CASE("ideal mount: zero error for every principle on the exact field", "[probe][physics]") {
  for (const std::string a : {"two", "diff4", "ring:8"}) {
    const ProbeSetup s = test::probe_setup(a, 720);
    const AngleErrorResult r = angle_error(exact_field(), s, Mount{});
    CAPTURE(a);
    CHECK(r.eps_deg.cwiseAbs().maxCoeff() < 1e-10);
  }
  for (SensorPrinciple p : kInPlane) {
    const AngleErrorResult r = angle_error(exact_field(), point_setup(p, 720), Mount{});
    CAPTURE(principle_name(p));
    CHECK(r.eps_deg.cwiseAbs().maxCoeff() < 1e-10);
    CHECK(r.in_window);
  }
}

TEST_CASE("in-plane static eccentricity: the second-order closed form", "[probe][closed-form]") {
  // C = (1/2) d2Bx/dy2 and b0 = -Bx on the axis of the sensing plane.
  const double z = 4.55, h = 0.01;
  const double bx0 = exact_field().B_T(Vec3(0, 0, z)).x();
  const double C =
      (exact_field().B_T(Vec3(0, h, z)).x() - 2 * bx0 + exact_field().B_T(Vec3(0, -h, z)).x()) / (2 * h * h);
  const double b0 = -bx0;
  REQUIRE(b0 > 0);
  for (double sigma_deg : {0.0, 30.0, 90.0}) {
    for (double s_mm : {0.02, 0.05}) {
      Mount m;
      m.sx_mm = s_mm * std::cos(rad(sigma_deg));
      m.sy_mm = s_mm * std::sin(rad(sigma_deg));
      const AngleErrorResult r = angle_error(exact_field(), point_setup(SensorPrinciple::InPlane), m);
      // eps = -(C s^2/b0) sin(2 sigma - 2 theta) = (C s^2/b0) [sin 2theta cos 2sigma - cos 2theta sin 2sigma].
      const double amp_deg = rad_to_deg(C * s_mm * s_mm / b0);
      CAPTURE(sigma_deg, s_mm, amp_deg);
      // O(s^4) next term: relative (s / a few mm)^2, below 1e-3 at 0.05 mm; the FD of C errs ~1e-5.
      const double tol = 2e-3 * std::abs(amp_deg) + 1e-12;
      CHECK(r.spectrum.b_deg[2] == Approx(amp_deg * std::cos(rad(2 * sigma_deg))).margin(tol));
      CHECK(r.spectrum.a_deg[2] == Approx(-amp_deg * std::sin(rad(2 * sigma_deg))).margin(tol));
      CHECK(std::abs(r.spectrum.a0_deg) < tol);
      CHECK(r.spectrum.c_deg[1] < tol);
      CHECK(r.spectrum.pp_deg == Approx(2 * std::abs(amp_deg)).epsilon(2e-3));
    }
  }
}

TEST_CASE("AMR bookkeeping: channel offset -> c2 = o/2, gain -> c4 = g/(2(2+g))", "[probe][closed-form]") {
  for (double o : {0.01, 0.05}) {
    ProbeSetup s = point_setup(SensorPrinciple::Amr);
    s.chain.offset_cos_rel = o;
    const AngleErrorResult r = angle_error(exact_field(), s, Mount{});
    CAPTURE(o);
    CHECK(rad(r.spectrum.c_deg[2]) == Approx(o / 2).epsilon(1e-9));
    CHECK(rad(r.spectrum.c_deg[4]) == Approx(o * o / 4).epsilon(1e-7));
    CHECK(r.spectrum.c_deg[1] < 1e-10);  // the 180-degree ambiguity: no odd harmonics
  }
  for (double g : {0.01, 0.04}) {
    ProbeSetup s = point_setup(SensorPrinciple::Amr);
    s.chain.gain_mismatch = g;
    const AngleErrorResult r = angle_error(exact_field(), s, Mount{});
    const double k = g / (2 + g);
    CAPTURE(g);
    CHECK(rad(r.spectrum.c_deg[4]) == Approx(k / 2).epsilon(1e-9));
    CHECK(rad(r.spectrum.c_deg[8]) == Approx(k * k / 4).epsilon(1e-7));
    CHECK(rad(r.spectrum.c_deg[4]) == Approx(g / 4).epsilon(0.6 * g));  // c4 ~ g/4 (to first order in g)
    CHECK(r.spectrum.c_deg[2] < 1e-10);
  }
  // xmr: the same offset on unit channels of the undoubled angle is a 1st harmonic of o rad.
  ProbeSetup x = point_setup(SensorPrinciple::Xmr);
  x.chain.offset_sin_rel = 0.01;
  CHECK(rad(angle_error(exact_field(), x, Mount{}).spectrum.c_deg[1]) == Approx(0.01).epsilon(1e-9));
}

TEST_CASE("AMR error is wrapped into -90 < eps <= 90 deg and sampled over the mechanical angle", "[probe][contract]") {
  ProbeSetup s = point_setup(SensorPrinciple::Amr, 360);
  s.chain.offset_cos_rel = 0.9;  // a large error, but |eps| < 90 deg
  s.chain.phase_error_deg = 60;
  const AngleErrorResult r = angle_error(exact_field(), s, Mount{});
  CHECK(r.eps_deg.maxCoeff() <= 90.0);
  CHECK(r.eps_deg.minCoeff() > -90.0);
  // Its spectrum has only even harmonics (the channels are functions of 2 theta).
  for (int n : {1, 3, 5, 7}) CHECK(r.spectrum.c_deg[n] < 1e-9);
}

TEST_CASE("in-plane spot under a sensor tilt: c2 = tan^2(a/2) rad", "[probe][closed-form]") {
  for (double a_deg : {2.0, 10.0}) {
    Mount m;
    m.tilt_x_deg = a_deg;
    const AngleErrorResult rx = angle_error(exact_field(), point_setup(SensorPrinciple::InPlane), m);
    const double t = std::tan(rad(a_deg) / 2);
    CAPTURE(a_deg);
    CHECK(rad(rx.spectrum.b_deg[2]) == Approx(-t * t).epsilon(1e-7));
    CHECK(std::abs(rx.spectrum.a_deg[2]) < 1e-10);
    Mount my;
    my.tilt_y_deg = a_deg;  // the cos channel sees cos b: the opposite sign
    const AngleErrorResult ry = angle_error(exact_field(), point_setup(SensorPrinciple::InPlane), my);
    CHECK(rad(ry.spectrum.b_deg[2]) == Approx(t * t).epsilon(1e-7));
  }
}

TEST_CASE("field window: extremes of the magnitude each principle uses", "[probe][contract]") {
  // bz `two`, ideal mount: each probe reads A cos(theta - b_k), peak A; min = max = A.
  ProbeSetup two = test::probe_setup("two", 720);
  const AngleErrorResult r = angle_error(exact_field(), two, Mount{});
  CHECK(r.field_min_mT == Approx(r.field_max_mT).epsilon(1e-6));
  CHECK(r.field_max_mT == Approx(r.probe_B_T.cwiseAbs().maxCoeff() * 1e3).epsilon(1e-15));
  CHECK(r.in_window);
  two.window.min_mT = r.field_max_mT + 1;
  CHECK_FALSE(angle_error(exact_field(), two, Mount{}).in_window);
  two.window = FieldWindow{0, r.field_min_mT - 1};
  CHECK_FALSE(angle_error(exact_field(), two, Mount{}).in_window);
  two.window = FieldWindow{r.field_min_mT - 1, r.field_max_mT + 1};
  CHECK(angle_error(exact_field(), two, Mount{}).in_window);
  // in-plane, static offset: hypot(b1, b2) varies over the turn; min < max, both near 50.87 mT.
  Mount m;
  m.sx_mm = 0.3;
  const AngleErrorResult p = angle_error(exact_field(), point_setup(SensorPrinciple::Xmr, 720), m);
  CHECK(p.field_min_mT < p.field_max_mT);
  CHECK(p.field_min_mT == Approx(p.probe_B_T.col(0).minCoeff() * 1e3));
  for (Eigen::Index i = 0; i < p.inplane_B_T.rows(); ++i)
    CHECK(p.probe_B_T(i, 0) == Approx(std::hypot(p.inplane_B_T(i, 0), p.inplane_B_T(i, 1))).epsilon(1e-15));
}

TEST_CASE("Gauss-Legendre rule: exact to degree 2n - 1", "[probe][closed-form]") {
  for (int n : {1, 2, 3, 5, 8, 16}) {
    std::vector<double> x, w;
    gauss_legendre(n, x, w);
    REQUIRE(x.size() == static_cast<std::size_t>(n));
    for (int d = 0; d <= 2 * n - 1; ++d) {
      double q = 0;
      for (int i = 0; i < n; ++i) q += w[static_cast<std::size_t>(i)] * std::pow(x[static_cast<std::size_t>(i)], d);
      const double exact = d % 2 ? 0.0 : 2.0 / (d + 1);
      CAPTURE(n, d);
      CHECK(q == Approx(exact).margin(1e-14));
    }
  }
}

TEST_CASE("finite sensing area: the mean over the square, converging with plate_points", "[probe][convergence]") {
  // Reference: one reading by a 200 x 200 midpoint rule over the square (error ~ (a/200)^2 f''),
  // against the pipeline's Gauss-Legendre mean at theta = 0 (column 0).
  const double a = 0.5;
  Mount m;
  m.sx_mm = 0.1;
  ProbeSetup s = point_setup(SensorPrinciple::InPlane, 16);
  s.area.plate_mm = a;
  s.area.plate_points = 8;
  const AngleErrorResult r = angle_error(exact_field(), s, m);
  // theta = 0: the spot centre at (sx, 0, z_s), die axes x, y.
  const int N = 200;
  double bx = 0, by = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      const Vec3 B = exact_field().B_T(Vec3(0.1 + a * ((i + 0.5) / N - 0.5), a * ((j + 0.5) / N - 0.5), 4.55));
      bx += B.x();
      by += B.y();
    }
  CHECK(r.inplane_B_T(0, 0) == Approx(bx / (N * N)).epsilon(1e-6));
  CHECK(r.inplane_B_T(0, 1) == Approx(by / (N * N)).margin(1e-9));
  // Convergence of a spectrum coefficient with n (bz two and in-plane): the changes shrink fast.
  for (const std::string arr : {"two", "point"}) {
    ProbeSetup t = arr == "two" ? test::probe_setup("two", 360) : point_setup(SensorPrinciple::InPlane, 360);
    t.area.plate_mm = 1.0;
    Mount mm;
    mm.sx_mm = 0.1;
    mm.dx_mm = 0.05;
    std::vector<double> c2;
    for (int n : {1, 2, 4, 8, 16}) {
      t.area.plate_points = n;
      c2.push_back(angle_error(exact_field(), t, mm).spectrum.c_deg[2]);
    }
    CAPTURE(arr, c2[0], c2[1], c2[2], c2[3], c2[4]);
    const double d2 = std::abs(c2[1] - c2[4]), d4 = std::abs(c2[2] - c2[4]), d8 = std::abs(c2[3] - c2[4]);
    CHECK(d4 < 0.1 * d2);
    CHECK(d8 < 1e-6 * std::abs(c2[4]) + 1e-12);
    CHECK(std::abs(c2[0] - c2[4]) > 1e-4 * std::abs(c2[4]));  // the area matters at 1 mm (n = 1 is the point)
  }
  // plate_mm = 0 is the point, bit for bit (bz and in-plane).
  ProbeSetup p0 = test::probe_setup("two", 64), p1 = p0;
  p1.area.plate_points = 9;  // unused at plate_mm = 0
  CHECK(angle_error(exact_field(), p0, m).eps_deg == angle_error(exact_field(), p1, m).eps_deg);
}

TEST_CASE("sensing principles: bad setups and sources are refused", "[probe][bad-input]") {
  const LinearField linear;
  CHECK_THROWS_WITH(angle_error(linear, point_setup(SensorPrinciple::InPlane, 64), Mount{}),
                    Catch::Contains("sensor.principle = inplane") && Catch::Contains("linear"));
  ProbeSetup wrong = test::probe_setup("two", 64);
  wrong.principle = SensorPrinciple::Xmr;
  CHECK_THROWS_WITH(angle_error(exact_field(), wrong, Mount{}), Catch::Contains("sensor.array = 'two'"));
  ProbeSetup bzpoint = test::probe_setup("point", 64);
  CHECK_THROWS_WITH(angle_error(exact_field(), bzpoint, Mount{}), Catch::Contains("sensor.principle = bz"));
  ProbeSetup rel = test::probe_setup("two", 64);
  rel.chain.offset_cos_rel = 0.01;
  CHECK_THROWS_WITH(angle_error(exact_field(), rel, Mount{}), Catch::Contains("sensor.offset_cos_rel"));
  ProbeSetup mT = point_setup(SensorPrinciple::Amr, 64);
  mT.chain.offset_sin_mT = 0.5;
  CHECK_THROWS_WITH(angle_error(exact_field(), mT, Mount{}), Catch::Contains("sensor.offset_sin_mT"));
  ProbeSetup plate = point_setup(SensorPrinciple::InPlane, 64);
  plate.area.plate_mm = -0.1;
  CHECK_THROWS_WITH(angle_error(exact_field(), plate, Mount{}), Catch::Contains("sensor.plate_mm"));
  ProbeSetup window = point_setup(SensorPrinciple::InPlane, 64);
  window.window = FieldWindow{80, 40};
  CHECK_THROWS_WITH(angle_error(exact_field(), window, Mount{}), Catch::Contains("sensor.field_min_mT"));
  // A spot far off the axis: the in-plane field there no longer turns once per turn.
  Mount far;
  far.sx_mm = 8.0;
  CHECK_THROWS_WITH(angle_error(exact_field(), point_setup(SensorPrinciple::InPlane, 360), far),
                    Catch::Contains("turns"));
}

TEST_CASE("in-plane principles on grid sources: a 3-D box serves them, a plane refuses", "[probe][cross-check]") {
  // The exact field sampled on a small 3-D box around the axis (cubic interpolation, 0.05 mm spacing),
  // and on a plane at z_s: the box reproduces the exact spectrum of sx 0.1 mm (c2 0.0340 deg) and of a
  // tilt to within the interpolation error (a few 1e-5 relative in B on this spacing: below 1e-4 deg here).
  const Vec3 origin(-0.5, -0.5, 4.55 - 0.3);
  const GridField box(sample_grid(exact_field(), origin, Vec3(0.05, 0.05, 0.05), {21, 21, 13}), Interp::Cubic);
  REQUIRE(box.gives_full_vector());
  Mount m;
  m.sx_mm = 0.1;
  m.tilt_x_deg = 2.0;
  m.dz_mm = 0.1;
  for (SensorPrinciple p : kInPlane) {
    const ProbeSetup s = point_setup(p, 360);
    const Spectrum g = angle_error(box, s, m).spectrum, e = angle_error(exact_field(), s, m).spectrum;
    CAPTURE(principle_name(p));
    CHECK(g.c_deg[2] == Approx(e.c_deg[2]).margin(1e-4));
    CHECK(g.pp_deg == Approx(e.pp_deg).margin(2e-4));
  }
  const GridField plane(sample_grid(exact_field(), Vec3(-0.5, -0.5, 4.55), Vec3(0.05, 0.05, 0.05), {21, 21, 1}),
                        Interp::Cubic);
  CHECK_THROWS_WITH(angle_error(plane, point_setup(SensorPrinciple::Amr, 64), Mount{}),
                    Catch::Contains("sensor.principle = amr") && Catch::Contains("only Bz on a plane"));
}
