// Points CSV of field_at (src/io/points_csv.*): column order, comments, CRLF, the answer table's round trip.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

#include "core/errors.hpp"
#include "io/points_csv.hpp"

TEST_CASE("points CSV: any column order, comments, blank lines and CRLF", "[io][contract]") {
  const Eigen::Matrix3Xd p =
      magenc::parse_points_csv("# points\r\nz_mm, x_mm ,y_mm\r\n1e-3,2,3\r\n\r\n-0,5.5,-7.25\r\n", "pts.csv");
  REQUIRE(p.cols() == 2);
  CHECK(p(0, 0) == 2);
  CHECK(p(1, 0) == 3);
  CHECK(p(2, 0) == 1e-3);
  CHECK(p(0, 1) == 5.5);
  CHECK(p(1, 1) == -7.25);
  CHECK(p(2, 1) == 0);
}

TEST_CASE("points CSV: the answer table reads back to the same doubles", "[io][contract]") {
  Eigen::Matrix3Xd p(3, 2), B(3, 2);
  p << 0.1, -1.0 / 3, 1e-300, 2.0, 3.0, 4.0;
  B << std::sqrt(2.0), -1e-17, 0.0, 1.0 / 7, 123456.789, -5e-9;
  const std::string t = magenc::points_field_csv(p, B);
  std::istringstream in(t);
  std::string line;
  std::getline(in, line);
  CHECK(line == "x_mm,y_mm,z_mm,Bx_T,By_T,Bz_T");
  for (int j = 0; j < 2; ++j) {
    std::getline(in, line);
    std::stringstream ss(line);
    std::string c;
    for (int k = 0; k < 6; ++k) {
      std::getline(ss, c, ',');
      CHECK(std::stod(c) == (k < 3 ? p(k, j) : B(k - 3, j)));
    }
  }
}

TEST_CASE("points CSV: bad files are refused with one line naming the line and column", "[io][bad-input]") {
  using Catch::Contains;
  CHECK_THROWS_WITH(magenc::parse_points_csv("x_mm,y_mm,x_mm\n", "f"), Contains("f line 1: column 'x_mm' appears twice"));
  CHECK_THROWS_WITH(magenc::parse_points_csv("x_mm,y_mm,z_mm\n1,,3\n", "f"),
                    Contains("f line 2: column y_mm is empty"));
  CHECK_THROWS_WITH(magenc::parse_points_csv("x_mm,y_mm,z_mm\n1,2,3,4\n", "f"), Contains("4 cells, the header has 3"));
  CHECK_THROWS_AS(magenc::parse_points_csv("x_m,y_m,z_m\n1,2,3\n", "f"), magenc::InputError);
  CHECK_THROWS_WITH(magenc::read_points_csv("/nonexistent/p.csv"), Contains("--points /nonexistent/p.csv does not exist"));
}

TEST_CASE("scan CSV: mT or T columns in any order, converted to T", "[io][contract]") {
  const auto a = magenc::parse_scan_csv("x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT\n1,2,3,-20,0.5,7\n", "s");
  CHECK(a.unit == "mT");
  CHECK(a.p_mm(2, 0) == 3);
  CHECK(a.B_T(0, 0) == Approx(-0.020).epsilon(1e-15));
  CHECK(a.B_T(2, 0) == Approx(0.007).epsilon(1e-15));
  const auto b = magenc::parse_scan_csv("# T\r\nBz_T,Bx_T,By_T,z_mm,y_mm,x_mm\r\n0.01,-0.02,0,5,0,1\r\n", "s");
  CHECK(b.unit == "T");
  CHECK(b.p_mm(0, 0) == 1);
  CHECK(b.B_T(0, 0) == -0.02);
  CHECK(b.B_T(2, 0) == 0.01);
}

TEST_CASE("scan CSV: bad files are refused with one line", "[io][bad-input]") {
  using Catch::Contains;
  CHECK_THROWS_WITH(magenc::parse_scan_csv("x_mm,y_mm,z_mm,Bx_mT,By_T,Bz_mT\n0,0,4,1,2,3\n", "s"),
                    Contains("field columns in both mT and T"));
  CHECK_THROWS_WITH(magenc::parse_scan_csv("x_mm,y_mm,z_mm,Bx_mT,By_mT\n0,0,4,1,2\n", "s"),
                    Contains("missing column 'Bz_mT'"));
  CHECK_THROWS_WITH(magenc::parse_scan_csv("x_mm,y_mm,z_mm\n0,0,4\n", "s"), Contains("missing column 'Bx_mT'"));
  CHECK_THROWS_WITH(magenc::parse_scan_csv("x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT\n0,0,4,1,inf,3\n", "s"),
                    Contains("s line 2: column By_mT = 'inf' is not finite"));
  CHECK_THROWS_WITH(magenc::parse_scan_csv("x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT,T_C\n", "s"),
                    Contains("unknown column 'T_C'"));
  CHECK_THROWS_WITH(magenc::read_scan_csv("/nonexistent/s.csv"), Contains("--scan /nonexistent/s.csv does not exist"));
}

TEST_CASE("points and scan CSV: files as spreadsheet programs save them (byte-order mark, semicolons, decimal comma)",
          "[io][contract]") {
  const auto p = magenc::parse_points_csv("\xEF\xBB\xBFx_mm;y_mm;z_mm\r\n0,5;-1,25;4,55\r\n", "pts.csv");
  REQUIRE(p.cols() == 1);
  CHECK(p(0, 0) == 0.5);
  CHECK(p(1, 0) == -1.25);
  CHECK(p(2, 0) == 4.55);
  const auto s = magenc::parse_scan_csv("x_mm;y_mm;z_mm;Bx_mT;By_mT;Bz_mT\n0;0;4,55;-20,5;0;7\n", "s");
  CHECK(s.B_T(0, 0) == -20.5e-3);
  CHECK(s.p_mm(2, 0) == 4.55);
}

TEST_CASE("scan CSV: readings in other units than the header claims are refused", "[io][bad-input]") {
  using Catch::Contains;
  const std::string head_mT = "x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT\n", head_T = "x_mm,y_mm,z_mm,Bx_T,By_T,Bz_T\n";
  CHECK_THROWS_WITH(magenc::parse_scan_csv(head_mT + "0,0,4,0,0,0\n1,0,4,0,0,0\n", "s"),
                    Contains("s: every reading is zero: allowed a largest |B| above 0"));
  CHECK_THROWS_WITH(magenc::parse_scan_csv(head_mT + "0,0,4,0.02,0.001,0.05\n", "s"),
                    Contains("the largest reading is 0.05 mT") && Contains("readings in T under a mT header?"));
  CHECK_THROWS_WITH(magenc::parse_scan_csv(head_T + "0,0,4,-20,1,50\n1,0,4,1,1,1\n", "s"),
                    Contains("column Bz_T holds 50 T (row 1)") && Contains("readings in mT under a T header?"));
  CHECK_THROWS_WITH(magenc::parse_scan_csv(head_mT + "0,0,4,1,1e300,1\n", "s"), Contains("column By_mT holds 1e+300 mT"));
  // Realistic readings (largest 1.5-500 mT) in tesla under mT columns, and in mT under T columns, are refused.
  for (const double largest_mT : {1.5, 30.0, 500.0}) {
    CAPTURE(largest_mT);
    const std::string mT = std::to_string(largest_mT), T = std::to_string(largest_mT * 1e-3);
    CHECK_THROWS_WITH(magenc::parse_scan_csv(head_mT + "0,0,4,0,0," + T + "\n", "s"),
                      Contains("readings in T under a mT header?") && Contains("between 1 mT and 1 T"));
    CHECK_THROWS_WITH(magenc::parse_scan_csv(head_T + "0,0,4,0,0," + mT + "\n", "s"), Contains("readings in mT under a T header?"));
    CHECK(magenc::parse_scan_csv(head_mT + "0,0,4,0,0," + mT + "\n", "s").B_T(2, 0) == Approx(largest_mT * 1e-3));
  }
  // A weak field (0.2 mT) is read only with checks.largest_field_min_mT lowered.
  CHECK_THROWS_WITH(magenc::parse_scan_csv(head_mT + "0,0,4,0.2,0,0\n", "s"), Contains("lower checks.largest_field_min_mT"));
  magenc::FieldTableLimits weak;
  weak.largest_field_min_T = 1e-4;
  CHECK(magenc::parse_scan_csv(head_mT + "0,0,4,0.2,0,0\n", "s", weak).B_T(0, 0) == Approx(2e-4));
}
