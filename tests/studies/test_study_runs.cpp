// Smoke tests of the study executables with tiny configurations (360 samples
// per turn, few sweep points): files exist, a few numbers with tolerances,
// and bad input exits non-zero leaving no output directory.
#include <catch2/catch.hpp>

#include <cmath>

#include "fields/analytic_field.hpp"
#include "probe/angle_error.hpp"
#include "fields/magnet.hpp"
#include "support/study_test_util.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;
using namespace magenc::test;

namespace {

const std::map<std::string, std::string>& find_row(const std::vector<std::map<std::string, std::string>>& rows,
                                                  const std::string& array, const std::string& sweep,
                                                  const std::string& col, double value) {
  for (const auto& r : rows)
    if (r.at("array") == array && r.at("sweep") == sweep && std::abs(num(r, col) - value) < 1e-12) return r;
  FAIL("no spectra row array=" << array << " sweep=" << sweep << " " << col << "=" << value);
  return rows.front();
}

ProbeSetup setup_for(const std::string& array, int steps) { return probe_setup(array, steps); }

}  // namespace

TEST_CASE("linear_model study: tiny run reproduces docs/physics.md sanity values", "[studies][physics][cli]") {
  const fs::path out = temp_out("linear_model");
  const StudyRun r = run_study_exe("linear_model", out, "--set sensor.steps=360 --set sweep.points=6");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"spectra.csv", "fits.csv", "summary.md", "config.toml", "run.json", "eps.png",
                          "harmonics.png", "coefficients.png", "eps.gp", "eps.dat"});
  CHECK(fs::file_size(out / "eps.png") > 1000);
  CHECK_FALSE(leftovers(out));

  const auto rows = read_csv(out / "spectra.csv");
  REQUIRE(rows.size() == 1 + 4 * 6);  // ideal + 4 offsets x 6 points
  // docs/physics.md: r0 = 2.4, two, 0.1 mm offsets.
  const auto& sx = find_row(rows, "two", "sx", "sx_mm", 0.1);
  CHECK(num(sx, "c2_deg") == Approx(1.653).margin(1e-3));
  CHECK(num(sx, "a0_deg") == Approx(1.169).margin(1e-3));
  CHECK(num(sx, "b2_deg") == Approx(-1.193).margin(1e-3));
  CHECK(num(sx, "c4_deg") == Approx(0.024).margin(1e-3));
  const auto& sy = find_row(rows, "two", "sy", "sy_mm", 0.1);
  CHECK(num(sy, "a0_deg") == Approx(-1.169).margin(1e-3));
  CHECK(num(sy, "b2_deg") == Approx(1.193).margin(1e-3));
  const auto& dx = find_row(rows, "two", "dx", "dx_mm", 0.1);
  CHECK(num(dx, "c1_deg") == Approx(3.376).margin(1e-3));
  CHECK(num(dx, "a2_deg") == Approx(-0.099).margin(1e-3));
  const auto& dy = find_row(rows, "two", "dy", "dy_mm", 0.5);
  CHECK(std::abs(num(dy, "pp_deg")) < 1e-9);

  const auto fits = read_csv(out / "fits.csv");
  CHECK(fits.size() == 4 * 9);
  for (const auto& f : fits)
    if (f.at("swept") == "sx_mm" && f.at("coef") == "c2_deg") {
      const double x = 0.1;
      const double v = ((num(f, "p3") * x + num(f, "p2")) * x + num(f, "p1")) * x + num(f, "p0");
      CHECK(v == Approx(1.653).margin(5e-3));  // the cubic through 6 points reproduces the value
    }
  const std::string md = slurp(out / "summary.md");
  CHECK(md.find("All listed values agree") != std::string::npos);
  CHECK(slurp(out / "config.toml").find("steps = 360") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("exact_field study: tiny run matches the library and docs/physics.md's qualitative picture",
          "[studies][physics][cli]") {
  const fs::path out = temp_out("exact_field");
  const StudyRun r = run_study_exe("exact_field", out,
                                   "--set sensor.steps=360 --set sweep.points=6 --set dz_sweep.points=5 "
                                   "--set study.arrays=two,diff4");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"spectra.csv", "fits.csv", "summary.md", "config.toml", "run.json", "eps.png",
                          "harmonics.png", "coefficients_sx.png", "coefficients_dx.png", "coefficients_dz.png"});
  const auto rows = read_csv(out / "spectra.csv");
  REQUIRE(rows.size() == 2 * (1 + 4 * 6 + 5));

  // The study's rows equal direct library runs (same field, same setup).
  const AnalyticField field{Magnet{}};
  Mount m;
  m.dx_mm = 0.1;
  const Spectrum two_dx = error_spectrum(field, setup_for("two", 360), m);
  const auto& row_two = find_row(rows, "two", "dx", "dx_mm", 0.1);
  CHECK(num(row_two, "c1_deg") == Approx(two_dx.c_deg[1]).epsilon(1e-9));
  CHECK(num(row_two, "c3_deg") == Approx(two_dx.c_deg[3]).epsilon(1e-9));
  // docs/physics.md: dynamic eccentricity with `two` gives a 1st and a sizeable 3rd
  // harmonic; with diff4 the 1st cancels and a 4th appears.
  CHECK(num(row_two, "c3_deg") > 0.1 * num(row_two, "c1_deg"));
  const auto& row_d4 = find_row(rows, "diff4", "dx", "dx_mm", 0.1);
  CHECK(num(row_d4, "c1_deg") < 1e-9);
  CHECK(num(row_d4, "c4_deg") > 1e-3);
  // Ideal mount: no error on the exact field.
  for (const auto& row : rows)
    if (row.at("sweep") == "ideal") CHECK(num(row, "pp_deg") < 1e-9);
  // dz alone-with-residual-dx: rows carry dx = 0.05.
  const auto& dz = find_row(rows, "two", "dz (dx=0.05)", "dz_mm", 0.5);
  CHECK(num(dz, "dx_mm") == Approx(0.05));

  const std::string md = slurp(out / "summary.md");
  CHECK(md.find("| dx = 0.10 mm | `diff4` |") != std::string::npos);
  CHECK(md.find("c4 ") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("studies: bad input exits non-zero and leaves no output", "[studies][bad-input][cli]") {
  for (const std::string study : {"linear_model", "exact_field"}) {
    for (const std::string args : {"--set sensor.steps=3", "--set nosuch.key=1", "--set sensor.array=three",
                                   "--set sweep.coefs=c9_deg"}) {
      const fs::path out = temp_out(study + "_bad");
      const StudyRun r = run_study_exe(study, out, args);
      INFO(study << " " << args << ": " << r.err);
      CHECK(r.code == 2);
      CHECK(r.err.find("error") != std::string::npos);
      CHECK_FALSE(fs::exists(out));
      CHECK_FALSE(leftovers(out));
    }
  }
}
