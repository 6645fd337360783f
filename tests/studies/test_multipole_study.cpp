// The multipole study (studies/multipole/) with a tiny configuration: the files, the e/r law and the
// ideal interpolation numbers through the tables, the nonius box's columns; and bad input (one line, exit 2,
// no output folder): pole_pairs 0 with a multipole pattern, a nonius with the master's pole pairs, a read
// head off the track (an array wider than the ring), a uniform magnet.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "support/study_test_util.hpp"

using namespace magenc::test;

namespace {
const std::string kTiny =
    "--set study.steps=360 --set 'study.gaps_mm=[0.4]' --set 'study.arrays=[\"two\"]' "
    "--set 'study.eccentricities_mm=[0.01]' --set study.pole_samples=2 --set study.box_samples=3 ";
}

TEST_CASE("multipole study: tiny run", "[studies][physics][cli]") {
  const fs::path out = temp_out("multipole");
  const StudyRun r = run_study_exe("multipole", out, "--config " MAGENC_SOURCE_DIR "/studies/multipole/multipole.toml " + kTiny);
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"interpolation.csv", "eccentricity.csv", "pole_errors.csv", "nonius_box.csv", "summary.md",
                          "interpolation.png", "eccentricity.png", "pole_errors.png", "nonius_margin.png",
                          "config.toml", "run.json"});
  CHECK_FALSE(leftovers(out));
  const auto interp = read_csv(out / "interpolation.csv");
  REQUIRE(interp.size() == 1);
  CHECK(num(interp[0], "ce4_deg") == Approx(0.09266).margin(5e-6));  // docs/physics.md's reference value
  const auto ecc = read_csv(out / "eccentricity.csv");
  REQUIRE(ecc.size() == 1);
  CHECK(num(ecc[0], "c1_over_law") == Approx(1.0).margin(0.02));
  CHECK(read_csv(out / "pole_errors.csv").size() == 2);
  const auto box = read_csv(out / "nonius_box.csv");
  REQUIRE(box.size() == 3);
  for (const auto& row : box) CHECK(num(row, "nonius_margin_deg") < 180.0);
}

TEST_CASE("multipole study: bad input is refused", "[studies][bad-input][cli]") {
  for (const std::string& args : {std::string("--set magnet.pole_pairs=0"), std::string("--set nonius.pole_pairs=32"),
                                 std::string("--set sensor.r0_mm=16"), std::string("--set magnet.pattern=uniform")}) {
    const fs::path out = temp_out("multipole_bad");
    const StudyRun r = run_study_exe("multipole", out,
                                     "--config " MAGENC_SOURCE_DIR "/studies/multipole/multipole.toml " + kTiny + args);
    CAPTURE(args, r.err);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
  }
}
