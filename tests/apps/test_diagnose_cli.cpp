// diagnose executable end to end: bad input gives a one-line error, exit 2 and no output directory;
// a good run writes fit.json (contract keys), fit.csv, summary.md and the PNGs.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/spreadsheet_text.hpp"
#include "support/study_test_util.hpp"

using namespace magenc::test;

namespace {

// A synthetic curve written by the test helper magenc_make_curve (same build).
fs::path make_curve(const std::string& name, const std::string& args) {
  const fs::path p = fs::temp_directory_path() / ("magenc_test_" + name + "_" + std::to_string(::getpid()) + ".csv");
  const std::string cmd = std::string(MAGENC_TEST_DIR) + "/magenc_make_curve '" + p.string() + "' " + args;
  REQUIRE(std::system(cmd.c_str()) == 0);
  return p;
}

}  // namespace

TEST_CASE("diagnose CLI: a fit writes the contract outputs", "[apps][contract][cli]") {
  const fs::path curve = make_curve("cli_good", "--set sx=0.04 --set dx=0.03 --zero 0.1 --points 180 --turns 2");
  const fs::path out = temp_out("diagnose_good");
  const StudyRun r = run_study_exe("diagnose", out, "--measured '" + curve.string() +
                                                       "' --field analytic --array two --r0 2.4 --free sx,sy,dx,dy --starts 2");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"fit.json", "fit.csv", "summary.md", "fit.png", "harmonics.png", "config.toml"});
  const auto j = nlohmann::json::parse(slurp(out / "fit.json"));
  CHECK(j["parameters"]["sx_mm"]["free"] == true);
  CHECK(j["parameters"]["sx_mm"]["value"].get<double>() == Approx(0.04).margin(0.005));
  CHECK(j["parameters"]["dx_mm"]["value"].get<double>() == Approx(0.03).margin(0.001));
  CHECK(j["parameters"]["dz_mm"]["free"] == false);
  CHECK(j["parameters"]["zero_offset_deg"]["value"].get<double>() == Approx(0.1).margin(0.05));
  CHECK(j["residual_rms_deg"].get<double>() < 0.03);
  CHECK(j["converged"] == true);
  CHECK(j["explained_fraction"].get<double>() > 0.9);
  CHECK(j["not_identifiable"].is_array());
  CHECK(j["run"]["seed"].is_null() == false);
  const auto rows = read_csv(out / "fit.csv");
  CHECK(rows.size() == 360);  // two turns of 180, folded, all kept
  CHECK(rows.front().count("residual_deg") == 1);
  CHECK_FALSE(leftovers(out));
  fs::remove_all(out);
  fs::remove(curve);
}

TEST_CASE("diagnose CLI: bad input is one line, exit 2, no output", "[apps][bad-input][cli]") {
  const fs::path bad = fs::temp_directory_path() / ("magenc_test_bad_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream f(bad);
    f << "theta_deg,error_deg\n";
    for (int i = 0; i < 80; ++i) f << i * 4.5 << "," << (i == 40 ? "nan" : "0.1") << "\n";
  }
  const fs::path out = temp_out("diagnose_bad");
  StudyRun r = run_study_exe("diagnose", out, "--measured '" + bad.string() + "'");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Catch::Contains("row 42") && Catch::Contains("not finite"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(out));
  const fs::path good = make_curve("cli_free", "--points 90");
  r = run_study_exe("diagnose", out, "--measured '" + good.string() + "' --free sx,foo");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Catch::Contains("'foo' is unknown"));
  r = run_study_exe("diagnose", out, "--measured '" + good.string() + "' --curve-set 2:dz+=0.1");
  CHECK(r.code == 2);
  CHECK_THAT(r.err, Catch::Contains("curve 2 does not exist"));
  CHECK_FALSE(fs::exists(out));
  fs::remove(bad);
  fs::remove(good);
}

TEST_CASE("diagnose CLI: curves saved as Excel's CSV UTF-8 and in the European form fit like the plain file",
          "[apps][regression][cli]") {
  // Once refused with "unknown column '\ufefftheta_deg'" and "unknown column 'theta_deg;error_deg'".
  const fs::path plain = make_curve("cli_plain", "--set sx=0.04 --set dx=0.03 --points 90");
  const std::string text = slurp(plain);
  const std::vector<std::pair<std::string, std::string>> forms = {
      {"plain", text},
      {"CSV UTF-8 (BOM, CRLF)", magenc::test::with_bom(magenc::test::with_crlf(text))},
      {"';' with decimal comma", magenc::test::european(text)}};
  std::vector<double> sx, dx;
  for (std::size_t k = 0; k < forms.size(); ++k) {
    CAPTURE(forms[k].first);
    const fs::path f = fs::temp_directory_path() / ("magenc_test_form" + std::to_string(k) + "_" +
                                                    std::to_string(::getpid()) + ".csv");
    std::ofstream(f, std::ios::binary) << forms[k].second;
    const fs::path out = temp_out("diagnose_form" + std::to_string(k));
    const StudyRun r = run_study_exe("diagnose", out, "--measured '" + f.string() +
                                                         "' --field analytic --array two --r0 2.4 --free sx,dx --starts 1");
    INFO(r.err);
    REQUIRE(r.code == 0);
    const auto j = nlohmann::json::parse(slurp(out / "fit.json"));
    sx.push_back(j["parameters"]["sx_mm"]["value"].get<double>());
    dx.push_back(j["parameters"]["dx_mm"]["value"].get<double>());
    fs::remove_all(out);
    fs::remove(f);
  }
  CHECK(sx[0] == Approx(0.04).margin(0.005));
  for (std::size_t k = 1; k < forms.size(); ++k) {
    CHECK(sx[k] == sx[0]);  // the same numbers, so the same fit
    CHECK(dx[k] == dx[0]);
  }
  fs::remove(plain);
}

TEST_CASE("diagnose CLI: a fit that does not explain the curve exits 3 with one line and no output",
          "[apps][bad-input][cli]") {
  // A 0.5 deg 7th harmonic: no parameter of `two` makes one.
  const fs::path curve = fs::temp_directory_path() / ("magenc_test_h7_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream f(curve);
    f << "theta_deg,error_deg\n";
    for (int i = 0; i < 180; ++i) f << i * 2.0 << "," << 0.5 * std::sin(7 * i * 2.0 * M_PI / 180) << "\n";
  }
  const fs::path out = temp_out("diagnose_h7");
  const StudyRun r = run_study_exe("diagnose", out, "--measured '" + curve.string() +
                                                       "' --field analytic --array two --r0 2.4 --free sx,sy,dx,dy --starts 2");
  CHECK(r.code == 3);
  CHECK_THAT(r.err, Catch::Contains("the fit leaves a residual RMS of") && Catch::Contains("in harmonics 1..8"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(out));
  fs::remove(curve);
}
