// The diagnosis study's tiny-config smoke test: it runs, writes its files, and its round trip's
// 2-sigma intervals cover the true offsets in most cases.
#include <catch2/catch.hpp>

#include "support/study_test_util.hpp"

using namespace magenc::test;

TEST_CASE("diagnosis study: tiny config runs and its round trip covers the truth", "[studies][cli]") {
  const fs::path out = temp_out("diagnosis_study");
  const StudyRun r = run_study_exe("diagnosis", out,
                                   "--set study.arrays=two --set roundtrip.cases=6 --set roundtrip.points=120 "
                                   "--set roundtrip.all_free_cases=1 --set roundtrip.starts=2");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"summary.md", "coverage.csv", "anomalies.csv", "example_fit.png", "config.toml", "run.json"});
  const auto rows = read_csv(out / "coverage.csv");
  REQUIRE(rows.size() >= 3);
  int fitted = 0, within = 0;
  for (const auto& row : rows) {
    fitted += static_cast<int>(num(row, "cases_fitted"));
    within += static_cast<int>(num(row, "within_2sigma"));
  }
  CHECK(fitted >= 6 * 3);
  CHECK(within >= 0.7 * fitted);  // 2-sigma coverage ~95 % expected; 70 % leaves room for 6 cases' scatter
  CHECK_THAT(slurp(out / "summary.md"), Catch::Contains("anomalies"));
  fs::remove_all(out);
}
