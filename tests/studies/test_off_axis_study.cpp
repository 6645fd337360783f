// off_axis study (studies/off_axis/) with a tiny configuration: the files, the trimmed side-shaft reader at
// the nominal mount (zero: the trim removes the ellipse), the raw one's pp (docs/physics.md: 75.9024 deg at
// 3600 steps; 360 steps sample the same curve, so the pp can only be a little smaller), the gain trim and
// ogp's ellipse both giving k - 1, and bad input (one line, exit 2, no output folder).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "support/study_test_util.hpp"

using namespace magenc::test;

namespace {
const std::string kTiny = "--config " + std::string(MAGENC_SOURCE_DIR) +
                          "/studies/off_axis/off_axis.toml --set off_axis.samples=6 --set off_axis.scan_samples=3 "
                          "--set 'off_axis.scan_side_x_mm=[18, 22]' --set 'off_axis.scan_gap_mm=[1, 2]' "
                          "--set 'off_axis.methods=[\"ogp\", \"harmonics:16\"]' --set 'off_axis.side_principles=[\"inplane\"]'";

const std::map<std::string, std::string>& reader(const std::vector<std::map<std::string, std::string>>& rows,
                                                 const std::string& label) {
  for (const auto& r : rows)
    if (r.at("reader") == label) return r;
  FAIL("no reader " << label);
  return rows.front();
}
}  // namespace

TEST_CASE("off_axis study: tiny run", "[studies][physics][cli]") {
  const fs::path out = temp_out("off_axis");
  const StudyRun r = run_study_exe("off_axis", out, kTiny);
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"readers.csv", "budget.csv", "scan_side.csv", "scan_gap.csv", "field_map.csv", "summary.md",
                          "config.toml", "run.json", "error_curves.png", "p99_scans.png", "spectra.png",
                          "field_map.png"});
  CHECK_FALSE(leftovers(out));
  const auto rows = read_csv(out / "readers.csv");
  REQUIRE(rows.size() == 4 + 3);  // raw, trimmed, ogp, harmonics:16; diff4, ring:8, ring:16
  const auto& raw = reader(rows, "side inplane raw");
  CHECK(num(raw, "direction") == -1);
  CHECK(std::abs(std::remainder(num(raw, "zero_deg") - 180.0, 360.0)) < 1e-6);
  CHECK(num(raw, "nominal_pp_deg") <= 75.9024 + 5e-5);
  CHECK(num(raw, "nominal_pp_deg") > 75.8);
  CHECK(num(reader(rows, "side inplane trimmed"), "nominal_pp_deg") < 1e-9);
  CHECK(num(reader(rows, "side inplane ogp"), "nominal_pp_deg") < 1e-6);
  CHECK(num(reader(rows, "side inplane trimmed"), "gain_mismatch") == Approx(3.194679).margin(5e-7));
  for (const auto& x : rows) CHECK(num(x, "p99_pp_deg") >= num(x, "p50_pp_deg"));
  const std::string md = slurp(out / "summary.md");
  CHECK(md.find("k = 4.19468") != std::string::npos);
}

TEST_CASE("off_axis study: bad input is refused", "[studies][bad-input][cli]") {
  for (const std::string args : {"--set magnet.inner_radius_mm=0", "--set 'off_axis.side_center_mm=[13, 0]'",
                                 "--set 'off_axis.bore_arrays=[\"point\"]'", "--set magnet.inner_radius_mm=16"}) {
    const fs::path out = temp_out("off_axis_bad");
    const StudyRun r = run_study_exe("off_axis", out, kTiny + " " + args);
    CAPTURE(args, r.err);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("error_spectrum: a ring's bad off-axis keys are one line naming them, exit 2, no output",
          "[studies][bad-input][cli]") {
  // The acceptance list's refusals at the command line: Ri >= R, a sensing point in the ring's material,
  // a direction other than 1, -1, auto, a die centre that puts the array over the material beside the ring.
  const std::string ring = "--set magnet.radius_mm=16 --set magnet.inner_radius_mm=11 --set magnet.height_mm=4 ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--set magnet.radius_mm=4 --set magnet.inner_radius_mm=4", "magnet.inner_radius_mm"},
      {ring + "--set sensor.principle=inplane --set 'sensor.center_mm=[13, 0]' --set sensor.plane_height_mm=-2",
       "sensor.center_mm"},
      {ring + "--set sensor.direction=2", "sensor.direction"},
      {ring + "--set sensor.r0_mm=2 --set 'sensor.center_mm=[12, 0]' --set sensor.plane_height_mm=-1",
       "sensor.center_mm"}};
  for (const auto& [args, key] : cases) {
    const fs::path out = temp_out("error_spectrum_bad");  // a file path that does not exist
    const StudyRun r = run_study_exe("error_spectrum", out, args);
    CAPTURE(args, r.err);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find(key) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
}
