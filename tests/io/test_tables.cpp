// CSV tables (src/io/tables.*): the spectra and fits headers of docs/interfaces.md,
// full-precision numbers, and strict parsing of mounting-case files.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/errors.hpp"
#include "io/tables.hpp"
#include "support/spreadsheet_text.hpp"

using namespace magenc;
namespace fs = std::filesystem;

namespace {
fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("magenc_test_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}
std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }
}  // namespace

TEST_CASE("spectra table header and numbers", "[io][contract]") {
  SpectrumRow r;
  r.field = "linear";
  r.array = "two";
  r.r0_mm = 2.4;
  r.mount.sx_mm = 0.1;
  r.spectrum.a0_deg = 1.1691393281234;
  r.spectrum.c_deg[8] = -2.5e-17;
  const std::string csv = spectra_csv({r});
  std::string want = "field,array,r0_mm,sx_mm,sy_mm,dx_mm,dy_mm,dz_mm,a0_deg";
  for (char k : {'a', 'b', 'c'})
    for (int n = 1; n <= 8; ++n) want += std::string(",") + k + std::to_string(n) + "_deg";
  want += ",pp_deg";
  CHECK(first_line(csv) == want);
  CHECK(csv.find("linear,two,2.4,0.1,0,0,0,0,1.169139328,") != std::string::npos);  // %.10g
  CHECK(csv.find("-2.5e-17") != std::string::npos);
  r.extra = {{"note", "a,b"}};
  CHECK(spectra_csv({r}).find(",\"a,b\"\n") != std::string::npos);
}

TEST_CASE("spectra table of a multipole read: ce1..ce4 after pp, every row or none", "[io][contract]") {
  SpectrumRow r;
  r.field = "analytic";
  r.array = "two";
  r.spectrum.pole_pairs = 32;
  r.spectrum.ce_deg = {0.5, 0.25, 0.125, 0.09266};
  r.extra = {{"principle", "bz"}};
  const std::string csv = spectra_csv({r, r});
  CHECK(first_line(csv).find(",pp_deg,ce1_deg,ce2_deg,ce3_deg,ce4_deg,principle") != std::string::npos);
  CHECK(csv.find(",0.5,0.25,0.125,0.09266,bz\n") != std::string::npos);
  CHECK(r.spectrum.column("ce4_deg") == 0.09266);
  SpectrumRow plain = r;
  plain.spectrum.pole_pairs = 0;
  CHECK_THROWS_AS(spectra_csv({r, plain}), std::invalid_argument);
  CHECK(first_line(spectra_csv({plain})).find("ce1_deg") == std::string::npos);
  CHECK_THROWS_AS(plain.spectrum.column("ce1_deg"), std::invalid_argument);
}

TEST_CASE("fits table header", "[io][contract]") {
  FitRow f{"static", "sx_mm", "c2_deg", {1, 2, 3, 4}, {}};
  CHECK(fits_csv({f}) == "study,swept,coef,p3,p2,p1,p0\nstatic,sx_mm,c2_deg,1,2,3,4\n");
}

TEST_CASE("cases CSV: columns in any order, missing = 0", "[io][contract]") {
  const auto p = write_temp("ok.csv", "dx_mm, sx_mm\n0.1,0.2\n-0.05 , 1e-2\r\n\n");
  const auto cases = read_cases_csv(p);
  REQUIRE(cases.size() == 2);
  CHECK(cases[0].dx_mm == 0.1);
  CHECK(cases[0].sx_mm == 0.2);
  CHECK(cases[0].sy_mm == 0.0);
  CHECK(cases[1].sx_mm == 0.01);
  fs::remove(p);
}

TEST_CASE("cases CSV: files as spreadsheet programs save them read as the plain CSV", "[io][regression]") {
  const std::string plain = "sx_mm,dx_mm,tilt_x_deg\n0.1,-0.05,1.5\n0,0.025,0\n";
  for (const std::string& text : {test::with_bom(plain), test::with_crlf(plain), test::european(plain),
                                  test::with_bom(test::with_crlf(test::european(plain))), test::european(plain, '\t')}) {
    CAPTURE(text);
    const auto p = write_temp("forms.csv", text);
    const auto cases = read_cases_csv(p);
    REQUIRE(cases.size() == 2);
    CHECK(cases[0].sx_mm == 0.1);
    CHECK(cases[0].dx_mm == -0.05);
    CHECK(cases[0].tilt_x_deg == 1.5);
    CHECK(cases[1].dx_mm == 0.025);
    fs::remove(p);
  }
  // A decimal comma between comma separators: one line naming the line and the likely cause.
  const auto p = write_temp("mixed.csv", "sx_mm,dx_mm\n0,1,0,2\n");
  try {
    read_cases_csv(p);
    FAIL("no InputError");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    CHECK(msg.find(":2:") != std::string::npos);
    CHECK(msg.find("decimal comma") != std::string::npos);
    CHECK(msg.find('\n') == std::string::npos);
  }
  fs::remove(p);
}

TEST_CASE("cases CSV: optional tilt columns", "[io][contract]") {
  const auto p = write_temp("tilt.csv", "sx_mm,tilt_x_deg,tilt_y_deg,magnet_tilt_deg,magnet_tilt_azimuth_deg\n"
                                        "0.1,1,-0.5,2,30\n0,0,0,0,0\n");
  const auto cases = read_cases_csv(p);
  REQUIRE(cases.size() == 2);
  CHECK(cases[0].tilt_x_deg == 1.0);
  CHECK(cases[0].tilt_y_deg == -0.5);
  CHECK(cases[0].magnet_tilt_deg == 2.0);
  CHECK(cases[0].magnet_tilt_azimuth_deg == 30.0);
  CHECK_FALSE(cases[1].tilted());
  fs::remove(p);
  const auto bad = write_temp("tilt_bad.csv", "tilt_x_deg\n50\n");
  try {
    read_cases_csv(bad);
    FAIL("no InputError");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    CAPTURE(msg);
    CHECK(msg.find(":2:") != std::string::npos);
    CHECK(msg.find("mount.tilt_x_deg") != std::string::npos);
    CHECK(msg.find("allowed") != std::string::npos);
  }
  fs::remove(bad);
}

TEST_CASE("cases CSV: strict errors name the file, line and column", "[io][bad-input]") {
  struct Bad {
    const char* text;
    const char* expect;  // substring of the message
  };
  for (const Bad b : {Bad{"sx_mm,foo\n1,2\n", "unknown column 'foo'"}, Bad{"sx_mm,dy_mm\n1\n", ":2:"},
                      Bad{"sx_mm\nabc\n", "column sx_mm = 'abc'"}, Bad{"sx_mm\nnan\n", "'nan'"},
                      Bad{"sx_mm\ninf\n", "'inf'"}, Bad{"sx_mm\n1e999\n", "'1e999'"}, Bad{"sx_mm\n0.1x\n", "'0.1x'"},
                      Bad{"sx_mm,sx_mm\n1,2\n", "twice"}, Bad{"sx_mm\n", "no data rows"},
                      Bad{"", "empty file"}, Bad{"sx_mm,dx_mm\n1,\n", "column dx_mm = ''"}}) {
    const auto p = write_temp("bad.csv", b.text);
    CAPTURE(b.text);
    try {
      read_cases_csv(p);
      FAIL("no InputError");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CAPTURE(msg);
      CHECK(msg.find(p.string()) != std::string::npos);
      CHECK(msg.find(b.expect) != std::string::npos);
      CHECK(msg.find("allowed") != std::string::npos);
      CHECK(msg.find('\n') == std::string::npos);
    }
    fs::remove(p);
  }
  CHECK_THROWS_AS(read_cases_csv("/nonexistent/cases.csv"), InputError);
}
