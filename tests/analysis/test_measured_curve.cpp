// Measured-curve reader (src/analysis/measured_curve): every bad-input class gets a one-line InputError
// naming the problem and the row; good files in each format, several turns folded, non-uniform sampling;
// least-squares harmonics on non-uniform samples.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "analysis/measured_curve.hpp"
#include "core/errors.hpp"
#include "core/units.hpp"
#include "support/spreadsheet_text.hpp"

using namespace magenc;

namespace {

// theta = 0, step, ... (n rows) with error = 0.1 + 0.05 cos(2 theta).
std::string curve_text(int n, double step_deg, double start_deg = 0.0) {
  std::ostringstream os;
  os << "theta_deg,error_deg\n";
  os.precision(12);
  for (int i = 0; i < n; ++i) {
    const double t = start_deg + i * step_deg;
    os << t << "," << 0.1 + 0.05 * std::cos(2 * deg_to_rad(t)) << "\n";
  }
  return os.str();
}

// The InputError message of parsing text (fails the test when it parses).
std::string error_of(const std::string& text, const CurveReadOptions& o = {}) {
  try {
    parse_measured_curve(text, "c.csv", o);
  } catch (const InputError& e) {
    return e.what();
  }
  FAIL("no InputError for:\n" << text.substr(0, 200));
  return "";
}

}  // namespace

TEST_CASE("measured curve: bad input classes each get a one-line error naming the row", "[analysis][bad-input]") {
  const std::string good = curve_text(72, 5.0);
  REQUIRE_NOTHROW(parse_measured_curve(good, "c.csv"));
  auto replace_line = [&](int line, const std::string& with) {  // 1-based line of the file
    std::istringstream in(good);
    std::ostringstream out;
    std::string l;
    for (int i = 1; std::getline(in, l); ++i) out << (i == line ? with : l) << "\n";
    return out.str();
  };
  std::string m;
  SECTION("NaN") {
    m = error_of(replace_line(5, "15,nan"));
    CHECK_THAT(m, Catch::Contains("row 5") && Catch::Contains("not finite"));
  }
  SECTION("non-numeric") {
    m = error_of(replace_line(7, "25,abc"));
    CHECK_THAT(m, Catch::Contains("row 7") && Catch::Contains("not a number"));
    m = error_of(replace_line(8, "30x,0.1"));
    CHECK_THAT(m, Catch::Contains("row 8") && Catch::Contains("theta_deg"));
  }
  SECTION("too few points") {
    m = error_of(curve_text(63, 360.0 / 63));
    CHECK_THAT(m, Catch::Contains("63") && Catch::Contains("at least 64"));
  }
  SECTION("less than a turn") {
    m = error_of(curve_text(100, 3.0));  // 0..297 deg
    CHECK_THAT(m, Catch::Contains("covers only 297") && Catch::Contains("one turn"));
  }
  SECTION("gap above the limit") {
    std::string t = "theta_deg,error_deg\n";
    for (int i = 0; i < 100; ++i) {
      const double th = i < 50 ? i * 2.0 : 140.0 + (i - 50) * 4.4;  // 98 -> 140: 42 deg gap
      t += std::to_string(th) + ",0.0\n";
    }
    m = error_of(t);
    CHECK_THAT(m, Catch::Contains("gap of 42") && Catch::Contains("row 51") && Catch::Contains("row 52"));
    CurveReadOptions o;
    o.max_gap_deg = 45;
    CHECK(parse_measured_curve(t, "c.csv", o).largest_gap_deg == Approx(42.0));
  }
  SECTION("duplicate angle with a different value") {
    m = error_of(replace_line(10, "5,0.3"));  // row 3 has theta 5
    CHECK_THAT(m, Catch::Contains("row 10") && Catch::Contains("repeats row 3"));
  }
  SECTION("duplicate angle with the same value is kept once") {
    std::istringstream in(good);
    std::string h, l1, l2;
    std::getline(in, h);
    std::getline(in, l1);
    std::getline(in, l2);
    const MeasuredCurve c = parse_measured_curve(good + l2 + "\n", "c.csv");
    CHECK(c.size() == 72);
    CHECK(c.duplicates == 1);
  }
  SECTION("unknown column") {
    m = error_of(replace_line(1, "theta_deg,err_deg"));
    CHECK_THAT(m, Catch::Contains("row 1") && Catch::Contains("unknown column 'err_deg'"));
    m = error_of(replace_line(1, "theta_deg,error_deg,phi_deg"));
    CHECK_THAT(m, Catch::Contains("one curve format"));
  }
  SECTION("wrong cell count and empty cell") {
    m = error_of(replace_line(4, "10,0.1,3"));
    CHECK_THAT(m, Catch::Contains("row 4") && Catch::Contains("3 cells"));
    m = error_of(replace_line(4, "10,"));
    CHECK_THAT(m, Catch::Contains("row 4") && Catch::Contains("empty"));
  }
  SECTION("no header, raw channels both zero, error sign on a phi file") {
    CHECK_THAT(error_of("# only a comment\n"), Catch::Contains("no header"));
    std::string raw = "theta_deg,u_cos,u_sin\n";
    for (int i = 0; i < 72; ++i) raw += std::to_string(i * 5.0) + (i == 3 ? ",0,0\n" : ",1,0.5\n");
    CHECK_THAT(error_of(raw), Catch::Contains("row 5") && Catch::Contains("u_cos = u_sin = 0"));
    std::string phi = "theta_deg,phi_deg\n";
    for (int i = 0; i < 72; ++i) phi += std::to_string(i * 5.0) + "," + std::to_string(i * 5.0) + "\n";
    CurveReadOptions o;
    o.error_sign = -1;
    CHECK_THAT(error_of(phi, o), Catch::Contains("--error-sign"));
  }
  CHECK(m.find('\n') == std::string::npos);
}

TEST_CASE("measured curve: formats, error sign, folding of two turns, non-uniform samples", "[analysis][contract]") {
  SECTION("two turns fold onto one, sorted, every sample kept") {
    const MeasuredCurve c = parse_measured_curve(curve_text(144, 5.0, -360.0 + 2.5), "c.csv");  // -357.5 .. 357.5
    CHECK(c.size() == 144);
    CHECK(c.turns == Approx(715.0 / 360.0));
    for (Eigen::Index i = 0; i < c.theta_deg.size(); ++i) {
      CHECK(c.theta_deg[i] >= 0.0);
      CHECK(c.theta_deg[i] < 360.0);
      if (i) CHECK(c.theta_deg[i] >= c.theta_deg[i - 1]);
      CHECK(c.error_deg[i] == Approx(0.1 + 0.05 * std::cos(2 * deg_to_rad(c.theta_deg[i]))).margin(1e-9));
    }
    CHECK(c.largest_gap_deg == Approx(5.0));
  }
  SECTION("non-uniform sampling with a reported (allowed) gap") {
    std::string t = "theta_deg,error_deg\n";
    double th = 0;
    for (int i = 0; th < 360.0; ++i) {
      t += std::to_string(th) + ",0.0\n";
      th += (i % 3 == 0) ? 0.7 : 2.3;
      if (std::abs(th - 180.0) < 1.2) th += 20.0;  // a 20-deg hole
    }
    const MeasuredCurve c = parse_measured_curve(t, "c.csv");
    REQUIRE_FALSE(c.gaps.empty());
    CHECK(c.gaps.front().width_deg > 20.0);
    CHECK(c.gaps.front().width_deg < 23.5);
  }
  SECTION("phi, raw channels and error sign give the same error") {
    std::string e = "theta_deg,error_deg\n", em = "theta_deg,error_deg\n", p = "# comment\ntheta_deg,phi_deg\n",
                r = "theta_deg,u_cos,u_sin\n";
    for (int i = 0; i < 90; ++i) {
      const double th = i * 4.0, err = 0.3 * std::sin(deg_to_rad(th)), phi = th + err;
      e += std::to_string(th) + "," + std::to_string(err) + "\n";
      em += std::to_string(th) + "," + std::to_string(-err) + "\n";
      p += std::to_string(th) + "," + std::to_string(std::fmod(phi + 720.0, 360.0)) + "\n";
      char buf[128];
      std::snprintf(buf, sizeof buf, "%.12g,%.12g,%.12g\n", th, 2.5 * std::cos(deg_to_rad(phi)), 2.5 * std::sin(deg_to_rad(phi)));
      r += buf;
    }
    CurveReadOptions neg;
    neg.error_sign = -1;
    const MeasuredCurve a = parse_measured_curve(e, "e.csv"), b = parse_measured_curve(em, "em.csv", neg),
                        c = parse_measured_curve(p, "p.csv"), d = parse_measured_curve(r, "r.csv");
    CHECK(c.format == "phi_deg");
    CHECK(d.format == "raw");
    for (Eigen::Index i = 0; i < a.error_deg.size(); ++i) {
      CHECK(b.error_deg[i] == Approx(a.error_deg[i]).margin(1e-6));
      CHECK(c.error_deg[i] == Approx(a.error_deg[i]).margin(1e-5));
      CHECK(d.error_deg[i] == Approx(a.error_deg[i]).margin(1e-6));
    }
  }
}

TEST_CASE("measured curve: files as spreadsheet programs save them read as the plain CSV", "[analysis][regression]") {
  // Excel's "CSV UTF-8" starts with a byte-order mark (once refused: "unknown column '\ufefftheta_deg'"); the
  // European form has ';' between fields and decimal commas (once refused: "unknown column
  // 'theta_deg;error_deg'"); Windows line ends; tab-separated text with decimal commas; old Mac CR line ends.
  const std::string plain = "# bench run 7\n" + curve_text(72, 5.0, 0.25);
  const MeasuredCurve ref = parse_measured_curve(plain, "c.csv");
  const std::vector<std::pair<std::string, std::string>> forms = {
      {"UTF-8 BOM", test::with_bom(plain)},
      {"CRLF", test::with_crlf(plain)},
      {"CR only", test::with_crlf(plain, true)},
      {"';' and decimal comma", test::european(plain)},
      {"BOM, ';', decimal comma, CRLF", test::with_bom(test::with_crlf(test::european(plain)))},
      {"tab and decimal comma", test::european(plain, '\t')},
      {"raw channels, ';' form", test::european("theta_deg,u_cos,u_sin\n0,1.5,0\n" + [] {
         std::string r;
         for (int i = 1; i < 72; ++i) r += std::to_string(i * 5) + ".0,1.5,0.25\n";
         return r;
       }())}};
  for (const auto& [form, text] : forms) {
    CAPTURE(form);
    const MeasuredCurve c = parse_measured_curve(text, "c.csv");
    if (form.rfind("raw", 0) == 0) {
      CHECK(c.format == "raw");
      CHECK(c.size() == 72);
      continue;
    }
    REQUIRE(c.size() == ref.size());
    CHECK(c.format == ref.format);
    CHECK(c.theta_deg == ref.theta_deg);
    CHECK(c.error_deg == ref.error_deg);
    CHECK(c.row == ref.row);
  }
  // A decimal comma in a comma-separated file splits the number: refused on one line naming the row.
  const std::string m = error_of("theta_deg,error_deg\n0,0,5\n");
  CHECK_THAT(m, Catch::Contains("row 2") && Catch::Contains("3 cells") && Catch::Contains("decimal comma"));
  CHECK(m.find('\n') == std::string::npos);
}

TEST_CASE("harmonics_ls recovers coefficients from non-uniform samples", "[analysis][closed-form]") {
  Eigen::VectorXd th(200), v(200);
  for (int i = 0; i < 200; ++i) {
    th[i] = 360.0 * std::pow((i + 0.5) / 200.0, 1.3);  // denser at small theta
    const double t = deg_to_rad(th[i]);
    v[i] = 0.2 - 0.7 * std::cos(t) + 0.3 * std::sin(3 * t) + 0.05 * std::cos(8 * t);
  }
  const Eigen::VectorXd h = harmonics_ls(th, v);
  CHECK(h[0] == Approx(0.2).margin(1e-12));
  CHECK(h[1] == Approx(-0.7).margin(1e-12));
  CHECK(h[6] == Approx(0.3).margin(1e-12));
  CHECK(h[15] == Approx(0.05).margin(1e-12));
  CHECK(std::abs(h[4]) < 1e-12);
}
