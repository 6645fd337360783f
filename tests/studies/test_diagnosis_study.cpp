// The diagnosis study's tiny-config smoke test: it runs, writes its files, and its round trip's
// 2-sigma intervals cover the true offsets in most cases. Its round trip's parallel cases and the exact
// field's tables against the serial, direct computation.
#include <catch2/catch.hpp>

#include <omp.h>

#include <cmath>
#include <memory>

#include "fields/analytic_field.hpp"
#include "fields/axisym_table_field.hpp"
#include "fields/magnet.hpp"
#include "studies/diagnosis/diagnosis_study.hpp"
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

// The round trip fits its cases in parallel (one case per thread): the counts and medians are those of
// one thread, bit for bit. The exact field through its (r, z) tables (fields/axisym_table_field.hpp)
// gives the same counts, and medians within 1e-6 relative (the fits' own tolerance; the tables differ
// from the quadrature by ~1e-13).
TEST_CASE("diagnosis round trip: one thread and two agree exactly, the tables agree with the quadrature",
          "[studies][determinism]") {
  using namespace magenc;
  ModelState base;
  base.setup.array = ProbeArray::parse("two");
  base.setup.r0_mm = 2.4;
  base.setup.plane_z_mm = 4.55;
  const auto exact = std::make_shared<AnalyticField>(Magnet{});
  const AxisymmetricTableField table(exact);
  RoundTripOptions o;
  o.cases = 4;
  o.free = {"sx", "sy", "dx"};
  o.randomized = o.free;
  o.synth.points = 90;
  o.starts = 2;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const RoundTripResult one = run_round_trip(*exact, base, o);
  omp_set_num_threads(2);
  const RoundTripResult two = run_round_trip(*exact, base, o);
  const RoundTripResult tab = run_round_trip(table, base, o);
  omp_set_num_threads(threads);
  REQUIRE(one.params.size() == 4);
  REQUIRE(two.params.size() == one.params.size());
  REQUIRE(tab.params.size() == one.params.size());
  CHECK(one.failed == 0);
  CHECK(two.median_residual_rms_deg == one.median_residual_rms_deg);
  for (std::size_t j = 0; j < one.params.size(); ++j) {
    INFO(one.params[j].json_name);
    CHECK(one.params[j].fitted == 4);
    for (const RoundTripResult* r : {&two, &tab}) {
      CHECK(r->params[j].fitted == one.params[j].fitted);
      CHECK(r->params[j].within_2sigma == one.params[j].within_2sigma);
      CHECK(r->params[j].not_identifiable == one.params[j].not_identifiable);
    }
    CHECK(two.params[j].median_abs_err == one.params[j].median_abs_err);
    CHECK(two.params[j].median_sigma == one.params[j].median_sigma);
    CHECK(std::abs(tab.params[j].median_sigma - one.params[j].median_sigma) <= 1e-6 * one.params[j].median_sigma);
    CHECK(std::abs(tab.params[j].median_abs_err - one.params[j].median_abs_err) <= 1e-6 * one.params[j].median_sigma);
  }
}
