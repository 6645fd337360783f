// field_at executable (apps/field_at.cpp) end to end: the table on stdout and with --out equals the
// library's field_at to the last bit (17 significant digits), grid: sources, and every kind of bad input
// -> exit 2, one line on stderr naming the input, no output file left.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fields/analytic_field.hpp"
#include "fields/field_at.hpp"
#include "fields/grid.hpp"

namespace fs = std::filesystem;

namespace {

struct RunResult {
  int exit_code;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Scratch {
  fs::path dir;
  Scratch() {
    static int counter = 0;
    dir = fs::temp_directory_path() / ("magenc_fa_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  fs::path file(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
  RunResult run(const std::string& args) const {
    const std::string cmd = std::string("cd '") + dir.string() + "' && '" MAGENC_BIN_DIR "/field_at' " + args +
                            " > stdout.txt 2> stderr.txt";
    const int status = std::system(cmd.c_str());
    RunResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "stdout.txt"), slurp(dir / "stderr.txt")};
    fs::remove(dir / "stdout.txt");
    fs::remove(dir / "stderr.txt");
    return r;
  }
  std::vector<std::string> entries() const {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
    std::sort(v.begin(), v.end());
    return v;
  }
};

// Rows of the answer table (header checked).
std::vector<std::vector<double>> parse_table(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  REQUIRE(line == "x_mm,y_mm,z_mm,Bx_T,By_T,Bz_T");
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) r.push_back(std::stod(c));
    REQUIRE(r.size() == 6);
    rows.push_back(r);
  }
  return rows;
}

const char* kPoints =
    "x_mm,y_mm,z_mm\n"
    "0,0,4.55\n"
    "0.3,-0.7,0.2\n"   // inside the magnet (R = 3, L = 5 below)
    "-4.1,2.2,-3.9\n"
    "1.25,1.25,2.6\n";

}  // namespace

TEST_CASE("field_at CLI: stdout and --out hold the library's B to the last bit", "[apps][cli][contract]") {
  Scratch s;
  s.file("pts.csv", kPoints);
  const std::string sets =
      "--set magnet.radius_mm=3 --set magnet.height_mm=5 --set magnet.magnetization_deg=40 "
      "--set magnet.magnetization_elevation_deg=-35 --set magnet.br_T=1.35";
  const RunResult r = s.run("--field analytic --points pts.csv " + sets);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto rows = parse_table(r.out);
  REQUIRE(rows.size() == 4);
  magenc::Magnet m;
  m.radius_mm = 3;
  m.height_mm = 5;
  m.magnetization_deg = 40;
  m.magnetization_elevation_deg = -35;
  m.br_T = 1.35;
  const magenc::AnalyticField field(m);
  for (const auto& row : rows) {
    const Eigen::Matrix3Xd B = magenc::field_at(field, Eigen::Vector3d(row[0], row[1], row[2]));
    CHECK(row[3] == B(0, 0));
    CHECK(row[4] == B(1, 0));
    CHECK(row[5] == B(2, 0));
  }
  CHECK(rows[1][3] > 0.3);  // inside: B includes mu0 M (Br cos(el) cos(beta) ~ 0.85 T) minus the demagnetizing field
  const RunResult w = s.run("--points pts.csv " + sets + " --out B.csv");
  REQUIRE(w.exit_code == 0);
  CHECK(w.out.empty());
  CHECK(slurp(s.dir / "B.csv") == r.out);
  CHECK(s.entries() == std::vector<std::string>{"B.csv", "pts.csv"});
}

TEST_CASE("field_at CLI: a grid source gives B inside its box and names the first point outside it",
          "[apps][cli][bad-input]") {
  Scratch s;
  // A 3-D grid holding a linear field B = (y, 2 z, x) T/mm, which every interpolation reproduces exactly.
  magenc::GridData g = magenc::GridData::from_range({-1, -1, 3}, {1, 1, 5}, {0.25, 0.25, 0.25});
  const Eigen::Matrix3Xd P = g.points_mm();
  Eigen::Matrix3Xd B(3, P.cols());
  for (Eigen::Index j = 0; j < P.cols(); ++j) B.col(j) = Eigen::Vector3d(P(1, j), 2 * P(2, j), P(0, j));
  g.set_B(B);
  magenc::write_grid_vti(s.dir / "box.vti", g);
  s.file("in.csv", "x_mm,y_mm,z_mm\n0.1,0.2,4.3\n-0.9,0.95,3.1\n");
  const RunResult r = s.run("--field grid:box.vti --interp linear --points in.csv");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto rows = parse_table(r.out);
  REQUIRE(rows.size() == 2);
  for (const auto& row : rows) {
    CHECK(row[3] == Approx(row[1]).margin(1e-12));
    CHECK(row[4] == Approx(2 * row[2]).margin(1e-12));
    CHECK(row[5] == Approx(row[0]).margin(1e-12));
  }
  s.file("out.csv", "x_mm,y_mm,z_mm\n0.1,0.2,4.3\n0.5,0.5,5.5\n3,0,4\n");
  const RunResult bad = s.run("--field grid:box.vti --points out.csv --out B.csv");
  CHECK(bad.exit_code == 2);
  CHECK(bad.out.empty());
  CHECK(bad.err.find("point 2 (x_mm = 0.5, y_mm = 0.5, z_mm = 5.5)") != std::string::npos);
  CHECK(std::count(bad.err.begin(), bad.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(s.dir / "B.csv"));
}

TEST_CASE("field_at CLI: bad input is one line, exit 2 and no output", "[apps][cli][bad-input]") {
  struct Case {
    const char* what;
    const char* points;  // file text (nullptr: no file)
    const char* args;
    const char* expect;  // part of the one-line message
  };
  const std::vector<Case> cases = {
      {"missing column", "x_mm,y_mm\n1,2\n", "", "missing column 'z_mm'"},
      {"unknown column", "x_mm,y_mm,z_mm,w\n1,2,3,4\n", "", "unknown column 'w'"},
      {"non-finite value", "x_mm,y_mm,z_mm\n1,2,3\n1,nan,3\n", "", "pts.csv line 3: column y_mm = 'nan' is not finite"},
      {"infinite value", "x_mm,y_mm,z_mm\n1,2,1e999\n", "", "column z_mm = '1e999' is not finite"},
      {"text value", "x_mm,y_mm,z_mm\n1,2,abc\n", "", "column z_mm = 'abc'"},
      {"short row", "x_mm,y_mm,z_mm\n1,2\n", "", "2 cells, the header has 3"},
      {"no rows", "x_mm,y_mm,z_mm\n", "", "has a header but no data rows"},
      {"empty file", "", "", "is empty: expected a header row"},
      {"point on the top face", "x_mm,y_mm,z_mm\n0,0,5\n0.5,0.5,2\n", "", "point 2 (x_mm = 0.5, y_mm = 0.5, z_mm = 2) lies on the magnet's surface"},
      {"point on the curved face", "x_mm,y_mm,z_mm\n2,0,1\n", "", "point 1 (x_mm = 2, y_mm = 0, z_mm = 1) lies on"},
      {"unknown key", "x_mm,y_mm,z_mm\n0,0,5\n", "--set magnet.colour=red", "magnet.colour"},
      {"bad magnet", "x_mm,y_mm,z_mm\n0,0,5\n", "--set magnet.radius_mm=-1", "magnet.radius_mm"},
      {"plane-only source", "x_mm,y_mm,z_mm\n0,0,5\n", "--field linear", "gives Bz on the sensing plane only"},
      {"unknown source", "x_mm,y_mm,z_mm\n0,0,5\n", "--field magic", "magic"},
      {"missing file", nullptr, "", "does not exist"},
  };
  for (const auto& c : cases) {
    Scratch s;
    if (c.points) s.file("pts.csv", c.points);
    const RunResult r = s.run(std::string("--points pts.csv --out B.csv ") + c.args);
    INFO(c.what << ": " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.out.empty());
    CHECK(r.err.find(c.expect) != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(s.dir / "B.csv"));
  }
}
