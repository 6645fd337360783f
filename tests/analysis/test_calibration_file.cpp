// Correction files (src/analysis/calibration_file.*): every method round-trips bit for bit through the CSV;
// the reader refuses bad files with one line naming the file and the problem; the JSON carries the same numbers.
#include <catch2/catch.hpp>

#include "analysis/calibration_file.hpp"
#include "core/errors.hpp"
#include "fields/analytic_field.hpp"
#include "support/probe_setup.hpp"

using namespace magenc;

TEST_CASE("correction files round-trip for every method", "[analysis][contract]") {
  const AnalyticField f{Magnet{}};
  ProbeSetup s = test::probe_setup("two", 720, 2.4);
  s.chain.offset_cos_mT = 0.7;
  s.chain.phase_error_deg = 1.1;
  const AngleErrorResult at = angle_error(f, s, Mount{0.1, 0, 0.1, 0, 0});
  for (const char* m : {"none", "harmonics:8", "harmonics:1", "lut:32", "lut:7", "ogp"}) {
    const Correction c = calibrate(CalibrationMethod::parse(m), at, SensorPrinciple::Bz);
    const std::string csv = correction_csv(c);
    const Correction back = parse_correction_csv(csv, "mem.csv");
    CAPTURE(m, csv.substr(0, 200));
    CHECK(back.method.name() == c.method.name());
    CHECK(back.turns == c.turns);
    CHECK(back.harmonics_deg == c.harmonics_deg);
    CHECK(back.lut_deg == c.lut_deg);
    CHECK(back.ellipse.offset_cos == c.ellipse.offset_cos);
    CHECK(back.ellipse.offset_sin == c.ellipse.offset_sin);
    CHECK(back.ellipse.gain_ratio == c.ellipse.gain_ratio);
    CHECK(back.ellipse.phase_deg == c.ellipse.phase_deg);
    CHECK(correction_csv(back) == csv);
    if (!c.method.none()) CHECK((residual_deg(back, at) - residual_deg(c, at)).cwiseAbs().maxCoeff() == 0.0);
    const std::string json = correction_json(c);
    CHECK(json.find("\"method\": \"" + c.method.name() + "\"") != std::string::npos);
  }
  // A spreadsheet's form of the same file (';' and decimal commas, CRLF) reads the same.
  const Correction c = calibrate(CalibrationMethod::parse("lut:4"), at, SensorPrinciple::Bz);
  std::string semi = correction_csv(c);
  for (auto& ch : semi)
    if (ch == ',') ch = ';';
  std::string crlf;
  for (char ch : semi) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  CHECK(parse_correction_csv(crlf, "excel.csv").lut_deg == c.lut_deg);
}

TEST_CASE("correction files: bad input is one line naming the file", "[analysis][bad-input]") {
  const std::string head = "quantity,index,value\n";
  const std::vector<std::string> bad = {
      "",
      "a,b,c\nmethod,0,lut:4\n",
      head,                                                         // no method
      head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,1,1\nlut_deg,2,1\n",  // one value missing
      head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,1,1\nlut_deg,2,1\nlut_deg,4,1\n",  // wrong index
      head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,0,1\nlut_deg,1,1\nlut_deg,2,1\nlut_deg,3,1\n",  // twice
      head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,1,nan\nlut_deg,2,1\nlut_deg,3,1\n",
      head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,1,1e999\nlut_deg,2,1\nlut_deg,3,1\n",
      head + "method,0,lut:3\n",
      head + "method,0,spline\n",
      head + "method,0,harmonics:1\na_deg,0,1\na_deg,1,1\n",     // b_1 missing
      head + "method,0,harmonics:1\na_deg,0,1\na_deg,1,1\nb_deg,1,1\nlut_deg,0,1\n",  // another method's rows
      head + "method,0,ogp\noffset_cos,0,0\noffset_sin,0,0\ngain_ratio,0,0\nphase_deg,0,0\n",
      head + "method,0,ogp\noffset_cos,0,0\noffset_sin,0,0\ngain_ratio,0,1\nphase_deg,0,90\n",
      head + "method,0,ogp\nturns,0,3\n",
      head + "method,0,ogp\nfoo,0,1\n",
      head + "method,0,lut:4\nlut_deg,-1,1\n",
      head + "method,0,lut:4\nlut_deg,1.5,1\n",
      head + "method,0,lut:4\nlut_deg,1\n",
      head + "method,0,lut:4\nmethod,0,lut:4\n",
      head + "method,0,\"lut:4\n",
      head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,1,720\nlut_deg,2,1\nlut_deg,3,1\n",   // beyond a turn
      head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,1,1e300\nlut_deg,2,1\nlut_deg,3,1\n",  // absurd
      head + "method,0,harmonics:1\na_deg,0,1\na_deg,1,-361\nb_deg,1,1\n",
      head + "method,0,ogp\noffset_cos,0,1e300\noffset_sin,0,0\ngain_ratio,0,1\nphase_deg,0,0\n",
  };
  for (const auto& text : bad) {
    CAPTURE(text);
    try {
      (void)parse_correction_csv(text, "c.csv");
      FAIL("accepted");
    } catch (const InputError& e) {
      const std::string msg = e.what();
      CAPTURE(msg);
      CHECK(msg.find("c.csv") != std::string::npos);
      CHECK(msg.find('\n') == std::string::npos);
      CHECK(msg.find("allowed") != std::string::npos);
    }
  }
  CHECK_THROWS_AS(read_correction_csv("/nonexistent/correction.csv"), InputError);
}

TEST_CASE("correction files: angles within a turn, trailing separators of spreadsheets", "[analysis][bad-input]") {
  const std::string head = "quantity,index,value\n";
  CHECK_THROWS_WITH(parse_correction_csv(head + "method,0,lut:4\nlut_deg,0,1\nlut_deg,1,720\n", "c.csv"),
                    Catch::Contains("correction c.csv line 4: lut_deg = 720: allowed an angle in [-360, 360] deg"));
  const Correction c = parse_correction_csv(
      "quantity;index;value;\nmethod;0;lut:4;\nlut_deg;0;360;\nlut_deg;1;-360;;\nlut_deg;2;0,5;\nlut_deg;3;1;\n", "c.csv");
  CHECK(c.lut_deg[0] == 360);
  CHECK(c.lut_deg[2] == 0.5);
}
