// Smoke test of the radius study executable with a tiny configuration, and
// its bad-input behaviour (non-zero exit, one-line message, no output dir).
#include <catch2/catch.hpp>

#include <set>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/study_test_util.hpp"

namespace fs = std::filesystem;

namespace {
using Run = magenc::test::StudyRun;
Run run_radius(const std::string& args, const fs::path& out) { return magenc::test::run_study_exe("radius", out, args); }
std::string tiny() {
  return "--set radius.fem_dir= --set radius.r0_min_mm=1.0 --set radius.r0_max_mm=3.0 --set radius.r0_step_mm=0.5 "
         "--set radius.samples=300 --set radius.validate_radii=2 --set radius.validate_samples=1 --set sensor.steps=720";
}
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> v;
  std::stringstream ss(line);
  std::string c;
  while (std::getline(ss, c, ',')) v.push_back(c);
  return v;
}
}  // namespace

TEST_CASE("radius study: tiny configuration", "[studies][cli][slow]") {
  const fs::path out = fs::temp_directory_path() / ("magenc_test_radius_smoke_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const Run r = run_radius(tiny(), out);
  INFO(r.err);
  REQUIRE(r.code == 0);
  magenc::test::check_files_exist(out, {"radius.csv", "radius_spectra.csv", "radius_recommendation.csv",
                                        "radius_validation.csv", "summary.md", "config.toml", "bz_profile.png",
                                        "percentiles_analytic.png", "harmonics_analytic_ring8.png", "total_p99.png"});
  std::ifstream csv(out / "radius.csv");
  std::string header, line;
  std::getline(csv, header);
  const auto cols = split(header);
  for (const char* c : {"field", "array", "r0_mm", "bz_amplitude_T", "worst_pp_deg", "mc_p95_pp_deg", "mc_p99_pp_deg",
                        "noise_pp_deg", "total_p99_pp_deg"})
    CHECK(std::find(cols.begin(), cols.end(), c) != cols.end());
  int rows = 0;
  while (std::getline(csv, line)) {
    const auto v = split(line);
    REQUIRE(v.size() == cols.size());
    auto col = [&](const char* name) {
      return std::stod(v[static_cast<std::size_t>(std::find(cols.begin(), cols.end(), name) - cols.begin())]);
    };
    const double p95 = col("mc_p95_pp_deg"), p99 = col("mc_p99_pp_deg"), worst = col("worst_pp_deg");
    CHECK(col("ideal_pp_deg") < 1e-6);  // exact field, ideal mount: no error
    CHECK(p95 <= p99);
    CHECK(p99 <= worst * 1.5);  // MC inside the box: the corners are near the top
    ++rows;
  }
  CHECK(rows == 5 * 3);
  std::ifstream rec(out / "radius_recommendation.csv");
  std::getline(rec, header);
  int recs = 0;
  while (std::getline(rec, line)) {
    const double r0 = std::stod(split(line)[2]);
    CHECK(r0 >= 1.0);
    CHECK(r0 <= 3.0);
    ++recs;
  }
  CHECK(recs == 3);
  // Error budget at the recommended r0 (the default box: offsets, sensor tilt, magnet tilt): one row per group and
  // array; the whole-box p99 is the recommendation's MC p99 (same samples, same surrogate); each group alone stays
  // below the whole box (the groups only add error here).
  CHECK(fs::exists(out / "radius_budget.csv"));
  CHECK(fs::exists(out / "budget.png"));
  std::ifstream bud(out / "radius_budget.csv");
  std::getline(bud, header);
  CHECK(header == "field,array,r0_mm,group,p99_only_deg,p99_all_deg,share");
  int brows = 0;
  std::set<std::string> groups;
  while (std::getline(bud, line)) {
    const auto v = split(line);
    REQUIRE(v.size() == 7);
    groups.insert(v[3]);
    const double only = std::stod(v[4]), all = std::stod(v[5]), share = std::stod(v[6]);
    CHECK(share == Approx(only / all).epsilon(1e-9));
    CHECK(only <= all * 1.0001);
    ++brows;
  }
  CHECK(brows == 3 * 5);  // 3 arrays x (static, dynamic, air gap, sensor tilt, magnet tilt)
  CHECK(groups.count("sensor tilt") == 1);
  CHECK(groups.count("magnet tilt") == 1);
  std::ifstream sm(out / "summary.md");
  std::stringstream sms;
  sms << sm.rdbuf();
  CHECK(sms.str().find("Share of a group = p99") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("radius study: the five-offset box (tilt tolerances 0) gives no tilt groups and the old 32 corners",
          "[studies][regression][cli]") {
  const fs::path out = fs::temp_directory_path() / ("magenc_test_radius_old_box_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const Run r = run_radius(tiny() + " --set radius.tol_tilt_x_deg=0 --set radius.tol_tilt_y_deg=0"
                                    " --set radius.tol_magnet_tilt_deg=0", out);
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream sm(out / "summary.md");
  std::stringstream sms;
  sms << sm.rdbuf();
  CHECK(sms.str().find("over its 32 corners") != std::string::npos);
  CHECK(sms.str().find("sensor tilt |tilt_x|") == std::string::npos);
  std::ifstream bud(out / "radius_budget.csv");
  std::string line;
  std::getline(bud, line);
  while (std::getline(bud, line)) CHECK(line.find("tilt") == std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("radius study: bad input exits non-zero with one line and no output", "[studies][bad-input][cli]") {
  const fs::path out = fs::temp_directory_path() / ("magenc_test_radius_bad_" + std::to_string(::getpid()));
  const std::string bad = GENERATE(as<std::string>{}, "--set radius.tol_dx_mm=-0.1",
                                   "--set radius.r0_min_mm=3 --set radius.r0_max_mm=1", "--set radius.samples=0",
                                   "--set radius.arrays=three", "--set radius.r0_min_mm=0.2",
                                   "--set sensor.offset_cos_mT=0.5", "--set sensor.plate_mm=0.2",
                                   "--set sensor.principle=inplane",
                                   "--set sensor.field_min_mT=70 --set sensor.field_max_mT=40");
  CAPTURE(bad);
  fs::remove_all(out);
  const Run r = run_radius(tiny() + " " + bad, out);
  INFO(r.err);
  CHECK(r.code == 2);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(out));
  fs::remove(out.string() + ".stderr");
}

TEST_CASE("radius study: a solved field of another magnet is never compared with this one", "[studies][bad-input][cli][slow]") {
  // solve.json of the default magnet (R = 2 mm); the study runs for R = 3 mm. Auto-added
  // (radius.fem_dir): the FEM field is skipped with a note saying why. Listed explicitly
  // (radius.fields = ...,fem:DIR): one-line error naming the key, no output.
  const fs::path base = fs::temp_directory_path() / ("magenc_test_radius_other_magnet_" + std::to_string(::getpid()));
  fs::remove_all(base);
  fs::create_directories(base / "field");
  std::ofstream(base / "field" / "solve.json")
      << R"({"magnet": {"radius_mm": 2.0, "height_mm": 4.0, "br_T": 1.2}, "plane_z_mm": 4.55})";
  const std::string field_dir = (base / "field").string();
  const std::string r3 = " --set magnet.radius_mm=3 --set radius.r0_min_mm=0.5";

  const fs::path out = base / "auto";
  const Run a = run_radius(tiny() + r3 + " --set radius.fem_dir=" + field_dir, out);
  INFO(a.err);
  REQUIRE(a.code == 0);
  std::ifstream in(out / "summary.md");
  std::stringstream ss;
  ss << in.rdbuf();
  CHECK(ss.str().find("was solved with magnet.radius_mm") != std::string::npos);
  CHECK(ss.str().find("FEM field not run") != std::string::npos);
  std::ifstream csv(out / "radius.csv");
  std::string line;
  std::getline(csv, line);
  while (std::getline(csv, line)) CHECK(line.rfind("analytic,", 0) == 0);  // no fem rows

  const fs::path out2 = base / "listed";
  const Run b = run_radius(tiny() + r3 + " --set radius.fields=analytic,fem:" + field_dir, out2);
  CHECK(b.code == 2);
  CHECK(b.err.find("radius.fields") != std::string::npos);
  CHECK(std::count(b.err.begin(), b.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(out2));
  fs::remove_all(base);
}

TEST_CASE("radius study: a field window counts out-of-window samples apart", "[studies][contract][cli]") {
  // Bz peaks near 46 mT at r0 2.4 mm and falls towards small radii: a 40 .. 70 mT window leaves the small
  // radii (all samples out) and keeps the peak region (all in); the counts add up to the samples.
  const fs::path out = fs::temp_directory_path() / ("magenc_test_radius_window_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const Run r = run_radius(tiny() + " --set radius.samples=50 --set radius.arrays=two"
                                    " --set sensor.field_min_mT=40 --set sensor.field_max_mT=70", out);
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream csv(out / "radius.csv");
  std::string line;
  std::getline(csv, line);
  const auto head = split(line);
  CHECK(head.back() == "field_max_mT");
  auto col = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(head.begin(), head.end(), name) - head.begin());
  };
  int all_out = 0, all_in = 0, rows = 0;
  while (std::getline(csv, line)) {
    const auto v = split(line);
    ++rows;
    const long out_n = std::stol(v[col("mc_out_of_window")]), in_n = std::stol(v[col("mc_samples")]);
    CHECK(out_n + in_n == 50);
    all_out += out_n == 50;
    all_in += in_n == 50;
    const double fmin = std::stod(v[col("field_min_mT")]), fmax = std::stod(v[col("field_max_mT")]);
    CHECK(fmin <= fmax);
    if (fmin >= 40 && fmax <= 70) CHECK(out_n == 0);  // every sample's extremes lie inside the window
  }
  CHECK(rows == 5);
  CHECK(all_out >= 1);  // r0 = 1 mm: Bz far below 40 mT
  CHECK(all_in >= 1);   // near the peak
  std::ifstream sm(out / "summary.md");
  std::stringstream sms;
  sms << sm.rdbuf();
  CHECK(sms.str().find("Field window") != std::string::npos);
  CHECK(sms.str().find("out of the window") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("radius study: no window, no window columns", "[studies][regression][cli]") {
  const fs::path out = fs::temp_directory_path() / ("magenc_test_radius_nowindow_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const Run r = run_radius(tiny() + " --set radius.samples=20 --set radius.arrays=two", out);
  REQUIRE(r.code == 0);
  std::ifstream csv(out / "radius.csv");
  std::string line;
  std::getline(csv, line);
  CHECK(split(line).back() == "total_worst_pp_deg");
  std::ifstream sm(out / "summary.md");
  std::stringstream sms;
  sms << sm.rdbuf();
  CHECK(sms.str().find("Field window") == std::string::npos);
  fs::remove_all(out);
}
