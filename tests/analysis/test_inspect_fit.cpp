// inspect's fit (src/analysis/inspect_fit.*): round trips on synthetic scans made with the exact field.
//   1. Noise-free: the truth comes back to ~1e-7 of its typical sizes.
//   2. With seeded Gaussian noise (0.05 mT per component), over 20 noise draws: every free parameter lies
//      within 4 sigma of the truth in each draw, and the normalised errors (fit - truth)/sigma have an RMS
//      between 0.6 and 1.5 (the stated sigma is the spread's size, neither too small nor too large).
//   3. Readings all at one point (3 numbers) cannot give the offset and the polarization (4 parameters):
//      reported as not identifiable; fewer components than free parameters: refused.
//   4. Bad input: too few readings, an unknown group.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "analysis/inspect_fit.hpp"
#include "core/errors.hpp"

using magenc::FieldScan;
using magenc::InspectValues;
using magenc::Magnet;

namespace {

// Nominal positions: a 7 x 7 grid (x, y in -3..3 mm) at each of the given heights above the magnet's centre.
Eigen::Matrix3Xd scan_points(const std::vector<double>& heights_mm) {
  Eigen::Matrix3Xd p(3, 49 * heights_mm.size());
  int j = 0;
  for (double z : heights_mm)
    for (int a = -3; a <= 3; ++a)
      for (int b = -3; b <= 3; ++b) p.col(j++) = Eigen::Vector3d(a, b, z);
  return p;
}

const InspectValues kTruth{0.05, -0.03, 0.08, 1.0, -0.5, 2.0, 1.17, 3.0, 2.0};

FieldScan synthetic_scan(const Magnet& m, const Eigen::Matrix3Xd& p, const InspectValues& truth, double noise_mT,
                         unsigned seed) {
  FieldScan s{p, magenc::inspect_model_T(m, p, truth)};
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, noise_mT * 1e-3);
  if (noise_mT > 0)
    for (Eigen::Index j = 0; j < s.B_T.cols(); ++j)
      for (int c = 0; c < 3; ++c) s.B_T(c, j) += n(rng);
  return s;
}

}  // namespace

TEST_CASE("inspect: a noise-free scan gives back the pose and the polarization", "[analysis][closed-form]") {
  Magnet m;  // R 2, L 4, Br 1.2 nominal, magnetization 0 deg
  const FieldScan s = synthetic_scan(m, scan_points({4.55, 5.55}), kTruth, 0.0, 1);
  magenc::InspectOptions opts;
  opts.groups = {"offset", "rotation", "polarization", "direction"};
  const auto res = magenc::inspect_scan(m, s, opts);
  const auto& table = magenc::inspect_parameters();
  for (int i = 0; i < magenc::kInspectParams; ++i) {
    INFO(table[i].name << " fit " << res.value[i] << " truth " << kTruth[i]);
    CHECK(std::abs(res.value[i] - kTruth[i]) < 1e-7 * table[i].scale);
  }
  CHECK(res.residual_rms_mT < 1e-8);
  CHECK(res.not_identifiable.empty());
}

TEST_CASE("inspect: with noise the truth lies within the stated sigma", "[analysis][physics]") {
  Magnet m;
  const Eigen::Matrix3Xd p = scan_points({4.55, 5.55});
  const auto& table = magenc::inspect_parameters();
  magenc::InspectOptions opts;
  opts.groups = {"offset", "rotation", "polarization", "direction"};
  double sum_z2 = 0;
  int count = 0;
  double worst = 0;
  for (unsigned draw = 0; draw < 20; ++draw) {
    const FieldScan s = synthetic_scan(m, p, kTruth, 0.05, 1000 + draw);
    const auto res = magenc::inspect_scan(m, s, opts);
    CHECK(res.residual_rms_mT == Approx(0.05).epsilon(0.15));
    for (int i = 0; i < magenc::kInspectParams; ++i) {
      INFO("draw " << draw << " " << table[i].name << " fit " << res.value[i] << " +- " << res.sigma[i] << " truth "
                   << kTruth[i]);
      REQUIRE(std::isfinite(res.sigma[i]));
      REQUIRE(res.sigma[i] > 0);
      const double z = (res.value[i] - kTruth[i]) / res.sigma[i];
      CHECK(std::abs(z) < 4.0);
      sum_z2 += z * z;
      ++count;
      worst = std::max(worst, std::abs(z));
    }
  }
  const double rms_z = std::sqrt(sum_z2 / count);
  WARN("inspect round trip: 20 noisy scans x 9 parameters, RMS of (fit - truth)/sigma = " << rms_z
                                                                                       << ", largest |z| = " << worst);
  CHECK(rms_z > 0.6);
  CHECK(rms_z < 1.5);
}

TEST_CASE("inspect: readings at one point cannot separate the offset from the polarization", "[analysis][physics]") {
  Magnet m;
  Eigen::Matrix3Xd p(3, 1);
  p << 0.0, 0.0, 4.55;
  const FieldScan s = synthetic_scan(m, p, kTruth, 0.0, 1);
  magenc::InspectOptions opts;
  opts.groups = {"offset", "polarization"};
  // 3 components for 4 free parameters: refused before fitting.
  REQUIRE_THROWS_WITH(magenc::inspect_scan(m, s, opts), Catch::Contains("allowed more components than free"));
  Eigen::Matrix3Xd line(3, 5);
  for (int j = 0; j < 5; ++j) line.col(j) = Eigen::Vector3d(0.3, -0.2, 4.55);
  const FieldScan repeated = synthetic_scan(m, line, kTruth, 0.0, 1);
  opts.groups = {"polarization", "offset"};
  const auto res = magenc::inspect_scan(m, repeated, opts);
  CHECK_FALSE(res.not_identifiable.empty());
}

TEST_CASE("inspect: bad groups are refused with one line", "[analysis][bad-input]") {
  CHECK_THROWS_WITH(magenc::parse_inspect_groups("offset,tilt", "--free"),
                    Catch::Contains("--free 'tilt' is not a parameter group: allowed"));
  CHECK_THROWS_AS(magenc::parse_inspect_groups("", "--free"), magenc::InputError);
  CHECK(magenc::parse_inspect_groups("direction,offset", "--free") == std::vector<std::string>{"direction", "offset"});
}

TEST_CASE("inspect: a fit that explains nothing of the scan is a failure, not a result", "[analysis][bad-input]") {
  Magnet m;
  magenc::InspectOptions opts;
  // Readings unrelated to the magnet (seeded Gaussian, 10 mT per component): the best fit leaves most of them.
  FieldScan noise{scan_points({4.55, 5.55}), Eigen::Matrix3Xd(3, 98)};
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 10e-3);
  for (Eigen::Index j = 0; j < noise.B_T.cols(); ++j)
    for (int c = 0; c < 3; ++c) noise.B_T(c, j) = n(rng);
  CHECK_THROWS_WITH(magenc::inspect_scan(m, noise, opts),
                    Catch::Contains("inspect: the fit leaves a residual RMS of") && Catch::Contains("allowed at most 50 %"));
  // A scan 1 km away whose readings are 1 mT: only an absurd polarization reaches them.
  FieldScan far{scan_points({1e6}), Eigen::Matrix3Xd::Constant(3, 49, 1e-3)};
  CHECK_THROWS_AS(magenc::inspect_scan(m, far, opts), magenc::ComputeError);
  // The good scan still fits.
  CHECK_NOTHROW(magenc::inspect_scan(m, synthetic_scan(m, scan_points({4.55}), kTruth, 0.05, 3), opts));
}
