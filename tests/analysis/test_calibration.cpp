// Calibration (src/analysis/calibration.*): the reference values of docs/physics.md "Calibration" on the
// exact field, exactness of each method where it must be exact, the interpolation rate of lut:K, the ogp
// ellipse against a synthetic signal chain, residuals after a change against closed forms, bad methods.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <omp.h>

#include "analysis/calibration.hpp"
#include "studies/calibration/calibration_study.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "probe/common_keys.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

double pp(const Eigen::VectorXd& v) { return v.maxCoeff() - v.minCoeff(); }

Mount mount_sd(double sx, double dx, double dz = 0) { return Mount{sx, 0, dx, 0, dz}; }

// A smooth periodic test curve e(phi) with harmonics 1..3 (deg).
double e_test(double phi_deg) {
  const double t = deg_to_rad(phi_deg);
  return 0.8 + 0.5 * std::sin(t) - 0.3 * std::cos(2 * t) + 0.2 * std::cos(3 * t + 1.0);
}

// Pairs whose error is exactly e_test of the sensor's angle: phi on a grid (offset so that no sample sits
// on a table node), theta = phi - e(phi).
void test_pairs(int n, Eigen::VectorXd& theta, Eigen::VectorXd& eps) {
  theta.resize(n);
  eps.resize(n);
  for (int i = 0; i < n; ++i) {
    const double phi = 360.0 * (i + 0.37) / n;
    eps[i] = e_test(phi);
    theta[i] = phi - eps[i];
  }
}

}  // namespace

TEST_CASE("calibration reference values of physics.md (two, r0 2.4, exact field)", "[analysis][physics][regression]") {
  // docs/physics.md "Calibration": calibrate at sx = dx = 0.1 mm; the reference values are given to 2-3
  // significant digits, so the bands below are the last digit's half-width (c3: the documented range).
  const AnalyticField f{Magnet{}};
  const ProbeSetup s = test::probe_setup("two", 3600, 2.4);
  const AngleErrorResult at = angle_error(f, s, mount_sd(0.1, 0.1));
  const AngleErrorResult run = angle_error(f, s, mount_sd(0.12, 0.08));
  const Correction h8 = calibrate(CalibrationMethod::parse("harmonics:8"), at, SensorPrinciple::Bz);
  const Correction l32 = calibrate(CalibrationMethod::parse("lut:32"), at, SensorPrinciple::Bz);
  const double h8_self = pp(residual_deg(h8, at)), l32_self = pp(residual_deg(l32, at));
  CAPTURE(pp(at.eps_deg), h8_self, l32_self);
  CHECK(h8_self == Approx(0.00094).margin(0.000005));
  CHECK(l32_self == Approx(0.137).margin(0.0005));
  for (const Correction* c : {&h8, &l32}) {
    const AngleErrorResult r = corrected(*c, run);
    CAPTURE(c->method.name(), r.spectrum.pp_deg, r.spectrum.c_deg[1], r.spectrum.c_deg[2], r.spectrum.c_deg[3]);
    CHECK(r.spectrum.pp_deg == Approx(1.43).margin(0.005 + 0.02));  // "about 1.43": both methods within 0.025
    CHECK(r.spectrum.c_deg[1] == Approx(0.49).margin(0.005));
    // c2: harmonics:8 gives 0.237, lut:32 0.254 (its table's own interpolation error adds to the change's);
    // physics.md gives one "about" value for both, so lut's band is the 0.015 it differs by, stated here.
    CHECK(r.spectrum.c_deg[2] == Approx(0.24).margin(c->method.kind == CalibrationKind::Lut ? 0.015 : 0.005));
    CHECK(r.spectrum.c_deg[3] >= 0.15 - 0.005);
    CHECK(r.spectrum.c_deg[3] <= 0.18 + 0.005);
  }
}

TEST_CASE("inplane: a calibration at dx 0.1 survives dz 0.2 exactly", "[analysis][physics]") {
  // physics.md: for the inplane point a change of the air gap leaves the residual of the calibration state.
  const AnalyticField f{Magnet{}};
  ProbeSetup s = test::probe_setup("point", 3600, 2.4);
  s.principle = SensorPrinciple::InPlane;
  const AngleErrorResult at = angle_error(f, s, mount_sd(0, 0.1));
  const AngleErrorResult run = angle_error(f, s, mount_sd(0, 0.1, 0.2));
  // The spot sits on the rotation axis: in the rotor frame it stays at -d, where the field's direction is
  // fixed relative to the magnet (and, d along M, along M by the mirror symmetry y -> -y), so eps is the
  // same at every theta (zero here) whatever dz; the correction taken at A leaves nothing at B.
  CHECK(pp(at.eps_deg) < 1e-9);
  CHECK(pp(run.eps_deg) < 1e-9);
  for (const char* m : {"harmonics:8", "lut:32", "ogp"}) {
    const Correction c = calibrate(CalibrationMethod::parse(m), at, s.principle);
    const Eigen::VectorXd r_at = residual_deg(c, at), r_run = residual_deg(c, run);
    CAPTURE(m, pp(r_at), pp(r_run), (r_run - r_at).cwiseAbs().maxCoeff());
    CHECK(r_run.cwiseAbs().maxCoeff() < 1e-9);
    CHECK((r_run - r_at).cwiseAbs().maxCoeff() < 1e-9);
  }
  // With a sensor eccentricity the same air-gap change does leave a residual (the check above can fail).
  const AngleErrorResult at_s = angle_error(f, s, mount_sd(0.1, 0.1)), run_s = angle_error(f, s, mount_sd(0.1, 0.1, 0.2));
  const Correction cs = calibrate(CalibrationMethod::parse("harmonics:8"), at_s, s.principle);
  CAPTURE(pp(at_s.eps_deg), pp(residual_deg(cs, at_s)), pp(residual_deg(cs, run_s)));
  CHECK(pp(at_s.eps_deg) > 0.1);
  CHECK(pp(residual_deg(cs, run_s)) > 10 * pp(residual_deg(cs, at_s)));
}

TEST_CASE("harmonics:N with N at least the curve's highest harmonic leaves round-off", "[analysis][closed-form]") {
  // e(phi) has harmonics up to 3: harmonics:3 and above reproduce it to round-off; harmonics:2 cannot.
  Eigen::VectorXd theta, eps;
  test_pairs(721, theta, eps);
  for (int N : {3, 5, 8}) {
    const Correction c = correct_pairs(CalibrationMethod::parse("harmonics:" + std::to_string(N)), theta + eps, eps);
    const double r = residual_of_pairs(c, theta, eps).cwiseAbs().maxCoeff();
    CAPTURE(N, r);
    CHECK(r < 1e-9);
  }
  const Correction c2 = correct_pairs(CalibrationMethod::parse("harmonics:2"), theta + eps, eps);
  CHECK(residual_of_pairs(c2, theta, eps).cwiseAbs().maxCoeff() > 0.1);
}

TEST_CASE("lut:K interpolation error falls as K^-2", "[analysis][convergence]") {
  // Periodic linear interpolation of a smooth function: max error ~ h^2 max|e''| / 8 with h = 360/K. The
  // pairs are dense (36000) so the table values are the curve's to ~1e-6 of the error at K = 128.
  Eigen::VectorXd theta, eps;
  test_pairs(36000, theta, eps);
  std::vector<double> err;
  const std::vector<int> Ks{16, 32, 64, 128};
  for (int K : Ks) {
    const Correction c = correct_pairs(CalibrationMethod::parse("lut:" + std::to_string(K)), theta + eps, eps);
    err.push_back(residual_of_pairs(c, theta, eps).cwiseAbs().maxCoeff());
  }
  for (std::size_t i = 1; i < Ks.size(); ++i) {
    const double rate = std::log(err[i - 1] / err[i]) / std::log(2.0);
    CAPTURE(Ks[i], err[i - 1], err[i], rate);
    CHECK(rate == Approx(2.0).margin(0.05));
  }
  // A table value at a node equals the curve there (the pairs bracket it closely).
  const Correction c = correct_pairs(CalibrationMethod::parse("lut:16"), theta + eps, eps);
  for (int k = 0; k < 16; ++k) CHECK(c.lut_deg[k] == Approx(e_test(360.0 * k / 16)).margin(1e-4));
}

TEST_CASE("ogp recovers a synthetic signal chain", "[analysis][closed-form]") {
  // Ideal channels A (cos theta, sin theta) through the chain of probe/signal_chain.hpp: the ellipse fit
  // returns its offsets, 1 + g and delta, and the inverted angle is theta again.
  SignalChain chain;
  chain.offset_cos_mT = 1.7;
  chain.offset_sin_mT = -0.9;
  chain.gain_mismatch = 0.04;
  chain.phase_error_deg = 2.5;
  const SignalChain::Applied ap = chain.applied();
  const int M = 1000;
  const double A = 0.05;  // T
  Eigen::MatrixXd ch(M, 2);
  Eigen::VectorXd theta(M);
  for (int m = 0; m < M; ++m) {
    theta[m] = 360.0 * m / M;
    double c = A * std::cos(deg_to_rad(theta[m])), s = A * std::sin(deg_to_rad(theta[m]));
    ap(c, s);
    ch(m, 0) = c;
    ch(m, 1) = s;
  }
  const Correction k = correct_channels(ch);
  CHECK(k.ellipse.offset_cos == Approx(1.7e-3).margin(1e-12));
  CHECK(k.ellipse.offset_sin == Approx(-0.9e-3).margin(1e-12));
  CHECK(k.ellipse.gain_ratio == Approx(1.04).margin(1e-9));
  CHECK(k.ellipse.phase_deg == Approx(2.5).margin(1e-9));
  double worst = 0;
  for (int m = 0; m < M; ++m)
    worst = std::max(worst, std::abs(wrap_deg(k.ellipse.angle_deg(ch(m, 0), ch(m, 1)) - theta[m])));
  CHECK(worst < 1e-9);
  // The same through the pipeline on the exact field (ideal mount: the channels are an exact ellipse).
  const AnalyticField f{Magnet{}};
  ProbeSetup s = test::probe_setup("two", 720, 2.4);
  s.chain = chain;
  const AngleErrorResult at = angle_error(f, s, Mount{});
  CHECK(pp(at.eps_deg) > 1.0);
  const Correction kp = calibrate(CalibrationMethod::parse("ogp"), at, SensorPrinciple::Bz);
  CHECK(kp.ellipse.gain_ratio == Approx(1.04).margin(1e-9));
  CHECK(kp.ellipse.phase_deg == Approx(2.5).margin(1e-9));
  CHECK(residual_deg(kp, at).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("residual after a change equals its closed form", "[analysis][closed-form]") {
  const AnalyticField f0{Magnet{}};
  const ProbeSetup s = test::probe_setup("two", 360, 2.4);
  SECTION("harmonics and lut of a constant offset: the change of the magnetization direction is left") {
    // eps = wrap(alpha) for an ideal mount (test_angle_error): calibrated at alpha 30, run at alpha 45.
    Magnet ma, mb;
    ma.magnetization_deg = 30;
    mb.magnetization_deg = 45;
    const AnalyticField fa(ma), fb(mb);
    const AngleErrorResult at = angle_error(fa, s, Mount{}), run = angle_error(fb, s, Mount{});
    for (const char* m : {"harmonics:4", "lut:16"}) {
      const Eigen::VectorXd r = residual_deg(calibrate(CalibrationMethod::parse(m), at, SensorPrinciple::Bz), run);
      CAPTURE(m);
      CHECK((r.array() - 15.0).abs().maxCoeff() < 1e-9);
    }
  }
  SECTION("ogp at one channel offset, run at another: the offset difference on a circle") {
    // Ideal mount: channels A (cos, sin) theta with A the probe amplitude; after the correction the
    // channels are A (cos, sin) theta + (dc, ds), so eps' = atan2(A sin + ds, A cos + dc) - theta.
    ProbeSetup sa = s, sb = s;
    sa.chain.offset_cos_mT = 2.0;
    sb.chain.offset_cos_mT = 3.0;
    sb.chain.offset_sin_mT = -1.0;
    const AngleErrorResult at = angle_error(f0, sa, Mount{}), run = angle_error(f0, sb, Mount{});
    const double A = angle_error(f0, s, Mount{}).probe_B_T.col(0).maxCoeff();
    const Eigen::VectorXd r = residual_deg(calibrate(CalibrationMethod::parse("ogp"), at, SensorPrinciple::Bz), run);
    double worst = 0;
    for (Eigen::Index m = 0; m < r.size(); ++m) {
      const double t = deg_to_rad(run.theta_deg[m]);
      const double expect = wrap_deg(rad_to_deg(std::atan2(A * std::sin(t) - 1e-3, A * std::cos(t) + 1e-3)) -
                                     run.theta_deg[m]);
      worst = std::max(worst, std::abs(r[m] - expect));
    }
    CAPTURE(A, pp(r), worst);
    CHECK(pp(r) > 0.5);
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("calibration with reference noise and quantization", "[analysis][physics][determinism]") {
  // The calibration run observed through diagnose's readout: quantization to 8192 positions and 0.005 deg
  // reference noise leave a residual at the calibration state of the order of the noise, not of the curve.
  const AnalyticField f{Magnet{}};
  const ProbeSetup s = test::probe_setup("two", 3600, 2.4);
  const AngleErrorResult at = angle_error(f, s, mount_sd(0.1, 0.1));
  const ReferenceReadout ro{0.005, 8192, 0.0};
  std::mt19937 r1(7), r2(7);
  const Correction c1 = calibrate(CalibrationMethod::parse("harmonics:8"), at, SensorPrinciple::Bz, ro, r1);
  const Correction c2 = calibrate(CalibrationMethod::parse("harmonics:8"), at, SensorPrinciple::Bz, ro, r2);
  CHECK(c1.harmonics_deg == c2.harmonics_deg);  // seeded: the same draw gives the same table
  const double res = pp(residual_deg(c1, at));
  CAPTURE(pp(at.eps_deg), res);
  CHECK(res > 0.00094);  // noise adds to the truncation
  CHECK(res < 0.01);
}

TEST_CASE("calibration methods: bad text is one error naming the key", "[analysis][bad-input]") {
  for (const char* bad : {"", "harmonics", "harmonics:", "harmonics:0", "harmonics:-1", "harmonics:257", "lut:3",
                          "lut:x", "lut:65537", "LUT:32", "ogp:2", "harmonics:8 ", "lut:99999999999"}) {
    CAPTURE(bad);
    try {
      (void)CalibrationMethod::parse(bad);
      FAIL("accepted");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CHECK(msg.find("calibration.method") != std::string::npos);
      CHECK(msg.find("allowed") != std::string::npos);
      CHECK(msg.find('\n') == std::string::npos);
    }
  }
  CHECK(CalibrationMethod::parse("lut:32").name() == "lut:32");
  CHECK(CalibrationMethod::parse("harmonics:8").order == 8);
  Eigen::VectorXd theta, eps;
  test_pairs(10, theta, eps);
  CHECK_THROWS_AS(correct_pairs(CalibrationMethod::parse("harmonics:5"), theta + eps, eps), InputError);
  CHECK_THROWS_AS(correct_pairs(CalibrationMethod::parse("ogp"), theta + eps, eps), InputError);
  Eigen::MatrixXd line(20, 2);
  for (int i = 0; i < 20; ++i) line.row(i) << i, 2.0 * i;
  CHECK_THROWS_AS(correct_channels(line), InputError);
}

TEST_CASE("the configured calibration: calibration.at over the run's values", "[analysis][contract][bad-input]") {
  Config cfg(merge_schemas(common_keys(), calibration_keys()));
  const AnalyticField f{Magnet{}};
  // Default method none: no correction, the run unchanged.
  const Correction none = correction_from_config(f, cfg, "two");
  CHECK(none.method.none());
  // The state is the run's configuration with the listed keys replaced.
  cfg.set("sensor.r0_mm=2.4");
  cfg.set("mount.sy_mm=0.05");
  cfg.set("calibration.method=harmonics:8");
  const Config state = calibration_state(cfg);
  CHECK(state.real("mount.sx_mm") == 0.1);
  CHECK(state.real("mount.dx_mm") == 0.1);
  CHECK(state.real("mount.sy_mm") == 0.05);  // the run's own value
  // The configured correction is the one taken by hand at that state.
  const Correction c = correction_from_config(f, cfg, "two");
  const ProbeSetup s = sensor_setup_from_config(state, "two");
  const Correction by_hand =
      calibrate(CalibrationMethod::parse("harmonics:8"), angle_error(f, s, Mount{0.1, 0.05, 0.1, 0, 0}), s.principle);
  CHECK((c.harmonics_deg - by_hand.harmonics_deg).cwiseAbs().maxCoeff() == 0.0);
  for (const char* bad : {"calibration.at={ mount.nope_mm = 1 }", "calibration.at={ magnet.br_T = 1.2 }",
                          "calibration.at={ calibration.method = \"ogp\" }", "calibration.at={ mount.tilt_x_deg = 90 }"}) {
    CAPTURE(bad);
    cfg.set(bad);
    try {
      (void)calibration_state(cfg);
      FAIL("accepted");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CHECK(msg.find("calibration.at") != std::string::npos);
      CHECK(msg.find('\n') == std::string::npos);
    }
  }
  cfg.set("calibration.at={}");
  cfg.set("calibration.method=lut:2");
  CHECK_THROWS_AS(correction_from_config(f, cfg, "two"), InputError);
}

TEST_CASE("calibration study: no drift leaves the factory residual, threads do not matter, bad drift keys",
          "[analysis][determinism][bad-input]") {
  Config cfg(merge_schemas(common_keys(), CalibrationStudyOptions::keys()));
  cfg.set("study.samples=24");
  cfg.set("study.mc_steps=180");
  cfg.set("study.sensors=[\"two\", \"inplane\"]");
  cfg.set("study.drift_scales=[1]");
  const AnalyticField f{Magnet{}};
  SECTION("a drift box of zero half-widths: every scenario equals the factory state") {
    cfg.set("drift.keys=[{ key = \"mount.sx_mm\", half_width = 0 }]");
    const CalibrationStudyResult r = run_calibration_study(f, cfg, CalibrationStudyOptions::from_config(cfg));
    for (const auto& s : r.sensors) {
      CAPTURE(s.label);
      CHECK((s.p99.row(s.scale1) - s.p99.row(0)).cwiseAbs().maxCoeff() == 0.0);
      CHECK(s.uncal_p99[static_cast<Eigen::Index>(s.scale1)] == s.uncal_p99[0]);
      CHECK(s.p99(0, 0) < 0.01);  // harmonics:8 at its own state (two: ~3e-4 deg, inplane: 0)
    }
  }
  SECTION("the same results with 1 and 2 threads") {
    const auto opt = CalibrationStudyOptions::from_config(cfg);
    omp_set_num_threads(1);
    const CalibrationStudyResult a = run_calibration_study(f, cfg, opt);
    omp_set_num_threads(2);
    const CalibrationStudyResult b = run_calibration_study(f, cfg, opt);
    for (std::size_t i = 0; i < a.sensors.size(); ++i) {
      CHECK(a.sensors[i].p99 == b.sensors[i].p99);
      CHECK(a.sensors[i].uncal_p99 == b.sensors[i].uncal_p99);
      CHECK(a.sensors[i].p99(1, 0) > a.sensors[i].p99(0, 0));  // the drift leaves more than the factory state
    }
  }
  for (const char* bad : {"drift.keys=[{ key = \"magnet.br_T\", half_width = 0.01 }]",
                          "drift.keys=[{ key = \"mount.nope_mm\", half_width = 0.01 }]",
                          "drift.keys=[{ key = \"sensor.array\", half_width = 1 }]",
                          "drift.keys=[{ key = \"mount.sx_mm\", half_width = 0.01 }, { key = \"mount.sx_mm\", half_width = 0.02 }]",
                          "study.methods=[\"spline\"]"}) {
    CAPTURE(bad);
    Config c = cfg;
    c.set(bad);
    try {
      (void)CalibrationStudyOptions::from_config(c);
      FAIL("accepted");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CHECK((msg.find("drift.keys") != std::string::npos || msg.find("study.methods") != std::string::npos));
      CHECK(msg.find('\n') == std::string::npos);
    }
  }
}

TEST_CASE("calibrated_pp_deg (angles or unit vectors) equals correct_pairs + residual_of_pairs to round-off", "[analysis][cross-check]") {
  // Error curves of the size of the Monte Carlo's (a few tenths of a degree, harmonics 1..3 and 5) at the
  // calibration state and, changed, at the run state; one with a large error (psi far from uniform).
  const int n = 360;
  Eigen::VectorXd theta(n), ec(n), er(n);
  for (double scale : {0.3, 4.0, 40.0}) {
    for (int i = 0; i < n; ++i) {
      theta[i] = 360.0 * i / n;
      const double t = deg_to_rad(theta[i]);
      ec[i] = scale * (0.4 * std::sin(t + 0.2) - 0.25 * std::cos(2 * t) + 0.1 * std::sin(3 * t) + 0.03 * std::cos(5 * t + 1));
      er[i] = ec[i] + scale * (0.05 * std::cos(t) + 0.02 * std::sin(2 * t + 0.5) + 0.01 * std::cos(7 * t));
    }
    for (const char* m : {"harmonics:1", "harmonics:4", "harmonics:8", "harmonics:20", "harmonics:80", "lut:32", "none"}) {
      const CalibrationMethod method = CalibrationMethod::parse(m, "test");
      for (int turns : {1, 2}) {
        const Correction c = correct_pairs(method, theta + ec, ec, turns);
        const double ref = pp(residual_of_pairs(c, theta, er));
        const double fast = calibrated_pp_deg(method, theta, ec, er, turns);
        CAPTURE(scale, m, turns, ref, fast);
        CHECK(std::abs(fast - ref) <= 1e-11 * std::max(1.0, scale));
        if (turns == 1) {
          // The same with the sensor's angles given as unit vectors (FastPipeline's UnitAngles).
          const Eigen::ArrayXd pc = (theta + ec).array() * (kPi / 180.0), pr = (theta + er).array() * (kPi / 180.0);
          const double unit = calibrated_pp_deg(method, theta, ec, pc.cos().matrix(), pc.sin().matrix(), er,
                                                pr.cos().matrix(), pr.sin().matrix());
          CAPTURE(unit);
          CHECK(std::abs(unit - ref) <= 1e-11 * std::max(1.0, scale));
        }
      }
    }
  }
}

TEST_CASE("ogp: channels that do not follow the fitted ellipse are refused, one line", "[analysis][bad-input]") {
  const int n = 360;
  Eigen::VectorXd c(n), s(n);
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  // Channels about a circle whose radius scatters by 50 % (a loose connector, a probe in noise): the
  // algebraic fit still finds an ellipse (pure noise gives a hyperbola, refused before), but the samples
  // do not follow it.
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n, r = std::max(0.05, 1 + 0.5 * g(rng));
    c[i] = r * std::cos(t), s[i] = r * std::sin(t);
  }
  try {
    fit_channel_ellipse(c, s);
    FAIL("noise taken for an ellipse");
  } catch (const InputError& e) {
    const std::string m = e.what();
    CAPTURE(m);
    CHECK(m.find("ogp calibration: the channels leave the fitted ellipse by ") == 0);
    CHECK(m.find("allowed at most 25 %") != std::string::npos);
    CHECK(m.find('\n') == std::string::npos);
  }
  // A real chain: offsets, gain ratio, phase and a 3 % third harmonic in each channel is read.
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    c[i] = 0.1 + std::cos(t) + 0.03 * std::cos(3 * t);
    s[i] = -0.05 + 1.1 * std::sin(t + 0.05) + 0.03 * std::sin(3 * t);
  }
  ChannelEllipse el;
  REQUIRE_NOTHROW(el = fit_channel_ellipse(c, s));
  CHECK(el.gain_ratio == Approx(1.1).epsilon(0.1));  // the harmonics bias the algebraic fit by a few %
}
