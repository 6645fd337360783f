// The turning encoder (src/probe/speed.*, docs/physics.md "Speed: the error of a turning encoder"):
// docs/physics.md's reference values, closed forms on other numbers, the static pipeline untouched at
// rpm 0, a brute-force simulation in time against the steady state, and bad input.
//
// Closed forms used below (ideal mount, exact field: the static channels are A cos theta, A sin theta):
//  * a delay tau on both channels turns the output back by omega tau: eps = -omega tau = -6 n tau deg
//    (n in rpm, tau in s), constant;
//  * a first-order filter at omega_c shifts the fundamental by -atan(omega / omega_c) and scales both
//    channels alike: eps = -atan(omega / omega_c), constant (amr: channels at 2 omega, eps =
//    -atan(2 omega / omega_c) / 2);
//  * a skew s of the sin channel: atan2(sin(theta - d), cos theta) - theta with d = omega s has the mean
//    -d/2 and the 2nd harmonic of amplitude d/2 rad (to first order in d);
//  * a zero-order hold at f_s: eps(theta) = theta_j - theta, theta_j the angle of the last sample, a
//    sawtooth from 0 to -360 n / (60 f_s) deg.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "probe/common_keys.hpp"
#include "probe/speed.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

namespace {

const AnalyticField& exact_field() {
  static const AnalyticField f{Magnet{}};
  return f;
}

ProbeSetup at_speed(double rpm, const std::string& array = "two", int steps = 3600) {
  ProbeSetup s = test::probe_setup(array, steps);
  s.speed.rpm = rpm;
  return s;
}

ProbeSetup point_at_speed(double rpm, SensorPrinciple p, int steps = 3600) {
  ProbeSetup s = at_speed(rpm, "point", steps);
  s.principle = p;
  return s;
}

Mount dx(double v) {
  Mount m;
  m.dx_mm = v;
  return m;
}

AngleErrorResult run(const ProbeSetup& s, const Mount& m = Mount{}) { return angle_error(exact_field(), s, m); }

double max_abs_harmonic(const Spectrum& sp) {
  double c = 0;
  for (int n = 1; n <= kHarmonics; ++n) c = std::max(c, sp.c_deg[n]);
  return c;
}

bool one_line(const std::string& s) { return s.find('\n') == std::string::npos; }

}  // namespace

TEST_CASE("speed: docs/physics.md reference values", "[probe][physics][regression]") {
  SECTION("delay 100 us: a0 -3.6 deg exactly, nothing else") {
    ProbeSetup s = at_speed(6000);
    s.speed.delay_us = 100;
    const Spectrum sp = run(s).spectrum;
    CHECK(sp.a0_deg == Approx(-3.6).margin(1e-9));
    CHECK(max_abs_harmonic(sp) < 1e-9);
    CHECK(sp.pp_deg < 1e-9);
  }
  SECTION("filter 1 kHz: a0 -5.71059") {
    ProbeSetup s = at_speed(6000);
    s.speed.filter_hz = 1000;
    const Spectrum sp = run(s).spectrum;
    CHECK(sp.a0_deg == Approx(-5.71059).margin(5e-6));
    CHECK(max_abs_harmonic(sp) < 1e-9);
  }
  SECTION("skew 10 us: a0 -0.18, c2 0.18, pp 0.36") {
    ProbeSetup s = at_speed(6000);
    s.speed.skew_us = 10;
    const Spectrum sp = run(s).spectrum;
    CHECK(sp.a0_deg == Approx(-0.18).margin(5e-6));
    CHECK(sp.c_deg[2] == Approx(0.18).margin(5e-6));
    CHECK(sp.pp_deg == Approx(0.36).margin(5e-6));
  }
  SECTION("sample 10 kHz: a0 -1.75, pp 3.5 on the 3600-step grid") {
    ProbeSetup s = at_speed(6000);
    s.speed.sample_hz = 10000;
    const Spectrum sp = run(s).spectrum;
    CHECK(sp.a0_deg == Approx(-1.75).margin(1e-9));
    CHECK(sp.pp_deg == Approx(3.5).margin(1e-9));
  }
  SECTION("delay 100 us + filter 1 kHz + ideal prediction: 0") {
    ProbeSetup s = at_speed(6000);
    s.speed.delay_us = 100;
    s.speed.filter_hz = 1000;
    s.speed.prediction = Prediction::Ideal;
    CHECK(run(s).eps_deg.cwiseAbs().maxCoeff() < 1e-9);
  }
  SECTION("dx 0.1 mm with filter 1 kHz: c1 2.50438, c3 0.85690 (static 2.50884, 0.86950)") {
    ProbeSetup s = at_speed(6000);
    s.speed.filter_hz = 1000;
    const Spectrum moving = run(s, dx(0.1)).spectrum;
    CHECK(moving.c_deg[1] == Approx(2.50438).margin(5e-6));
    CHECK(moving.c_deg[3] == Approx(0.85690).margin(5e-6));
    const Spectrum still = run(test::probe_setup("two"), dx(0.1)).spectrum;
    CHECK(still.c_deg[1] == Approx(2.50884).margin(5e-6));
    CHECK(still.c_deg[3] == Approx(0.86950).margin(5e-6));
  }
  SECTION("-6000 rpm flips the sign of a0") {
    for (const double delay_us : {0.0, 100.0}) {
      ProbeSetup fwd = at_speed(6000), back = at_speed(-6000);
      fwd.speed.delay_us = back.speed.delay_us = delay_us;
      fwd.speed.filter_hz = back.speed.filter_hz = 1000;
      const double a_fwd = run(fwd).spectrum.a0_deg, a_back = run(back).spectrum.a0_deg;
      CHECK(a_fwd < -1);
      CHECK(a_back == Approx(-a_fwd).margin(1e-9));
    }
  }
}

TEST_CASE("speed: rpm 0 leaves every result bit for bit as the static pipeline's", "[probe][regression]") {
  Mount m;
  m.sx_mm = 0.07;
  m.dy_mm = -0.05;
  m.tilt_x_deg = 0.4;
  for (const std::string array : {"two", "diff4", "ring:5", "point"}) {
    for (const SensorPrinciple p : all_principles()) {
      if ((array == "point") != reads_in_plane(p)) continue;
      ProbeSetup still = test::probe_setup(array, 720);
      still.principle = p;
      ProbeSetup timed = still;  // every timing key set, at rpm 0
      timed.speed.delay_us = 96;
      timed.speed.skew_us = 2;
      timed.speed.filter_hz = 800;
      timed.speed.sample_hz = 10000;
      const AngleErrorResult a = run(still, m), b = run(timed, m);
      CAPTURE(array, principle_name(p));
      CHECK((a.eps_deg.array() == b.eps_deg.array()).all());
      CHECK((a.channels.array() == b.channels.array()).all());
      CHECK(a.spectrum.pp_deg == b.spectrum.pp_deg);
    }
  }
}

TEST_CASE("speed: the lag 6 n tau, atan(omega / omega_c), skew and hold closed forms", "[probe][closed-form]") {
  SECTION("delay: eps = -6 n tau deg on every array and principle") {
    for (const double rpm : {1234.0, -20000.0}) {
      for (const std::string array : {"two", "diff4", "ring:7"}) {
        ProbeSetup s = at_speed(rpm, array, 720);
        s.speed.delay_us = 37;
        CHECK(run(s).spectrum.a0_deg == Approx(-6.0 * rpm * 37e-6).margin(1e-9));
      }
      for (const SensorPrinciple p : {SensorPrinciple::InPlane, SensorPrinciple::Xmr, SensorPrinciple::Amr}) {
        ProbeSetup s = point_at_speed(rpm, p, 720);
        s.speed.delay_us = 37;
        CHECK(run(s).spectrum.a0_deg == Approx(-6.0 * rpm * 37e-6).margin(1e-9));
      }
    }
  }
  SECTION("filter: eps = -atan(omega / omega_c); amr -atan(2 omega / omega_c) / 2") {
    const double rpm = 9000, fc = 333, w = 2 * kPi * rpm / 60, wc = 2 * kPi * fc;
    ProbeSetup s = at_speed(rpm, "diff4", 720);
    s.speed.filter_hz = fc;
    CHECK(run(s).spectrum.a0_deg == Approx(-rad_to_deg(std::atan(w / wc))).margin(1e-9));
    ProbeSetup amr = point_at_speed(rpm, SensorPrinciple::Amr, 720);
    amr.speed.filter_hz = fc;
    const AngleErrorResult r = run(amr);
    CHECK(r.spectrum.a0_deg == Approx(-rad_to_deg(std::atan(2 * w / wc)) / 2).margin(1e-9));
    CHECK(r.spectrum.pp_deg < 1e-9);
    amr.speed.prediction = Prediction::Ideal;  // the ideal prediction removes the amr lag too
    CHECK(run(amr).eps_deg.cwiseAbs().maxCoeff() < 1e-9);
  }
  SECTION("skew: 2nd harmonic omega * skew / 2 rad, mean -omega * skew / 2") {
    const double rpm = 3000, skew_us = 5, d_deg = rad_to_deg(2 * kPi * rpm / 60 * skew_us * 1e-6);
    ProbeSetup s = at_speed(rpm, "two", 720);
    s.speed.skew_us = skew_us;
    const Spectrum sp = run(s).spectrum;
    // second order in d: d^2 / 4 rad relative to d / 2, i.e. 1e-4 of it here
    CHECK(sp.c_deg[2] == Approx(d_deg / 2).epsilon(2e-4));
    CHECK(sp.a0_deg == Approx(-d_deg / 2).epsilon(2e-4));
    CHECK(sp.c_deg[1] < 1e-9);
  }
  SECTION("hold: the sawtooth theta_j - theta, on and off the sample grid") {
    for (const double fs : {1000.0, 777.0}) {
      for (const double rpm : {1000.0, -1000.0}) {
        ProbeSetup s = at_speed(rpm, "two", 3600);
        s.speed.sample_hz = fs;
        const AngleErrorResult r = run(s);
        const double S = fs * 60 / std::abs(rpm);  // samples per turn
        double worst = 0;
        for (int m = 0; m < 3600; ++m) {
          const double u = (rpm > 0 ? m : (3600 - m) % 3600) / 3600.0;  // the time of theta_m, in turns
          const double v = std::floor(u * S + 1e-9) / S;                  // its sample's
          const double expect_deg = 360.0 * (rpm > 0 ? v - u : u - v);
          worst = std::max(worst, std::abs(r.eps_deg[m] - expect_deg));
        }
        CAPTURE(fs, rpm);
        CHECK(worst < 1e-9);
        // pp: one sample interval less at most one grid step (0.1 deg) where the samples fall on the grid
        CHECK(r.spectrum.pp_deg <= 360.0 / S + 1e-9);
        CHECK(r.spectrum.pp_deg >= 360.0 / S - 0.1 - 1e-9);
      }
    }
  }
  SECTION("hold off the grid reads the static curve between its samples") {
    ProbeSetup s = at_speed(1000, "two", 3600);
    s.speed.sample_hz = 777;  // 46.62 samples per turn: most sample angles fall between grid points
    const AngleErrorResult r = run(s, dx(0.1));
    const double S = 777 * 60 / 1000.0;
    Eigen::VectorXd theta_s(3600);
    for (int m = 0; m < 3600; ++m) theta_s[m] = 360.0 * std::floor(m / 3600.0 * S + 1e-9) / S;
    const AngleErrorResult at = angle_error_at(exact_field(), test::probe_setup("two"), dx(0.1), theta_s);
    double worst = 0;
    for (int m = 0; m < 3600; ++m)
      worst = std::max(worst, std::abs(r.eps_deg[m] - (at.eps_deg[m] + theta_s[m] - 0.1 * m)));
    CHECK(worst < 1e-8);
  }
}

namespace {

// The brute force: channels of the static pipeline at the delayed angles theta(t - tau) of a time grid,
// each through the exact discretization of the first-order low-pass for a input linear between the steps,
// then atan2, the prediction's constant advance and a hold at sample_hz; eps at the M grid angles of
// the last simulated turn (transient gone: turns >> the filter's time constant).
Eigen::VectorXd simulate_in_time(const ProbeSetup& s, const Mount& m, int steps_per_turn, int turns, int M) {
  const SpeedChain& c = s.speed;
  const double w = c.omega_rad_s(), T = 2 * kPi / std::abs(w), dt = T / steps_per_turn;
  const int n = steps_per_turn * turns;
  ProbeSetup still = s;
  still.speed = SpeedChain{};
  auto channel = [&](double tau_us, int col) {
    Eigen::VectorXd th(n + 1);
    for (int i = 0; i <= n; ++i) th[i] = rad_to_deg(w * (i * dt - tau_us * 1e-6));
    return Eigen::VectorXd(angle_error_at(exact_field(), still, m, th).channels.col(col));
  };
  Eigen::VectorXd uc = channel(c.delay_us, 0), us = channel(c.delay_us + c.skew_us, 1);
  if (c.filter_hz > 0) {
    const double a = 2 * kPi * c.filter_hz * dt, e = std::exp(-a), b1 = 1 - (1 - e) / a, b0 = (1 - e) / a - e;
    for (Eigen::VectorXd* x : {&uc, &us}) {
      double y = (*x)[0], prev = (*x)[0];  // started at rest on the first value
      for (int i = 1; i <= n; ++i) {
        const double cur = (*x)[i];
        y = e * y + b0 * prev + b1 * cur;  // exact for x linear on [t_{i-1}, t_i]
        prev = cur;
        (*x)[i] = y;
      }
    }
  }
  const int per_sample = c.sample_hz > 0 ? static_cast<int>(std::lround(steps_per_turn * std::abs(c.rpm) / 60 / c.sample_hz)) : 1;
  const double lead_deg = c.prediction == Prediction::Ideal ? c.lag_deg(1) : 0.0;
  Eigen::VectorXd eps(M);
  for (int k = 0; k < M; ++k) {
    const int i = (turns - 1) * steps_per_turn + k * (steps_per_turn / M);  // rotor at +-360 k / M
    const int j = (i / per_sample) * per_sample;                           // its last sample
    const double psi_deg = rad_to_deg(std::atan2(us[j], uc[j])) + lead_deg;
    eps[k] = wrap_deg(psi_deg - rad_to_deg(w * i * dt));
  }
  return eps;
}

}  // namespace

TEST_CASE("speed: a brute-force simulation in time agrees with the steady state", "[probe][cross-check]") {
  // 6000 rpm, dx 0.1 mm and a sensor offset: every static harmonic present; delay, skew, filter and hold
  // together. Time steps of T/36000 (0.28 us), 4 turns (the filter's time constant 0.16 ms is 1/60 turn).
  ProbeSetup s = at_speed(6000, "two", 360);
  s.speed.delay_us = 40;
  s.speed.skew_us = 3;
  s.speed.filter_hz = 1000;
  s.speed.sample_hz = 5000;  // 50 samples per turn: every 720 time steps
  Mount m = dx(0.1);
  m.sy_mm = 0.05;
  const AngleErrorResult steady = run(s, m);
  const Eigen::VectorXd brute = simulate_in_time(s, m, 36000, 4, 360);
  // M = 360 grid angles of a +-rotation: eps at theta_k = 360 k / M (the time grid visits them in order).
  const double worst = (steady.eps_deg - brute).cwiseAbs().maxCoeff();
  CAPTURE(worst);
  CHECK(worst < 1e-7);  // measured 8e-9 deg (the filter's discretization, O(step^2))
  s.speed.prediction = Prediction::Ideal;
  s.speed.sample_hz = 0;
  const double worst_pred = (run(s, m).eps_deg - simulate_in_time(s, m, 36000, 4, 360)).cwiseAbs().maxCoeff();
  CAPTURE(worst_pred);
  CHECK(worst_pred < 1e-7);
}

TEST_CASE("speed: bad input is one line naming the keys", "[probe][bad-input]") {
  auto config = [](const std::string& toml) {
    Config cfg(common_keys());
    cfg.load_toml_string(toml);
    return cfg;
  };
  struct Bad {
    std::string toml, names;
  };
  const std::vector<Bad> cases = {
      {"[sensor]\nprediction = \"ideal\"\n", "speed.rpm"},
      {"[sensor]\nprediction = \"ideal\"\n", "sensor.prediction"},
      {"[sensor]\nsample_hz = 150\n[speed]\nrpm = 6000\n", "sensor.sample_hz"},
      {"[sensor]\nsample_hz = 150\n[speed]\nrpm = -6000\n", "speed.rpm"},
  };
  for (const auto& b : cases) {
    CAPTURE(b.toml);
    try {
      (void)SpeedChain::from_config(config(b.toml));
      FAIL("no InputError");
    } catch (const InputError& e) {
      CHECK(one_line(e.what()));
      CHECK(std::string(e.what()).find(b.names) != std::string::npos);
    }
  }
  for (const char* key : {"delay_us", "skew_us", "filter_hz", "sample_hz"}) {
    CAPTURE(key);
    SpeedChain c;
    c.rpm = 100;
    if (std::string(key) == "delay_us") c.delay_us = -1;
    if (std::string(key) == "skew_us") c.skew_us = -1;
    if (std::string(key) == "filter_hz") c.filter_hz = -1;
    if (std::string(key) == "sample_hz") c.sample_hz = -1;
    CHECK_THROWS_WITH(c.validate(), Catch::Contains(std::string("sensor.") + key) && Catch::Contains(">= 0"));
    CHECK_THROWS_AS(config(std::string("[sensor]\n") + key + " = -1\n"), InputError);
  }
  // 300 Hz is twice 9000 rpm's 150 Hz: allowed; an arbitrary-angle run refuses a speed.
  CHECK_NOTHROW(SpeedChain::from_config(config("[sensor]\nsample_hz = 300\n[speed]\nrpm = 9000\n")));
  ProbeSetup s = at_speed(100, "two", 64);
  s.speed.delay_us = 1;
  CHECK_THROWS_AS(angle_error_at(exact_field(), s, Mount{}, Eigen::VectorXd::Zero(3)), InputError);
}
