// sensor_principles study (studies/sensor_principles/sensor_principles.cpp) with a tiny
// configuration: the files, the spectra table's extra columns, docs/physics.md's
// in-plane reference value through the study (sx 0.1 mm: c2 0.0340 deg), the
// in-plane spot's indifference to dynamic eccentricity, the window counts, and
// bad input (one line, exit 2, no output folder).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "support/study_test_util.hpp"

using namespace magenc::test;

namespace {
const std::map<std::string, std::string>& row_of(const std::vector<std::map<std::string, std::string>>& rows,
                                                 const std::string& sensor, const std::string& c) {
  for (const auto& r : rows)
    if (r.at("sensor") == sensor && r.at("case") == c) return r;
  FAIL("no spectra row sensor=" << sensor << " case=" << c);
  return rows.front();
}
}  // namespace

TEST_CASE("sensor_principles study: tiny run", "[studies][physics][cli]") {
  const fs::path out = temp_out("sensor_principles");
  const StudyRun r = run_study_exe("sensor_principles", out,
                                   "--set sensor.steps=720 --set study.samples=8 --set study.mc_steps=64 "
                                   "--set 'study.sensors=[\"two\", \"inplane\", \"amr\"]'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"spectra.csv", "principles.csv", "summary.md", "config.toml", "run.json", "pp_heatmap.png",
                          "box_p99.png"});
  CHECK(fs::file_size(out / "pp_heatmap.png") > 1000);
  CHECK_FALSE(leftovers(out));
  const auto rows = read_csv(out / "spectra.csv");
  REQUIRE(rows.size() == 8 * 3);  // 8 single errors x 3 sensors
  // docs/physics.md: in-plane point, sx 0.1 mm: c2 0.0340 deg; dx: nothing but a constant.
  CHECK(num(row_of(rows, "inplane", "sx"), "c2_deg") == Approx(0.0340).margin(5e-5));
  CHECK(num(row_of(rows, "amr", "sx"), "c2_deg") == Approx(0.0340).margin(5e-5));
  CHECK(num(row_of(rows, "inplane", "dx"), "pp_deg") < 1e-9);
  CHECK(num(row_of(rows, "two", "dx"), "pp_deg") > 1.0);
  CHECK(row_of(rows, "inplane", "sx").at("field_min_mT").size() > 0);
  // Windows of the study config: two 35..70 mT (its ~60 mT peak is inside), amr >= 31.4 mT.
  const auto p = read_csv(out / "principles.csv");
  REQUIRE(p.size() == 3);
  for (const auto& x : p) CHECK(num(x, "mc_samples_in_window") + num(x, "mc_out_of_window") == 8);
  const std::string md = slurp(out / "summary.md");
  CHECK(md.find("Which principle tolerates which error") != std::string::npos);
  CHECK(md.find("pp_heatmap.png") != std::string::npos);
}

TEST_CASE("sensor_principles study: bad input is refused", "[studies][bad-input][cli]") {
  for (const std::string args : {"--set 'study.sensors=[\"two\", \"point\"]'", "--set window.xmr_min_mT=80 "
                                 "--set window.xmr_max_mT=40", "--set study.field=linear"}) {
    const fs::path out = temp_out("sensor_principles_bad");
    const StudyRun r = run_study_exe("sensor_principles", out, args + " --set study.samples=2");
    CAPTURE(args, r.err);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
  }
}
