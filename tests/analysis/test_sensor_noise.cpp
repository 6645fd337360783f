// Sensor noise model (src/analysis/sensor_noise.hpp) against a direct Monte Carlo of
// noisy probe readings through atan2.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "core/errors.hpp"
#include "probe/probe_array.hpp"
#include "analysis/sensor_noise.hpp"
#include "core/units.hpp"

using namespace magenc;

namespace {
// rms of wrap(atan2(S, C) - theta) with readings A cos(b_k - theta) + noise,
// optionally quantized with step lsb (0 = none), over random theta.
double simulated_sigma_rad(const ProbeArray& a, double A, double sigma, double lsb, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> turn(0.0, 2 * kPi);
  double s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double th = turn(rng);
    double C = 0, S = 0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      double B = A * std::cos(deg_to_rad(a.angle_deg[k]) - th) + (sigma > 0 ? noise(rng) : 0.0);
      if (lsb > 0) B = lsb * std::round(B / lsb);
      C += a.w_cos[k] * B;
      S += a.w_sin[k] * B;
    }
    const double e = std::remainder(std::atan2(S, C) - th, 2 * kPi);
    s2 += e * e;
  }
  return std::sqrt(s2 / n);
}
}  // namespace

TEST_CASE("angle noise: closed forms of the three arrays", "[noise]") {
  const double A = 0.05, s = 1e-5;
  CHECK(angle_noise_sigma_rad(ProbeArray::parse("two"), A, s) == Approx(s / A));
  CHECK(angle_noise_sigma_rad(ProbeArray::parse("diff4"), A, s) == Approx(s / (std::sqrt(2.0) * A)));
  CHECK(angle_noise_sigma_rad(ProbeArray::parse("ring:8"), A, s) == Approx(s / (2.0 * A)));
  CHECK(angle_noise_sigma_rad(ProbeArray::parse("ring:5"), A, s) == Approx(s / (std::sqrt(2.5) * A)));
  CHECK_THROWS_AS(angle_noise_sigma_rad(ProbeArray::parse("two"), 0.0, s), InputError);
}

TEST_CASE("angle noise matches a direct Monte Carlo of noisy channels", "[noise]") {
  const auto spec = GENERATE(as<std::string>{}, "two", "diff4", "ring:8", "ring:3");
  const ProbeArray a = ProbeArray::parse(spec);
  CAPTURE(spec);
  const double A = 0.02, sigma = 2e-4;  // 1% noise: first order holds well
  const double predicted = angle_noise_sigma_rad(a, A, sigma);
  const double simulated = simulated_sigma_rad(a, A, sigma, 0.0, 200000, 11);
  CHECK(simulated == Approx(predicted).epsilon(0.01));
}

TEST_CASE("quantization noise: LSB/sqrt(12) per probe", "[noise]") {
  SensorNoise n;
  n.probe_noise_uT_rms = 0;
  n.adc_bits = 10;
  n.adc_full_scale_mT = 100;
  CHECK(n.lsb_T() == Approx(0.2 / 1024));
  CHECK(n.probe_sigma_T() == Approx(n.lsb_T() / std::sqrt(12.0)));
  // Antipodal probes read opposite fields, so their quantization errors are
  // opposite: diff4/ring channels see them coherently (the simulation knows
  // nothing of the model; it just rounds the readings).
  const double A = 0.07;  // many LSB per turn: quantization error ~ uniform
  const double q = n.lsb_T() / std::sqrt(12.0);
  for (const char* spec : {"two", "diff4", "ring:8", "ring:5"}) {
    CAPTURE(spec);
    const ProbeArray a = ProbeArray::parse(spec);
    const double predicted = angle_noise_sigma_rad(a, A, 0.0, q);
    const double simulated = simulated_sigma_rad(a, A, 0.0, n.lsb_T(), 200000, 5);
    CHECK(simulated == Approx(predicted).epsilon(0.05));
  }
  CHECK(angle_noise_sigma_rad(ProbeArray::parse("diff4"), A, 0.0, q) == Approx(q / A));
  CHECK(angle_noise_sigma_rad(ProbeArray::parse("ring:8"), A, 0.0, q) == Approx(std::sqrt(2.0) * q / (2 * A)));
  // Field noise and quantization add in quadrature.
  n.probe_noise_uT_rms = 30;
  CHECK(n.probe_sigma_T() == Approx(std::hypot(30e-6, n.lsb_T() / std::sqrt(12.0))));
  // pp equivalent and clipping flag.
  const ProbeArray a = ProbeArray::parse("diff4");
  const AngleNoise an = angle_noise(a, 0.15, n);
  CHECK(an.pp_deg == Approx(6 * an.sigma_deg));
  CHECK(an.adc_clipped);
  CHECK_FALSE(angle_noise(a, 0.05, n).adc_clipped);
}
