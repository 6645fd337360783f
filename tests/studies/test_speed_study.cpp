// The speed study (studies/speed/) with a tiny configuration: the files, the closed forms through the
// tables (a delay alone: a0 = -6 n tau deg; the ideal prediction removes it; torque factor cos(p eps)),
// and bad input (one line, exit 2, no output folder).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "support/study_test_util.hpp"

using namespace magenc::test;

TEST_CASE("speed study: tiny run", "[studies][physics][cli]") {
  const fs::path out = temp_out("speed");
  const StudyRun r = run_study_exe("speed", out,
                                   "--set study.rpm_points=4 --set study.steps=360 --set study.rpm_max=30000 "
                                   "--set 'study.timing_sample_hz=[0, 0]' --set 'study.pole_pairs=[4]' "
                                   "--set mount.dx_mm=0.1 --set study.calibration_rpm=10000");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"speed_vs_rpm.csv", "commutation.csv", "attenuation.csv", "calibration_vs_rpm.csv",
                          "summary.md", "speed_error.png", "commutation.png", "attenuation.png", "calibration.png",
                          "config.toml", "run.json"});
  CHECK_FALSE(leftovers(out));
  const auto sweep = read_csv(out / "speed_vs_rpm.csv");
  REQUIRE(sweep.size() == 2 * 2 * 4);  // timings x predictions x speeds
  const auto still = read_csv(out / "attenuation.csv").front();
  for (const auto& row : sweep) {
    const double rpm = num(row, "rpm"), delay_s = row.at("timing") == "AS5045 fast" ? 96e-6 : 384e-6;
    const double static_a0 = num(still, "a0_deg");  // the eccentric mount's own mean error
    if (row.at("prediction") == "none")
      CHECK(num(row, "a0_deg") - static_a0 == Approx(-6.0 * rpm * delay_s).margin(1e-6));
    else
      CHECK(num(row, "a0_deg") == Approx(static_a0).margin(1e-6));
  }
  for (const auto& row : read_csv(out / "commutation.csv"))
    if (row.at("prediction") == "none" && num(row, "rpm") == 30000 && row.at("timing") == "AS5045 fast")
      CHECK(num(row, "electrical_mean_deg") == Approx(4 * (num(still, "a0_deg") - 17.28)).margin(1e-5));
  const auto cal = read_csv(out / "calibration_vs_rpm.csv");
  REQUIRE(cal.size() == 4);
  // A delay alone (AS5045 fast, no hold): each correction fits its own speed; the one taken at 10,000 rpm
  // carries that speed's lag 6 n tau = 5.76 deg into a run at rest, and the one taken at rest leaves it.
  CHECK(num(cal[0], "max_abs_calibrated_at_rest_deg") < 1e-3);
  CHECK(num(cal[1], "max_abs_calibrated_at_10000_rpm_deg") < 1e-3);
  CHECK(num(cal[0], "max_abs_calibrated_at_10000_rpm_deg") == Approx(5.76).margin(1e-3));
  CHECK(num(cal[1], "max_abs_calibrated_at_rest_deg") == Approx(5.76).margin(1e-3));
}

TEST_CASE("speed study: bad input is refused", "[studies][bad-input][cli]") {
  for (const std::string& args : {std::string("--set 'study.timing_delay_us=[96]'"),
                                 std::string("--set 'study.timing_sample_hz=[500, 500]'"),
                                 std::string("--set sensor.prediction=ideal"),
                                 std::string("--set study.calibration_method=ogp")}) {
    const fs::path out = temp_out("speed_bad");
    const StudyRun r = run_study_exe("speed", out, args + " --set study.rpm_points=3 --set study.steps=64");
    CAPTURE(args, r.err);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
  }
}
