// error_sources study (studies/error_sources/error_sources.cpp) with a tiny configuration:
// the docs/physics.md reference values ("Beyond the five offsets": exact field,
// default magnet, r0 = 2.4 mm, `two`), the symmetry statements (elevation
// gives nothing on diff4), the fits table naming the source, the harmonic
// table and heat map, and bad input.
// Tolerances: docs/physics.md prints three decimals (7.70: two), so each value
// must agree within one unit of its last printed digit (0.001 deg; 0.01 deg
// for 7.70). 720 samples per turn instead of 3600: the spectrum of these
// smooth error curves (harmonics above 8 are < 1e-5 deg) does not depend on it
// beyond 1e-9 deg.
#include <catch2/catch.hpp>

#include <cmath>

#include "support/study_test_util.hpp"

using namespace magenc::test;

namespace {
double value_of(const std::vector<std::map<std::string, std::string>>& rows, const std::string& array,
                const std::string& swept, double value, const std::string& col) {
  for (const auto& r : rows)
    if (r.at("array") == array && r.at("swept") == swept && std::abs(num(r, "value") - value) < 1e-12)
      return num(r, col);
  FAIL("no spectra row array=" << array << " swept=" << swept << " value=" << value);
  return NAN;
}
}  // namespace

TEST_CASE("error_sources study: tiny run reproduces docs/physics.md reference values", "[studies][physics][cli]") {
  const fs::path out = temp_out("error_sources");
  const StudyRun r = run_study_exe("error_sources", out,
                                   "--set sensor.steps=720 --set sweep.points=5 --set study.arrays=two,diff4");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"spectra.csv", "fits.csv", "harmonics.csv", "summary.md", "config.toml", "run.json",
                          "harmonics_heatmap.png", "coefficients_tilt_x_deg.png", "coefficients_phase_error_deg.png"});
  CHECK(fs::file_size(out / "harmonics_heatmap.png") > 1000);
  CHECK_FALSE(leftovers(out));

  const auto rows = read_csv(out / "spectra.csv");
  REQUIRE(rows.size() == 8 * 2 * 5);  // 8 sources x 2 arrays x 5 values
  // Sweep grids: tilts 0..2 (step 0.5), elevation 0..5 (1.25), offsets 0..1 (0.25), gain 0..0.02 (0.005), phase 0..2.
  CHECK(value_of(rows, "two", "tilt_x_deg", 1.0, "a0_deg") == Approx(-0.403).margin(1e-3));
  CHECK(value_of(rows, "two", "tilt_x_deg", 1.0, "c2_deg") == Approx(0.754).margin(1e-3));
  CHECK(value_of(rows, "two", "magnet_tilt_deg", 1.0, "c1_deg") == Approx(2.476).margin(1e-3));
  CHECK(value_of(rows, "two", "magnet_tilt_deg", 1.0, "c3_deg") == Approx(0.259).margin(1e-3));
  CHECK(value_of(rows, "two", "magnetization_elevation_deg", 5.0, "c1_deg") == Approx(7.70).margin(1e-2));
  CHECK(value_of(rows, "two", "offset_cos_mT", 0.5, "c1_deg") == Approx(0.627).margin(1e-3));
  CHECK(value_of(rows, "two", "gain_mismatch", 0.01, "c2_deg") == Approx(0.285).margin(1e-3));
  CHECK(value_of(rows, "two", "phase_error_deg", 1.0, "a0_deg") == Approx(0.500).margin(1e-3));
  CHECK(value_of(rows, "two", "phase_error_deg", 1.0, "c2_deg") == Approx(0.500).margin(1e-3));
  // docs/physics.md: the axial magnetization adds a common offset to every probe: nothing for diff4.
  CHECK(value_of(rows, "diff4", "magnetization_elevation_deg", 5.0, "pp_deg") < 1e-9);
  // Every sweep starts at an ideal mount: no error at value 0.
  for (const char* s : {"tilt_x_deg", "magnet_tilt_deg", "offset_sin_mT", "phase_error_deg"})
    CHECK(value_of(rows, "two", s, 0.0, "pp_deg") < 1e-9);

  // Fits name the source; the cubic of c2 against the gain passes through the computed point.
  const auto fits = read_csv(out / "fits.csv");
  bool found = false;
  for (const auto& f : fits)
    if (f.at("swept") == "gain_mismatch" && f.at("coef") == "c2_deg" && f.at("array") == "two") {
      found = true;
      const double x = 0.01;
      const double y = ((num(f, "p3") * x + num(f, "p2")) * x + num(f, "p1")) * x + num(f, "p0");
      CHECK(y == Approx(0.285).margin(1e-3));
    }
  CHECK(found);
  // harmonics.csv: one row per source and array, at the largest swept value.
  const auto h = read_csv(out / "harmonics.csv");
  REQUIRE(h.size() == 16);
  for (const auto& row : h)
    if (row.at("source") == "magnetization_elevation_deg" && row.at("array") == "two") {
      CHECK(num(row, "value") == Approx(5.0));
      CHECK(num(row, "c1_deg") == Approx(7.70).margin(1e-2));
    }
  const std::string md = slurp(out / "summary.md");
  CHECK(md.find("Which source makes which harmonic") != std::string::npos);
  CHECK(md.find("harmonics_heatmap.png") != std::string::npos);
}

TEST_CASE("error_sources study: bad input exits non-zero without output", "[studies][bad-input][cli]") {
  const fs::path out = temp_out("error_sources_bad");
  StudyRun r = run_study_exe("error_sources", out, "--set study.sources=tilt_x_deg,tilt_z_deg");
  CHECK(r.code == 2);
  CHECK(r.err.find("tilt_z_deg") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  r = run_study_exe("error_sources", out, "--set study.field=linear --set study.sources=magnetization_elevation_deg");
  CHECK(r.code == 2);
  CHECK(r.err.find("allowed analytic") != std::string::npos);
  CHECK_FALSE(fs::exists(out));
  r = run_study_exe("error_sources", out, "--set sweep.tilt_max_deg=-1");
  CHECK(r.code == 2);
  CHECK_FALSE(fs::exists(out));
}
