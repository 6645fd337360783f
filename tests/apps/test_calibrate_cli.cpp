// calibrate executable end to end: a simulated calibration applied after a re-mount gives the library's
// residual; the correction file written is read back to the same residual; an ogp correction of a raw
// curve recovers its chain; bad input is one line, exit 2 and no output directory.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/study_test_util.hpp"

using namespace magenc::test;

TEST_CASE("calibrate CLI: simulated calibration, table, re-mount, round trip", "[apps][contract][cli]") {
  const fs::path out = temp_out("calibrate_sim"), again = temp_out("calibrate_again");
  const std::string remount = " --apply run --set mount.sx_mm=0.12 --set mount.dx_mm=0.08";
  StudyRun r = run_study_exe("calibrate", out, "--method harmonics:8" + remount);
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"correction.csv", "correction.json", "config.toml", "residual.csv", "residual.json"});
  const auto j = nlohmann::json::parse(slurp(out / "residual.json"));
  CHECK(j["pp_after_deg"].get<double>() == Approx(1.4288).margin(0.0005));  // physics.md: about 1.43
  CHECK(j["pp_before_deg"].get<double>() > 5.0);
  const auto cj = nlohmann::json::parse(slurp(out / "correction.json"));
  CHECK(cj["method"] == "harmonics:8");
  CHECK(cj["a_deg"].size() == 9);
  // The table read back applies to the same residual.
  r = run_study_exe("calibrate", again, "--correction '" + (out / "correction.csv").string() + "'" + remount);
  REQUIRE(r.code == 0);
  CHECK(slurp(again / "residual.csv") == slurp(out / "residual.csv"));
  CHECK_FALSE(leftovers(out));
  fs::remove_all(out);
  fs::remove_all(again);
}

TEST_CASE("calibrate CLI: ogp of a raw curve recovers the chain", "[apps][closed-form][cli]") {
  const fs::path curve = fs::temp_directory_path() / ("magenc_test_raw_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream f(curve);
    f.precision(17);
    f << "theta_deg,u_cos,u_sin\n";
    const double d = 3.0 * M_PI / 180;
    for (int i = 0; i < 200; ++i) {
      const double t = 2 * M_PI * i / 200;
      f << 360.0 * i / 200 << "," << 40 * std::cos(t) + 1.5 << "," << 1.05 * 40 * std::sin(t + d) - 0.5 << "\n";
    }
  }
  const fs::path out = temp_out("calibrate_ogp");
  const StudyRun r = run_study_exe("calibrate", out, "--method ogp --measured '" + curve.string() + "' --apply '" +
                                                         curve.string() + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto cj = nlohmann::json::parse(slurp(out / "correction.json"));
  CHECK(cj["offset_cos"].get<double>() == Approx(1.5).margin(1e-9));
  CHECK(cj["offset_sin"].get<double>() == Approx(-0.5).margin(1e-9));
  CHECK(cj["gain_ratio"].get<double>() == Approx(1.05).margin(1e-9));
  CHECK(cj["phase_deg"].get<double>() == Approx(3.0).margin(1e-9));
  const auto j = nlohmann::json::parse(slurp(out / "residual.json"));
  CHECK(j["pp_before_deg"].get<double>() > 1.0);
  CHECK(j["pp_after_deg"].get<double>() < 1e-8);
  fs::remove_all(out);
  fs::remove(curve);
}

TEST_CASE("calibrate CLI: bad input is one line, exit 2, no output", "[apps][bad-input][cli]") {
  const fs::path bad = fs::temp_directory_path() / ("magenc_test_badcorr_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream f(bad);
    f << "quantity,index,value\nmethod,0,lut:4\nlut_deg,0,1\n";
  }
  const fs::path lut32 = fs::temp_directory_path() / ("magenc_test_lut32_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream f(lut32);
    f << "quantity,index,value\nmethod,0,lut:32\nturns,0,1\n";
    for (int k = 0; k < 32; ++k) f << "lut_deg," << k << "," << 0.1 * std::sin(0.2 * k) << "\n";
  }
  const fs::path out = temp_out("calibrate_bad");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--correction '" + bad.string() + "'", "lut_deg"},
      {"--correction /nonexistent.csv", "nonexistent"},
      {"", "calibration.method"},
      {"--method lut:2", "calibration.method"},
      {"--method harmonics:8 --set 'calibration.at={mount.nope=1}'", "calibration.at"},
      {"--method ogp --measured '" + bad.string() + "'", bad.string()},
      // A table applied under another method, or of a sensor of other turns.
      {"--method lut:64 --correction '" + lut32.string() + "'", "calibration.method = lut:64 (--method) contradicts"},
      {"--set sensor.principle=amr --set sensor.array=point --correction '" + lut32.string() + "'",
       "has turns 1 but sensor.principle amr"},
  };
  for (const auto& [args, names] : cases) {
    CAPTURE(args);
    const StudyRun r = run_study_exe("calibrate", out, args);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains(names));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
  }
  fs::remove(bad);
  // The same table under its own method, or none given, applies.
  for (const std::string method : {"", "--method lut:32 "}) {
    CAPTURE(method);
    const StudyRun r = run_study_exe("calibrate", out, method + "--correction '" + lut32.string() + "'");
    CHECK(r.code == 0);
    fs::remove_all(out);
  }
  fs::remove(lut32);
}
