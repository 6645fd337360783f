// B-H curve tables (bh_curve.hpp): the monotone interpolation, its slope, the
// mu0 extension beyond the last row, and bad tables as one-line input errors.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "field_solver/mesh/bh_curve.hpp"
#include "core/errors.hpp"
#include "support/spreadsheet_text.hpp"

using namespace magenc::fem;

namespace {

// A soft-steel-like curve (A/m, T): steep start, knee near 1.5 T, saturation.
const char* kSteel =
    "# test curve\n"
    "H_A_per_m,B_T\n"
    "0,0\n100,0.2\n300,0.9\n600,1.2\n1000,1.35\n3000,1.55\n10000,1.7\n50000,1.85\n200000,2.05\n";

std::string error_of(const std::string& text) {
  try {
    parse_bh_csv(text, "B-H curve t.csv");
  } catch (const magenc::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("B-H curve: through the rows, monotone, C1, slope mu0 beyond the last row", "[field_solver][closed-form]") {
  const BhCurve c = parse_bh_csv(kSteel, "t");
  for (std::size_t i = 0; i < c.H().size(); ++i) CHECK(c.B_T(c.H()[i]) == Approx(c.B()[i]).epsilon(1e-14));
  // Monotone between every pair of rows (no overshoot), densely sampled, and odd in H.
  double prev = -1;
  for (double H = 0; H < 3e5; H += 37.0) {
    const double b = c.B_T(H);
    CHECK(b >= prev);
    CHECK(c.dB_dH(H) >= 0);
    CHECK(c.B_T(-H) == -b);
    prev = b;
  }
  // Beyond the table: B = B_n + mu0 (H - H_n), dB/dH = mu0 (saturated iron).
  CHECK(c.B_T(1e6) == Approx(2.05 + kMu0_T_m_per_A * 8e5).epsilon(1e-14));
  CHECK(c.dB_dH(1e6) == kMu0_T_m_per_A);
  // dB/dH is the derivative of B(H): central differences inside segments (relative 1e-6).
  for (double H : {10.0, 150.0, 450.0, 800.0, 2000.0, 7000.0, 30000.0, 120000.0}) {
    const double e = 1e-4 * H, fd = (c.B_T(H + e) - c.B_T(H - e)) / (2 * e);
    CAPTURE(H, fd, c.dB_dH(H));
    CHECK(c.dB_dH(H) == Approx(fd).epsilon(1e-6));
  }
  // The secant permeability falls from the initial one to ~1 in deep saturation.
  CHECK(c.mu_r(50.0) > 1000);
  CHECK(c.mu_r(1e8) < 1.05);
}

TEST_CASE("B-H curve: a straight line B = mu0 mu_r H stays that line", "[field_solver][closed-form]") {
  const double mu = 1000.0 * kMu0_T_m_per_A;
  std::string t = "H_A_per_m;B_T\r\n";
  for (double H : {0.0, 200.0, 500.0, 900.0, 1400.0}) {
    std::ostringstream row;
    row << std::setprecision(17) << H << ";" << mu * H << "\r\n";
    t += row.str();
  }
  const BhCurve c = parse_bh_csv(t, "t");
  for (double H = 0; H < 1400; H += 13.0) {
    CHECK(c.B_T(H) == Approx(mu * H).epsilon(1e-12).margin(1e-15));
    CHECK(c.dB_dH(H) == Approx(mu).epsilon(1e-12));
    CHECK(c.mu_r(H + 1) == Approx(1000.0).epsilon(1e-9));
  }
}

TEST_CASE("B-H curve: bad tables are one-line input errors", "[field_solver][bad-input]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"H_A_per_m,B_T\n0,0\n100,0.5\n50,0.8\n300,1.0\n", "does not increase"},       // H not increasing
      {"H_A_per_m,B_T\n0,0\n100,0.5\n200,0.4\n300,1.0\n", "does not increase"},      // B not increasing
      {"H_A_per_m,B_T\n0,0\n100,0.5\n200,0.5\n300,1.0\n", "does not increase"},      // flat
      {"H_A_per_m,B_T\n0,0\n-100,-0.5\n200,0.6\n300,1.0\n", "does not increase"},    // negative
      {"H_A_per_m,B_T\n10,0.01\n100,0.5\n200,0.6\n300,1.0\n", "not (0, 0)"},         // not from 0
      {"H_A_per_m,B_T\n0,0\n100,0.5\n200,0.6\n", "too few"},                         // too short
      {"H_A_per_m,B_T\n0,0\n100,0.5\n200,0.6\n1e7,1.0\n", "below 1"},                // B < mu0 H
      {"H_A_per_m,B_mT\n0,0\n100,500\n200,600\n300,1000\n", "column"},               // wrong header
      {"H_A_per_m,B_T\n0,0\n100,abc\n200,0.6\n300,1.0\n", "not a number"},           // not a number
      {"", "empty"},
      // Units other than the header's (the steel curve above): B in mT, H in kA/m, a near-duplicate H.
      {"H_A_per_m,B_T\n0,0\n100,200\n300,900\n600,1200\n10000,1700\n", "row 2 (H 100 A/m, B 200 T) has a polarization"},
      {"H_A_per_m,B_T\n0,0\n0.1,0.2\n0.3,0.9\n0.6,1.2\n10,1.7\n", "(H 0.1 A/m, B 0.2 T) gives a relative permeability of"},
      {"H_A_per_m,B_T\n0,0\n100,0.1\n100.0001,0.2\n1000,1.2\n10000,1.9\n", "over the segment from the row before"},
  };
  for (const auto& [text, needle] : cases) {
    const std::string e = error_of(text);
    CAPTURE(text, e);
    CHECK(e.find(needle) != std::string::npos);
    CHECK(e.find("B-H curve t.csv") == 0);
    CHECK(e.find('\n') == std::string::npos);
  }
  CHECK(error_of(kSteel).empty());
  // Trailing separators as spreadsheet programs write them ("H_A_per_m;B_T;;") are no columns.
  CHECK(error_of(magenc::test::trailing_separators(kSteel, ',', 2)).empty());
  CHECK_THROWS_AS(read_bh_csv("/nonexistent/curve.csv"), magenc::InputError);
}

TEST_CASE("B-H curve: a steep start keeps the curve's own initial permeability", "[field_solver][regression]") {
  // The three-point end slope of 0,0 / 100,0.1 / 110,0.2 is negative; the slope at H = 0 is then the first
  // segment's secant B_1 / H_1 = 1e-3 T m/A (mu_r 796), not mu0 (which made a steel part air near H = 0).
  const BhCurve c = parse_bh_csv("H_A_per_m,B_T\n0,0\n100,0.1\n110,0.2\n1000,1.2\n10000,1.9\n", "t");
  CHECK(c.dB_dH(0.0) == Approx(1e-3).epsilon(1e-12));
  CHECK(c.mu_r(0.0) == Approx(1e-3 / kMu0_T_m_per_A).epsilon(1e-12));
  // Still monotone, through the rows, with B >= mu0 H everywhere below the last row.
  double prev = -1;
  for (double H = 0; H <= 10000; H += 0.5) {
    const double b = c.B_T(H);
    CHECK(b >= prev);
    CHECK(b >= kMu0_T_m_per_A * H);
    prev = b;
  }
  for (std::size_t i = 0; i < c.H().size(); ++i) CHECK(c.B_T(c.H()[i]) == Approx(c.B()[i]).epsilon(1e-14));
  // The curves of materials/ are plausible (none trips the unit checks).
  for (const char* f : {"electrical_steel_bh.csv", "free_cutting_steel_bh.csv", "low_carbon_steel_hot_rolled_bh.csv",
                        "structural_steel_bh.csv"})
    CHECK_NOTHROW(read_bh_csv(std::filesystem::path(MAGENC_SOURCE_DIR) / "materials" / f));
}

TEST_CASE("B-H curve: a steel curve in Oe, A/cm, kA/m or mT of mu0 H is refused naming the likely unit",
          "[field_solver][bad-input]") {
  // Every curve of materials/ with its H column divided by the unit's size in A/m, as a file holding H in
  // that unit under the H_A_per_m header would be read. Their true secant permeabilities are 1,000-6,100
  // and they reach 1.7 T at 4.4-6.8 kA/m: read in Oe 80 times, in kA/m 1000 times that permeability.
  struct Unit {
    const char* name;
    double A_per_m;
    const char* named;  // what the message must name
  };
  const std::vector<Unit> units = {{"Oe", 1e3 / (4 * M_PI), "H likely in Oe"},
                                   {"A/cm", 100.0, "H likely in Oe (or A/cm"},
                                   {"kA/m", 1000.0, "H likely in kA/m"},
                                   {"mT of mu0 H", 0.0, "or mT of mu0 H"}};
  for (const char* f : {"electrical_steel_bh.csv", "free_cutting_steel_bh.csv", "low_carbon_steel_hot_rolled_bh.csv",
                        "structural_steel_bh.csv"}) {
    const BhCurve c = read_bh_csv(std::filesystem::path(MAGENC_SOURCE_DIR) / "materials" / f);
    for (const auto& u : units) {
      // mT of mu0 H: the number is 1e3 mu0 H, i.e. H divided by 1 / (1e3 mu0) = 795.8 A/m.
      const double per = std::string(u.name) == "mT of mu0 H" ? 1.0 / (1e3 * kMu0_T_m_per_A) : u.A_per_m;
      std::ostringstream t;
      t << std::setprecision(17) << "H_A_per_m,B_T\n";
      for (std::size_t i = 0; i < c.H().size(); ++i) t << c.H()[i] / per << "," << c.B()[i] << "\n";
      const std::string e = error_of(t.str());
      CAPTURE(f, u.name, e);
      CHECK(e.find("B-H curve t.csv: row ") == 0);
      CHECK(e.find("relative permeability") != std::string::npos);
      CHECK(e.find(u.named) != std::string::npos);
      CHECK(e.find('\n') == std::string::npos);
    }
  }
  // B in kG, mT or G: the polarization check names the unit.
  CHECK(error_of("H_A_per_m,B_T\n0,0\n100,2\n300,9\n600,12\n10000,17\n").find("B in kG") != std::string::npos);
  CHECK(error_of("H_A_per_m,B_T\n0,0\n100,200\n300,900\n600,1200\n10000,1700\n").find("B in mT") != std::string::npos);
  CHECK(error_of("H_A_per_m,B_T\n0,0\n100,2000\n300,9000\n600,12000\n10000,17000\n").find("B in G") != std::string::npos);
}

TEST_CASE("B-H curve: a high-permeability iron curve passes with fem.bh_iron_max_mu_r raised", "[field_solver][bad-input]") {
  // Grain-oriented Fe-Si along its rolling direction (order of magnitude of a Hi-B grade: 1.5 T at 15 A/m,
  // secant mu_r 8e4, saturation 2.03 T): refused by the default bound, read with the bound raised.
  const std::string go = "H_A_per_m,B_T\n0,0\n5,0.4\n15,1.5\n30,1.8\n100,1.9\n1000,1.96\n10000,2.03\n";
  const std::string e = error_of(go);
  CAPTURE(e);
  CHECK(e.find("B-H curve t.csv: row 3 (H 15 A/m, B 1.5 T) gives a relative permeability of ") == 0);
  CHECK(e.find("on a curve reaching a polarization of 1.7 T (iron or steel): allowed at most") != std::string::npos);
  CHECK(e.find("(fem.bh_iron_max_mu_r; H likely in ") != std::string::npos);
  const BhCurve c = parse_bh_csv(go, "t", 1e5);
  CHECK(c.mu_r(15.0) == Approx(1.5 / (15 * kMu0_T_m_per_A)).epsilon(1e-12));
  // A nickel alloy (mu-metal: saturation 0.8 T, mu_r up to 1e5) never reaches 1.7 T: only the 1e6 bound applies.
  CHECK(error_of("H_A_per_m,B_T\n0,0\n1,0.1\n4,0.5\n10,0.7\n100,0.8\n").empty());
  // The bound of every curve stays: 1e6 is refused whatever fem.bh_iron_max_mu_r says.
  CHECK_THROWS_AS(parse_bh_csv("H_A_per_m,B_T\n0,0\n0.1,0.2\n0.3,0.9\n0.6,1.2\n10,1.9\n", "t", 1e6), magenc::InputError);
}
