// Study calibration end to end on a tiny configuration: exit 0 and the documented outputs; a bad drift key
// is one line, exit 2, no output directory.
#include <catch2/catch.hpp>

#include "support/study_test_util.hpp"

using namespace magenc::test;

TEST_CASE("calibration study: a tiny run writes its outputs", "[studies][contract]") {
  const fs::path out = temp_out("calibration_study");
  const StudyRun r = run_study_exe("calibration", out,
                                   "--set study.samples=8 --set study.mc_steps=64 --set 'study.sensors=[\"two\", \"xmr\"]' "
                                   "--set 'study.drift_scales=[0.5, 1]'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"summary.md", "residual.csv", "residual_spectra.csv", "p99_vs_drift.png",
                          "residual_spectra.png", "config.toml", "run.json"});
  const auto rows = read_csv(out / "residual.csv");
  // 2 sensors x (factory + 2 scales + 5 drift keys alone) x 3 methods.
  CHECK(rows.size() == 2 * 8 * 3);
  CHECK_THAT(slurp(out / "summary.md"), Catch::Contains("Budget"));
  fs::remove_all(out);
}

TEST_CASE("calibration study: a bad drift key is one line, exit 2, no output", "[studies][bad-input]") {
  const fs::path out = temp_out("calibration_study_bad");
  const StudyRun r = run_study_exe("calibration", out, "--set 'drift.keys=[{ key = \"magnet.br_T\", half_width = 0.01 }]'");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Catch::Contains("drift.keys") && Catch::Contains("magnet.br_T"));
  CHECK_FALSE(fs::exists(out));
}
