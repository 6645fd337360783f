// The stray_field and temperature studies (studies/stray_field/stray_field.cpp, studies/temperature/temperature.cpp) with tiny
// configurations: the files, docs/physics.md's reference values through the tables (uniform Bz on `two`:
// c1 1.774 deg per mT; 100 A along y at 10 mm: `diff4` c1 0.639 deg), and bad input (one line, exit 2,
// no output folder).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "support/study_test_util.hpp"

using namespace magenc::test;

TEST_CASE("stray_field study: tiny run", "[studies][physics][cli]") {
  const fs::path out = temp_out("stray_field");
  const StudyRun r = run_study_exe("stray_field", out,
                                   "--set 'study.sensors=[\"two\", \"diff4\", \"inplane\"]' --set study.polar_points=5 "
                                   "--set study.azimuth_points=4 --set study.curve_points=5 "
                                   "--set 'study.levels_kA_per_m=[1]' --set 'study.wire_distances_mm=[10]' "
                                   "--set 'study.wire_currents_A=[100]'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"levels.csv", "tolerated.csv", "wires.csv", "summary.md", "error_vs_field.png", "wires.png",
                          "direction_map_two.png", "config.toml", "run.json"});
  CHECK_FALSE(leftovers(out));
  const auto levels = read_csv(out / "levels.csv");
  bool seen = false;
  for (const auto& row : levels)
    if (row.at("sensor") == "two" && row.at("kind") == "level") {
      seen = true;
      CHECK(num(row, "c1_at_worst_deg") == Approx(1.774 * 1.2566370614).epsilon(2e-3));
      CHECK(std::abs(num(row, "worst_dir_z")) == Approx(1.0));
    }
  CHECK(seen);
  for (const auto& row : read_csv(out / "wires.csv"))
    if (row.at("sensor") == "diff4" && row.at("orientation") == "along y")
      CHECK(num(row, "c1_deg") == Approx(0.639).margin(0.001));  // 360 steps: within 0.001 of the 3600-step value
  const std::string md = slurp(out / "summary.md");
  CHECK(md.find("Uniform field tolerated") != std::string::npos);
}

TEST_CASE("temperature study: tiny run", "[studies][physics][cli]") {
  const fs::path out = temp_out("temperature");
  const StudyRun r = run_study_exe("temperature", out,
                                   "--set 'study.sensors=[\"two\", \"inplane\"]' --set study.temperature_step_K=95 "
                                   "--set study.samples=10");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"temperature.csv", "summary.md", "pp_vs_temperature.png", "field_vs_temperature.png"});
  const auto rows = read_csv(out / "temperature.csv");
  REQUIRE(rows.size() == 2 * 2 * 3);  // sensors x mounts x (-40, 55, 150)
  for (const auto& row : rows)
    if (num(row, "temperature_C") == 150) CHECK(num(row, "br_scale") == Approx(0.844));
}

TEST_CASE("stray_field and temperature studies: bad input is refused", "[studies][bad-input][cli]") {
  struct Bad {
    const char* study;
    std::string args;
  };
  for (const Bad& b : {Bad{"stray_field", "--set 'stray.wire_direction=[0, 0, 0]' --set stray.wire_current_A=1"},
                       Bad{"stray_field", "--set 'study.sensors=[\"point\"]'"},
                       Bad{"stray_field", "--set study.curve_min_mT=5 --set study.curve_max_mT=1"},
                       Bad{"temperature", "--set study.temperature_min_C=100 --set study.temperature_max_C=0"},
                       Bad{"temperature", "--set 'study.sensors=[\"xmr\"]'"},
                       Bad{"temperature", "--set magnet.material=alnico"}}) {
    const fs::path out = temp_out(std::string(b.study) + "_bad");
    const StudyRun r = run_study_exe(b.study, out, b.args);
    CAPTURE(b.study, b.args, r.err);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
  }
}
