// "Beyond the five offsets" (docs/physics.md): sensor tilt, magnet tilt, signal
// chain. Kinematics against hand-built rotations, the zero-tilt identity with
// the five-offset pipeline, closed forms of the signal chain, symmetries, the
// reference values of docs/physics.md, and the sources that cannot serve a tilt.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "fields/grid_field.hpp"
#include "probe/angle_error.hpp"
#include "probe/common_keys.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

ProbeSetup setup_for(const std::string& array, int steps = 3600) {
  ProbeSetup s = test::probe_setup(array, steps);
  s.magnet_height_mm = 4.0;
  return s;
}

// The five-offset pipeline written out independently (docs/physics.md "Mounting
// kinematics"): q = Rot(-theta)(p_k + s) - d at z_s + dz, reading Bz.
Eigen::VectorXd five_offset_eps_deg(const FieldSource& f, const ProbeSetup& s, const Mount& m) {
  const int M = s.steps;
  const std::size_t K = s.array.size();
  Eigen::VectorXd eps(M);
  for (int i = 0; i < M; ++i) {
    const double th = 2.0 * kPi * i / M;
    double uc = 0, us = 0;
    for (std::size_t k = 0; k < K; ++k) {
      const double b = deg_to_rad(s.array.angle_deg[k]);
      const double X = s.r0_mm * std::cos(b) + m.sx_mm, Y = s.r0_mm * std::sin(b) + m.sy_mm;
      const Vec3 q(std::cos(th) * X + std::sin(th) * Y - m.dx_mm, -std::sin(th) * X + std::cos(th) * Y - m.dy_mm,
                   s.plane_z_mm + m.dz_mm);
      const double Bz = f.Bz_T(q);
      uc += s.array.w_cos[k] * Bz;
      us += s.array.w_sin[k] * Bz;
    }
    eps[i] = wrap_deg(rad_to_deg(std::atan2(us, uc) - th));
  }
  return eps;
}

}  // namespace

TEST_CASE("sensor tilt kinematics: Rs = Ry(b) Rx(a) about the sensor centre", "[probe][closed-form]") {
  const double a = deg_to_rad(30.0), b = deg_to_rad(20.0);
  // Rx(a) e_y = (0, cos a, sin a); Rx(a) e_z = (0, -sin a, cos a) (right-handed).
  CHECK((rot_x(a) * Eigen::Vector3d::UnitY() - Eigen::Vector3d(0, std::cos(a), std::sin(a))).norm() < 1e-15);
  CHECK((rot_y(b) * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(std::sin(b), 0, std::cos(b))).norm() < 1e-15);
  CHECK((rot_z(b) * Eigen::Vector3d::UnitX() - Eigen::Vector3d(std::cos(b), std::sin(b), 0)).norm() < 1e-15);
  Mount m;
  m.sx_mm = 0.1;
  m.sy_mm = -0.2;
  m.dz_mm = 0.3;
  m.tilt_x_deg = 30.0;
  // theta = 0, no magnet tilt, d = 0: magnet frame = fixed frame. Probe at (0, r0) on the sensor:
  // c + Rx(a) (0, r0, 0) = (sx, sy + r0 cos a, z_s + dz + r0 sin a).
  Eigen::Vector3d q = probe_position_mm(m, 0.0, 2.4, 0.0, 4.55);
  CHECK((q - Eigen::Vector3d(0.1, -0.2 + 2.4 * std::cos(a), 4.85 + 2.4 * std::sin(a))).norm() < 1e-14);
  CHECK((probe_normal(m, 0.0) - Eigen::Vector3d(0, -std::sin(a), std::cos(a))).norm() < 1e-15);
  // Both: first about x, then about y (fixed axes): n = Ry(b) Rx(a) e_z, written out.
  m.tilt_y_deg = 20.0;
  const Eigen::Vector3d n_expect(std::sin(b) * std::cos(a), -std::sin(a), std::cos(b) * std::cos(a));
  CHECK((probe_normal(m, 0.0) - n_expect).norm() < 1e-15);
  // Probe at (r0, 0): Ry(b) Rx(a) e_x = Ry(b) e_x = (cos b, 0, -sin b).
  q = probe_position_mm(m, 2.4, 0.0, 0.0, 4.55);
  CHECK((q - Eigen::Vector3d(0.1 + 2.4 * std::cos(b), -0.2, 4.85 - 2.4 * std::sin(b))).norm() < 1e-14);
  // At rotor angle theta the magnet frame sees the fixed-frame point turned by Rz(-theta).
  const double th = deg_to_rad(40.0);
  const Eigen::Vector3d fixed(0.1 + 2.4 * std::cos(b), -0.2, 4.85 - 2.4 * std::sin(b));
  CHECK((probe_position_mm(m, 2.4, 0.0, th, 4.55) - rot_z(-th) * fixed).norm() < 1e-14);
  CHECK((probe_normal(m, th) - rot_z(-th) * n_expect).norm() < 1e-15);
}

TEST_CASE("magnet tilt kinematics: pivot at the bottom-face centre, top leans towards psi", "[probe][closed-form]") {
  const double g = deg_to_rad(10.0), L = 4.0;
  for (const double psi_deg : {0.0, 90.0, 200.0}) {
    const double psi = deg_to_rad(psi_deg);
    Mount m;
    m.magnet_tilt_deg = 10.0;
    m.magnet_tilt_azimuth_deg = psi_deg;
    m.dx_mm = 0.05;
    m.dy_mm = -0.03;
    // The top-face centre (0, 0, L/2) of the magnet frame sits, in the rotor frame, at
    // d + P + Rt (0, 0, L) = d + (L sin g cos psi, L sin g sin psi, -L/2 + L cos g): the top
    // leans towards azimuth psi. A probe placed there (theta = 0: rotor = fixed frame) reads it.
    const Eigen::Vector3d top_rotor(0.05 + L * std::sin(g) * std::cos(psi), -0.03 + L * std::sin(g) * std::sin(psi),
                                    -L / 2 + L * std::cos(g));
    const Eigen::Vector3d q = probe_position_mm(m, top_rotor.x(), top_rotor.y(), 0.0, top_rotor.z(), L);
    CHECK((q - Eigen::Vector3d(0, 0, L / 2)).norm() < 1e-14);
    // The pivot itself (rotor frame d + P) is the bottom-face centre.
    const Eigen::Vector3d qp = probe_position_mm(m, 0.05, -0.03, 0.0, -L / 2, L);
    CHECK((qp - Eigen::Vector3d(0, 0, -L / 2)).norm() < 1e-14);
    // Directions: the rotor's z axis seen from the tilted magnet leans away from psi.
    const Eigen::Vector3d n = probe_normal(m, 0.0);
    CHECK((n - Eigen::Vector3d(-std::sin(g) * std::cos(psi), -std::sin(g) * std::sin(psi), std::cos(g))).norm() < 1e-15);
    // The wobble turns with the magnet: at theta the tilt is fixed in the rotor frame.
    const double th = deg_to_rad(70.0);
    const Eigen::Vector3d f(1.0, 2.0, 4.55);
    const Eigen::Vector3d r = rot_z(-th) * f;  // rotor-frame point
    const Eigen::Matrix3d Rt = rot_axis(Eigen::Vector3d(-std::sin(psi), std::cos(psi), 0), g);
    const Eigen::Vector3d P(0, 0, -L / 2), d(0.05, -0.03, 0);
    CHECK((probe_position_mm(m, 1.0, 2.0, th, 4.55, L) - (Rt.transpose() * (r - d - P) + P)).norm() < 1e-14);
  }
}

TEST_CASE("zero tilts and an ideal chain reproduce the five-offset pipeline", "[probe][regression]") {
  const AnalyticField f(Magnet{});
  for (const char* arr : {"two", "diff4", "ring:5"}) {
    const ProbeSetup s = setup_for(arr, 720);
    const Mount m{0.1, -0.05, 0.08, 0.02, 0.1};
    const Eigen::VectorXd want = five_offset_eps_deg(f, s, m);
    const AngleErrorResult got = angle_error(f, s, m);
    CHECK((got.eps_deg - want).cwiseAbs().maxCoeff() < 1e-12);
    // Positions: the full kinematics with zero tilts is the five-offset formula (to round-off: the
    // compiler may contract a*b + c*d differently in the two places).
    const double th = 0.3;
    const Eigen::Vector3d q = probe_position_mm(m, 2.4, 0.0, th, 4.55, 4.0);
    CHECK(q.x() == Approx(std::cos(th) * 2.5 + std::sin(th) * (-0.05) - 0.08).epsilon(0).margin(1e-15));
    CHECK(q.y() == Approx(-std::sin(th) * 2.5 + std::cos(th) * (-0.05) - 0.02).epsilon(0).margin(1e-15));
    CHECK(q.z() == 4.55 + 0.1);
  }
  // A tiny tilt takes the full-vector path (n.B); it must agree with the Bz path to O(tilt).
  const ProbeSetup s = setup_for("two", 360);
  Mount m{0.1, 0.0, 0.05, 0.0, 0.0};
  const Spectrum base = error_spectrum(f, s, m);
  m.tilt_x_deg = 1e-9;
  const Spectrum tiny = error_spectrum(f, s, m);
  CHECK(tiny.a0_deg == Approx(base.a0_deg).margin(1e-8));
  for (int n = 1; n <= kHarmonics; ++n) {
    CHECK(tiny.a_deg[n] == Approx(base.a_deg[n]).margin(1e-8));
    CHECK(tiny.b_deg[n] == Approx(base.b_deg[n]).margin(1e-8));
  }
}

TEST_CASE("reference values of docs/physics.md (exact field, default magnet, r0 2.4 mm, two)", "[probe][physics][regression]") {
  const AnalyticField f(Magnet{});
  const ProbeSetup two = setup_for("two");
  {  // sensor tilt_x 1 deg: a0 -0.403, c2 0.754 deg
    Mount m;
    m.tilt_x_deg = 1.0;
    const Spectrum s = error_spectrum(f, two, m);
    WARN("sensor tilt_x 1 deg: a0 " << s.a0_deg << " c1 " << s.c_deg[1] << " c2 " << s.c_deg[2] << " c3 "
                                    << s.c_deg[3] << " c4 " << s.c_deg[4]);
    CHECK(s.a0_deg == Approx(-0.403).margin(0.0005));
    CHECK(s.c_deg[2] == Approx(0.754).margin(0.0005));
  }
  {  // magnet tilt 1 deg at azimuth 0: c1 2.476, c3 0.259 deg
    Mount m;
    m.magnet_tilt_deg = 1.0;
    const Spectrum s = error_spectrum(f, two, m);
    WARN("magnet tilt 1 deg az 0: a0 " << s.a0_deg << " c1 " << s.c_deg[1] << " c2 " << s.c_deg[2] << " c3 "
                                       << s.c_deg[3]);
    CHECK(s.c_deg[1] == Approx(2.476).margin(0.0005));
    CHECK(s.c_deg[3] == Approx(0.259).margin(0.0005));
  }
  {  // oc 0.5 mT: c1 0.627 deg
    ProbeSetup s2 = two;
    s2.chain.offset_cos_mT = 0.5;
    const Spectrum s = error_spectrum(f, s2, Mount{});
    WARN("offset_cos 0.5 mT: a0 " << s.a0_deg << " c1 " << s.c_deg[1] << " c2 " << s.c_deg[2]);
    CHECK(s.c_deg[1] == Approx(0.627).margin(0.0005));
  }
  {  // g 0.01: c2 0.285 deg
    ProbeSetup s2 = two;
    s2.chain.gain_mismatch = 0.01;
    const Spectrum s = error_spectrum(f, s2, Mount{});
    WARN("gain 0.01: a0 " << s.a0_deg << " c1 " << s.c_deg[1] << " c2 " << s.c_deg[2]);
    CHECK(s.c_deg[2] == Approx(0.285).margin(0.0005));
  }
  {  // delta 1 deg: a0 0.500, c2 0.500 deg
    ProbeSetup s2 = two;
    s2.chain.phase_error_deg = 1.0;
    const Spectrum s = error_spectrum(f, s2, Mount{});
    WARN("phase 1 deg: a0 " << s.a0_deg << " c2 " << s.c_deg[2]);
    CHECK(s.a0_deg == Approx(0.500).margin(0.0005));
    CHECK(s.c_deg[2] == Approx(0.500).margin(0.0005));
  }
}

// ---- Signal chain: exact Fourier series for ideal signals u_c = A cos th, u_s = A sin th ----
// (ideal mount on the exact field: the two probes read exactly A cos th, A sin th).
//  * cos offset, e = oc/A: phi - th = arg(1 + e e^{-i th}) = sum_n (-1)^n (e^n/n) sin(n th):
//    b_n = (-1)^n e^n/n rad, a_n = 0, a0 = 0. Small e: a 1st harmonic of e rad.
//  * sin offset, e = os/A: phi - th = arg(1 + i e e^{-i th}) = sum_n (-1)^(n+1) (e^n/n) sin(n (pi/2 - th)):
//    n = 1 gives a1 = +e rad.
//  * gain, k = 1 + g: cos th + i k sin th = ((1+k)/2) e^{i th} (1 - q e^{-2i th}), q = (k-1)/(k+1), so
//    phi - th = sum_n (q^n/n) sin(2n th): b2 = q = g/(2+g) rad ~ g/2; odd harmonics 0.
//  * phase delta: cos th + i sin(th + delta) = cos(delta/2) e^{i(th + delta/2)} (1 + i t e^{-i(2 th + delta)}),
//    t = tan(delta/2), so phi - th = delta/2 + sum_n (-1)^(n+1) (t^n/n) sin(n (pi/2 - 2 th - delta)):
//    a0 = delta/2 exactly, c2 = t = tan(delta/2) ~ delta/2, c4 = t^2/2.
TEST_CASE("signal chain: offsets, gain and phase give their exact Fourier series", "[probe][closed-form]") {
  const AnalyticField f(Magnet{});
  ProbeSetup two = setup_for("two", 3600);
  const double A_T = f.Bz_T(Vec3(2.4, 0.0, 4.55));  // amplitude of both channels
  REQUIRE(A_T > 0.01);
  const double tol = 1e-9;  // deg: the exact field's ideal error is ~1e-10 deg; aliasing from n >= 3600 is nil
  SECTION("cos offset") {
    two.chain.offset_cos_mT = 0.5;
    const double e = 0.5e-3 / A_T;
    const Spectrum s = error_spectrum(f, two, Mount{});
    CHECK(s.a0_deg == Approx(0).margin(tol));
    for (int n = 1; n <= 4; ++n) {
      CAPTURE(n);
      CHECK(s.b_deg[n] == Approx(rad_to_deg(std::pow(-e, n) / n)).margin(tol));
      CHECK(s.a_deg[n] == Approx(0).margin(tol));
    }
    CHECK(s.c_deg[1] == Approx(rad_to_deg(e)).epsilon(1e-9));  // offset/amplitude rad
  }
  SECTION("sin offset") {
    two.chain.offset_sin_mT = -0.8;
    const double e = -0.8e-3 / A_T;
    const Spectrum s = error_spectrum(f, two, Mount{});
    // sin(n(pi/2 - th)) = sin(n pi/2) cos(n th) - cos(n pi/2) sin(n th)
    for (int n = 1; n <= 4; ++n) {
      const double cn = std::pow(-1.0, n + 1) * std::pow(e, n) / n;
      CAPTURE(n);
      CHECK(s.a_deg[n] == Approx(rad_to_deg(cn * std::sin(n * kPi / 2))).margin(tol));
      CHECK(s.b_deg[n] == Approx(rad_to_deg(-cn * std::cos(n * kPi / 2))).margin(tol));
    }
  }
  SECTION("gain mismatch") {
    for (const double g : {0.01, -0.05}) {
      two.chain.gain_mismatch = g;
      const double q = g / (2.0 + g);
      const Spectrum s = error_spectrum(f, two, Mount{});
      CAPTURE(g);
      CHECK(s.a0_deg == Approx(0).margin(tol));
      CHECK(s.b_deg[2] == Approx(rad_to_deg(q)).margin(tol));
      CHECK(s.b_deg[4] == Approx(rad_to_deg(q * q / 2)).margin(tol));
      CHECK(s.c_deg[1] == Approx(0).margin(tol));
      CHECK(s.c_deg[3] == Approx(0).margin(tol));
      CHECK(s.c_deg[2] == Approx(rad_to_deg(std::abs(g) / 2)).epsilon(std::abs(g)));  // small-signal g/2
    }
  }
  SECTION("phase error") {
    for (const double d_deg : {1.0, -3.0}) {
      two.chain.phase_error_deg = d_deg;
      const double d = deg_to_rad(d_deg), t = std::tan(d / 2);
      const Spectrum s = error_spectrum(f, two, Mount{});
      CAPTURE(d_deg);
      CHECK(s.a0_deg == Approx(d_deg / 2).margin(tol));
      CHECK(s.c_deg[2] == Approx(rad_to_deg(std::abs(t))).margin(tol));
      CHECK(s.c_deg[4] == Approx(rad_to_deg(t * t / 2)).margin(tol));
      // n = 1 term: t sin(pi/2 - 2 th - d) = t cos(2 th + d) = t (cos d cos 2th - sin d sin 2th)
      CHECK(s.a_deg[2] == Approx(rad_to_deg(t * std::cos(d))).margin(tol));
      CHECK(s.b_deg[2] == Approx(rad_to_deg(-t * std::sin(d))).margin(tol));
      CHECK(s.c_deg[1] == Approx(0).margin(tol));
    }
  }
  SECTION("chain is applied to the channels of any array") {
    // diff4 channels are 2A cos th, 2A sin th: the same offset gives half the error.
    ProbeSetup d4 = setup_for("diff4", 3600);
    d4.chain.offset_cos_mT = 0.5;
    const double e = 0.5e-3 / (2 * A_T);
    CHECK(error_spectrum(f, d4, Mount{}).b_deg[1] == Approx(rad_to_deg(-e)).margin(tol));
  }
}

TEST_CASE("signal chain validation and config keys", "[probe][bad-input]") {
  SignalChain c;
  c.gain_mismatch = -1.0;
  CHECK_THROWS_AS(c.validate(), InputError);
  c.gain_mismatch = 0;
  c.phase_error_deg = 90;
  CHECK_THROWS_AS(c.validate(), InputError);
  c.phase_error_deg = std::nan("");
  CHECK_THROWS_AS(c.validate(), InputError);
  Config cfg(common_keys());
  cfg.set("sensor.offset_cos_mT=0.5");
  cfg.set("sensor.offset_sin_mT=-0.25");
  cfg.set("sensor.gain_mismatch=0.01");
  cfg.set("sensor.phase_error_deg=1");
  const SignalChain r = SignalChain::from_config(cfg);
  CHECK(r.offset_cos_mT == 0.5);
  CHECK(r.offset_sin_mT == -0.25);
  CHECK(r.gain_mismatch == 0.01);
  CHECK(r.phase_error_deg == 1.0);
  CHECK_THROWS_AS(cfg.set("sensor.gain_mismatch=-1"), InputError);
  CHECK_THROWS_AS(cfg.set("sensor.phase_error_deg=90"), InputError);
  cfg.set("mount.tilt_x_deg=1.5");
  cfg.set("mount.tilt_y_deg=-0.5");
  cfg.set("mount.magnet_tilt_deg=2");
  cfg.set("mount.magnet_tilt_azimuth_deg=30");
  const Mount m = Mount::from_config(cfg);
  CHECK(m.tilt_x_deg == 1.5);
  CHECK(m.tilt_y_deg == -0.5);
  CHECK(m.magnet_tilt_deg == 2.0);
  CHECK(m.magnet_tilt_azimuth_deg == 30.0);
  CHECK_THROWS_AS(cfg.set("mount.tilt_x_deg=46"), InputError);
  cfg.set("magnet.magnetization_elevation_deg=5");
  CHECK(Magnet::from_config(cfg).magnetization_elevation_deg == 5.0);
  CHECK_THROWS_AS(cfg.set("magnet.magnetization_elevation_deg=91"), InputError);
}

namespace {
ProbeArray custom_two(double b0_deg) {  // probes at b0 and b0 + 90 with `two`'s weights
  ProbeArray a;
  a.name = "two@" + std::to_string(b0_deg);
  a.angle_deg = {b0_deg, b0_deg + 90.0};
  a.w_cos = {1.0, 0.0};
  a.w_sin = {0.0, 1.0};
  return a;
}
Eigen::Vector2d rot2(double x, double y, double g_deg) {
  const double g = deg_to_rad(g_deg);
  return {std::cos(g) * x - std::sin(g) * y, std::sin(g) * x + std::cos(g) * y};
}
}  // namespace

TEST_CASE("symmetry: rotating the whole set-up about the axis leaves the error unchanged", "[probe][physics]") {
  // Turning everything by gamma about the rotation axis (probe angles, s, d, the magnetization
  // azimuth, the magnet-tilt azimuth) is a rigid motion commuting with the rotor's turn: every probe
  // reads the same value at every theta, so eps(theta) is identical. A sensor tilt about x becomes,
  // for gamma = 90 deg, a tilt about y (Rz(90) Rx(a) Rz(-90) = Ry(a)).
  const int steps = 720;
  Magnet magA;
  const AnalyticField fA(magA);
  ProbeSetup sA = setup_for("two", steps);
  Mount mA{0.08, -0.03, 0.05, 0.02, 0.1};
  SECTION("sensor tilt_x <-> tilt_y by 90 deg") {
    mA.tilt_x_deg = 1.5;
    const Eigen::VectorXd eA = angle_error(fA, sA, mA).eps_deg;
    Magnet magB;
    magB.magnetization_deg = 90.0;
    const AnalyticField fB(magB);
    ProbeSetup sB = sA;
    sB.array = custom_two(90.0);
    Mount mB = mA;
    mB.tilt_x_deg = 0.0;
    mB.tilt_y_deg = 1.5;
    const Eigen::Vector2d s = rot2(mA.sx_mm, mA.sy_mm, 90), d = rot2(mA.dx_mm, mA.dy_mm, 90);
    mB.sx_mm = s.x();
    mB.sy_mm = s.y();
    mB.dx_mm = d.x();
    mB.dy_mm = d.y();
    const Eigen::VectorXd eB = angle_error(fB, sB, mB).eps_deg;
    CHECK((eA - eB).cwiseAbs().maxCoeff() < 1e-9);
    // ... and the tilt does matter (the check above is not vacuous).
    CHECK((eA - angle_error(fA, sA, Mount{0.08, -0.03, 0.05, 0.02, 0.1}).eps_deg).cwiseAbs().maxCoeff() > 0.1);
  }
  SECTION("magnet tilt azimuth by any angle") {
    mA.magnet_tilt_deg = 1.0;
    mA.magnet_tilt_azimuth_deg = 20.0;
    const Eigen::VectorXd eA = angle_error(fA, sA, mA).eps_deg;
    for (const double gamma : {37.0, 90.0, 180.0}) {
      Magnet magB;
      magB.magnetization_deg = gamma;
      const AnalyticField fB(magB);
      ProbeSetup sB = sA;
      sB.array = custom_two(gamma);
      Mount mB = mA;
      mB.magnet_tilt_azimuth_deg = 20.0 + gamma;
      const Eigen::Vector2d s = rot2(mA.sx_mm, mA.sy_mm, gamma), d = rot2(mA.dx_mm, mA.dy_mm, gamma);
      mB.sx_mm = s.x();
      mB.sy_mm = s.y();
      mB.dx_mm = d.x();
      mB.dy_mm = d.y();
      CAPTURE(gamma);
      CHECK((eA - angle_error(fB, sB, mB).eps_deg).cwiseAbs().maxCoeff() < 1e-9);
    }
  }
}

TEST_CASE("sources that know only Bz on a plane refuse tilts", "[probe][bad-input]") {
  const LinearField lin;
  CHECK_FALSE(lin.gives_full_vector());
  const ProbeSetup two = setup_for("two", 64);
  for (int which = 0; which < 3; ++which) {
    Mount m;
    (which == 0 ? m.tilt_x_deg : which == 1 ? m.tilt_y_deg : m.magnet_tilt_deg) = 0.5;
    try {
      angle_error(lin, two, m);
      FAIL("a tilt with the linear model must be refused");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CAPTURE(msg);
      CHECK(msg.find(which == 0 ? "mount.tilt_x_deg" : which == 1 ? "mount.tilt_y_deg" : "mount.magnet_tilt_deg") !=
            std::string::npos);
      CHECK(msg.find("linear") != std::string::npos);
      CHECK(msg.find('\n') == std::string::npos);
    }
  }
  // The signal chain needs no field vector: fine with the linear model.
  ProbeSetup chained = two;
  chained.chain.offset_cos_mT = 0.1;
  CHECK_NOTHROW(angle_error(lin, chained, Mount{}));
  // A 2-D plane grid (even one with the B vector) refuses; a 3-D box with B serves tilts.
  const AnalyticField f(Magnet{});
  const GridField plane(sample_grid(f, Vec3(-3.2, -3.2, 4.55), Vec3(0.2, 0.2, 0.2), {33, 33, 1}), Interp::Cubic);
  CHECK_FALSE(plane.gives_full_vector());
  Mount tilted;
  tilted.tilt_x_deg = 0.5;
  CHECK_THROWS_AS(angle_error(plane, two, tilted), InputError);
  const GridField box_bz(sample_grid(f, Vec3(-3.2, -3.2, 4.0), Vec3(0.2, 0.2, 0.1), {33, 33, 12}, true), Interp::Cubic);
  CHECK_FALSE(box_bz.gives_full_vector());
  const GridField box(sample_grid(f, Vec3(-3.2, -3.2, 4.0), Vec3(0.2, 0.2, 0.1), {33, 33, 12}), Interp::Cubic);
  CHECK(box.gives_full_vector());
  CHECK(f.gives_full_vector());
}

TEST_CASE("probe-in-magnet check with tilts (exact field)", "[probe][bad-input]") {
  const AnalyticField f(Magnet{});
  ProbeSetup s = setup_for("two", 64);
  // Sensor beside the magnet (plane within its height): r0 = 2.4 > R = 2 is fine untilted ...
  Mount m;
  m.dz_mm = -3.0;  // plane at z = 1.55
  CHECK_NOTHROW(angle_error(f, s, m));
  // ... a tilted magnet leans towards the probes: hull radius R + L sin g = 2 + 4 sin 10 = 2.69 > 2.4.
  m.magnet_tilt_deg = 10.0;
  CHECK_THROWS_AS(angle_error(f, s, m), InputError);
  // Sensor tilt moves the probes in z: tilt about x by 45 deg lifts the probe at (0, r0) by
  // r0 sin 45 = 1.70 mm, from z = 1.55 to 3.25, above the top face (2); probe 0 stays at 1.55.
  Mount t;
  t.dz_mm = -3.0;
  t.tilt_x_deg = 45.0;
  CHECK_NOTHROW(angle_error(f, s, t));
  // The magnet-height mismatch between setup and field is refused when the magnet is tilted.
  Mount g;
  g.magnet_tilt_deg = 1.0;
  ProbeSetup wrong = s;
  wrong.magnet_height_mm = 5.0;
  CHECK_THROWS_AS(angle_error(f, wrong, g), InputError);
  CHECK_NOTHROW(angle_error(f, s, g));
}

TEST_CASE("magnetization elevation in the probe pipeline", "[probe][physics]") {
  // The axial part is symmetric about the axis: a common offset on every probe. `two` sees a 1st
  // harmonic (~offset/amplitude rad); diff4 and ring:N cancel it exactly for an ideal mount.
  Magnet mag;
  mag.magnetization_elevation_deg = 5.0;
  const AnalyticField f(mag);
  const Spectrum two = error_spectrum(f, setup_for("two"), Mount{});
  WARN("elevation 5 deg, two: a0 " << two.a0_deg << " c1 " << two.c_deg[1] << " c2 " << two.c_deg[2] << " c3 "
                                  << two.c_deg[3]);
  CHECK(two.c_deg[1] == Approx(7.70).margin(0.005));
  // Closed form: channels A cos(el) cos th + C, A cos(el) sin th + C with C = sin(el) Bz_axial(r0):
  // the exact series of a cos offset plus a sin offset of the same size (see the chain test).
  for (const char* arr : {"diff4", "ring:8"}) {
    const Spectrum s = error_spectrum(f, setup_for(arr, 720), Mount{});
    CAPTURE(arr);
    CHECK(s.pp_deg < 1e-9);
  }
  // Equivalent to a channel offset of the axial field on both channels of `two`.
  const AnalyticField plain(Magnet{});
  Magnet axial;
  axial.magnetization_elevation_deg = 90.0;
  const double C_mT = 1e3 * AnalyticField(axial).Bz_T(Vec3(2.4, 0.0, 4.55)) * std::sin(deg_to_rad(5.0));
  ProbeSetup chain = setup_for("two");
  chain.chain.offset_cos_mT = chain.chain.offset_sin_mT = C_mT / std::cos(deg_to_rad(5.0));
  const Spectrum eq = error_spectrum(plain, chain, Mount{});
  CHECK(eq.c_deg[1] == Approx(two.c_deg[1]).epsilon(1e-9));
  CHECK(eq.c_deg[2] == Approx(two.c_deg[2]).epsilon(1e-6));
}

TEST_CASE("angle_error_at and probe_normals honour tilts, chain and elevation", "[probe][cross-check]") {
  Magnet mag;
  mag.magnetization_elevation_deg = 3.0;
  const AnalyticField f(mag);
  ProbeSetup s = setup_for("diff4", 360);
  s.chain.offset_cos_mT = 0.2;
  s.chain.gain_mismatch = -0.01;
  s.chain.phase_error_deg = 0.5;
  Mount m{0.05, -0.02, 0.03, 0.01, 0.1};
  m.tilt_x_deg = 0.7;
  m.tilt_y_deg = -0.4;
  m.magnet_tilt_deg = 0.6;
  m.magnet_tilt_azimuth_deg = 120.0;
  const AngleErrorResult uniform = angle_error(f, s, m);
  Eigen::VectorXd theta_deg(3);
  theta_deg << 359.0, 17.0, 0.0;
  const AngleErrorResult at = angle_error_at(f, s, m, theta_deg);
  CHECK(at.eps_deg[0] == Approx(uniform.eps_deg[359]).margin(1e-12));
  CHECK(at.eps_deg[1] == Approx(uniform.eps_deg[17]).margin(1e-12));
  CHECK(at.eps_deg[2] == Approx(uniform.eps_deg[0]).margin(1e-12));
  for (Eigen::Index k = 0; k < 4; ++k) CHECK(at.probe_B_T(1, k) == Approx(uniform.probe_B_T(17, k)).epsilon(1e-12));
  // Normals: one per probe and angle, unit, equal to probe_normal; the readings are n.B there.
  const Eigen::Matrix3Xd n = probe_normals(s, m, theta_deg);
  const Eigen::Matrix3Xd p = probe_paths_mm(s, m, theta_deg);
  REQUIRE(n.cols() == 12);
  for (Eigen::Index c = 0; c < n.cols(); ++c) {
    CHECK(n.col(c).norm() == Approx(1.0).epsilon(1e-15));
    const double th = deg_to_rad(theta_deg[c / 4]);
    CHECK((n.col(c) - probe_normal(m, th)).norm() < 1e-15);
    CHECK(at.probe_B_T(c / 4, c % 4) == Approx(n.col(c).dot(f.B_T(Vec3(p.col(c))))).epsilon(1e-13));
  }
}
