// error_spectrum executable (apps/error_spectrum.cpp) end to end:
// output table, --cases, flag/config precedence, and every kind of bad input
// -> non-zero exit, one-line stderr naming the input, no output file left.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

// A scratch directory per test case, removed afterwards.
struct Scratch {
  fs::path dir;
  Scratch() {
    static int counter = 0;  // test-local sequence number
    dir = fs::temp_directory_path() /
          ("magenc_es_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  fs::path file(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
  RunResult run(const std::string& args) const {
    const std::string cmd = std::string("cd '") + dir.string() + "' && '" MAGENC_BIN_DIR "/error_spectrum' " + args +
                            " > stdout.txt 2> stderr.txt";
    const int status = std::system(cmd.c_str());
    RunResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "stdout.txt"), slurp(dir / "stderr.txt")};
    fs::remove(dir / "stdout.txt");
    fs::remove(dir / "stderr.txt");
    return r;
  }
  // Files other than inputs written by the test (no outputs, no temporaries).
  int stray_files(const std::vector<std::string>& inputs) const {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
      bool input = false;
      for (const auto& i : inputs) input = input || e.path().filename() == i;
      n += input ? 0 : 1;
    }
    return n;
  }
};

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace

TEST_CASE("error_spectrum writes the spectra table", "[apps][contract][cli]") {
  Scratch s;
  SECTION("one case to --out") {
    const RunResult r = s.run("--field linear --array two --r0 2.4 --sx 0.1 --out spectra.csv");
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string csv = slurp(s.dir / "spectra.csv");
    CHECK(count_lines(csv) == 2);
    CHECK(csv.rfind("field,array,r0_mm,sx_mm,sy_mm,dx_mm,dy_mm,dz_mm,a0_deg,a1_deg,", 0) == 0);
    CHECK(csv.find("\nlinear,two,2.4,0.1,0,0,0,0,1.169139") != std::string::npos);
    CHECK(s.stray_files({"spectra.csv"}) == 0);
  }
  SECTION("stdout without --out; analytic field; ring array") {
    const RunResult r = s.run("--field analytic --array ring:8 --r0 2.4 --dx 0.05 --steps 360");
    REQUIRE(r.exit_code == 0);
    CHECK(count_lines(r.out) == 2);
    CHECK(r.out.find("\nanalytic,ring:8,2.4,0,0,0.05,0,0,") != std::string::npos);
  }
  SECTION("--cases: one row per case") {
    s.file("cases.csv", "sx_mm,dx_mm\n0.1,0\n0,0.1\n0.05,0.05\n");
    const RunResult r = s.run("--field linear --cases cases.csv --out out.csv");
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string csv = slurp(s.dir / "out.csv");
    CHECK(count_lines(csv) == 4);
    CHECK(csv.find("\nlinear,two,2.4,0,0,0.1,0,0,") != std::string::npos);
  }
  SECTION("flags override --config and --set") {
    s.file("c.toml", "[sensor]\nr0_mm = 3.0\narray = \"diff4\"\n");
    RunResult r = s.run("--config c.toml --field linear");
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("\nlinear,diff4,3,") != std::string::npos);
    r = s.run("--config c.toml --set sensor.r0_mm=2.0 --field linear --r0 2.4 --array two");
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("\nlinear,two,2.4,") != std::string::npos);
  }
}

TEST_CASE("error_spectrum rejects bad input cleanly", "[apps][bad-input][cli]") {
  struct Bad {
    std::string args;
    std::string names;  // the input the message must name
  };
  const std::string out = " --out out.csv";
  const std::vector<Bad> cases = {
      {"--field linear --r0 -1", "--r0"},
      {"--field linear --r0 0", "--r0"},
      {"--field linear --r0 nan", "--r0"},
      {"--field linear --sx nan", "--sx"},
      {"--field analytic --set magnet.radius_mm=-2", "magnet.radius_mm"},
      {"--field analytic --set magnet.br_T=nan", "magnet.br_T"},
      {"--field linear --steps 8", "--steps"},
      {"--field linear --steps 20.5", "--steps"},
      {"--field linear --array three", "--array"},
      {"--field linear --array ring:2", "--array"},
      {"--field magic", "--field"},
      {"--field grid:plane.vti", "--field"},
      {"--field linear --interp spline", "--interp"},
      {"--field linear --config bad.toml", "bad.toml"},
      {"--field linear --config unknown.toml", "sensor.radius"},
      {"--field linear --config missing.toml", "missing.toml"},
      {"--field linear --cases badcases.csv", "badcases.csv"},
      {"--field linear --cases nancases.csv", "nancases.csv"},
      {"--field linear --cases emptycases.csv", "emptycases.csv"},
      {"--field linear --cases cases.csv --sx 0.1", "--cases"},
      {"--field linear --sx 2.0 --dx 0.5", "r0"},
      {"--field analytic --dz -3 --dx 0.5", "magnet"},
      {"--field linear --bogus 1", "bogus"},
      {"--field linear --cases cases.csv --paths p.vtp", "--paths"},
      {"--field analytic --dz -3 --dx 0.5 --paths p.vtp", "magnet"},  // no .vtp either
  };
  for (const auto& b : cases) {
    Scratch s;
    s.file("bad.toml", "[sensor\nr0_mm = 2\n");
    s.file("unknown.toml", "[sensor]\nradius = 2\n");
    s.file("badcases.csv", "sx_mm,dx_mm\n0.1,abc\n");
    s.file("nancases.csv", "sx_mm\nNaN\n");
    s.file("emptycases.csv", "sx_mm,dx_mm\n");
    s.file("cases.csv", "sx_mm\n0.1\n");
    const RunResult r = s.run(b.args + out);
    CAPTURE(b.args, r.err, r.exit_code);
    CHECK(r.exit_code != 0);
    CHECK(count_lines(r.err) == 1);  // exactly one line
    CHECK(r.err.find(b.names) != std::string::npos);
    CHECK(r.out.empty());
    CHECK_FALSE(fs::exists(s.dir / "out.csv"));
    CHECK(s.stray_files({"bad.toml", "unknown.toml", "badcases.csv", "nancases.csv", "emptycases.csv",
                         "cases.csv"}) == 0);
  }
}

TEST_CASE("error_spectrum: sensing principles and field windows", "[apps][contract][cli]") {
  Scratch s;
  // In-plane spot, sx 0.1 mm (docs/physics.md: c2 0.0340 deg); the field-window columns after the standard ones.
  RunResult r = s.run("--field analytic --principle inplane --sx 0.1 --steps 720 --out a.csv");
  CAPTURE(r.err);
  REQUIRE(r.exit_code == 0);
  std::string csv = slurp(s.dir / "a.csv");
  CHECK(csv.rfind("field,array,r0_mm,sx_mm,sy_mm,dx_mm,dy_mm,dz_mm,a0_deg,", 0) == 0);
  CHECK(csv.find(",pp_deg,principle,field_min_mT,field_max_mT,in_window\n") != std::string::npos);
  CHECK(csv.find("\nanalytic,point,0,0.1,") != std::string::npos);  // r0 is not used by the point array
  CHECK(csv.find(",inplane,50.7") != std::string::npos);  // |b| over the turn: 50.776 .. 50.836 mT at sx 0.1 mm
  // A window the field leaves: in_window 0, still exit 0 (a mount outside the window is reported, not refused).
  r = s.run("--field analytic --principle xmr --set sensor.field_min_mT=60 --steps 64 --out b.csv");
  REQUIRE(r.exit_code == 0);
  csv = slurp(s.dir / "b.csv");
  CHECK(csv.substr(csv.size() - 3) == ",0\n");
  // A chip definition as a config file (docs/interfaces.md keys; inf is TOML's infinity): a window of 30 .. 50 mT
  // that the spot's 50.84 .. 50.86 mT leaves on the high side; with inf it is inside.
  s.file("chip.toml", "[sensor]\nprinciple = \"xmr\"\narray = \"point\"\nfield_min_mT = 30.0\nfield_max_mT = 50.0\n"
                      "offset_cos_rel = 0.002\n");
  r = s.run("--config chip.toml --sx 0.05 --steps 64");
  CAPTURE(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find(",xmr,50.8") != std::string::npos);
  CHECK(r.out.substr(r.out.size() - 3) == ",0\n");
  s.file("chip2.toml", "[sensor]\nprinciple = \"amr\"\nfield_min_mT = 31.4\nfield_max_mT = inf\n");
  r = s.run("--config chip2.toml --steps 64");
  CAPTURE(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.substr(r.out.size() - 3) == ",1\n");
  // bz, default: the columns are there too; in_window 1 without a window.
  r = s.run("--field linear --sx 0.1");
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find(",bz,") != std::string::npos);
  CHECK(r.out.substr(r.out.size() - 3) == ",1\n");
}

TEST_CASE("error_spectrum at a speed: the rpm column and docs/physics.md's delay", "[apps][contract][cli]") {
  Scratch s;
  RunResult r = s.run("--field analytic --array two --r0 2.4 --set speed.rpm=6000 --set sensor.delay_us=100");
  REQUIRE(r.exit_code == 0);
  const auto header = r.out.substr(0, r.out.find('\n'));
  CHECK(header.substr(header.size() - 4) == ",rpm");
  CHECK(r.out.find(",-3.6,") != std::string::npos);  // a0 = -6 n tau exactly
  CHECK(r.out.substr(r.out.size() - 6) == ",6000\n");
  r = s.run("--field analytic --array two --r0 2.4 --set sensor.delay_us=100");  // at rest: no rpm column
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.substr(0, r.out.find('\n')).find("rpm") == std::string::npos);
}

TEST_CASE("error_spectrum: sensing-principle bad input, one line, exit 2, no output", "[apps][bad-input][cli]") {
  struct Bad {
    std::string args;
    std::string names;
  };
  const std::vector<Bad> cases = {
      {"--principle inplane --array two", "--array"},                                // array/principle mismatch
      {"--principle amr --array diff4", "--array"},
      {"--array point", "--array"},                                                   // point on bz
      {"--principle xmr --r0 2.0", "sensor.r0_mm"},                                   // r0 does not apply
      {"--set sensor.offset_cos_rel=0.01", "sensor.offset_cos_rel"},                  // relative offset on bz
      {"--principle inplane --set sensor.offset_sin_rel=0.01", "sensor.offset_sin_rel"},
      {"--principle xmr --set sensor.offset_cos_mT=0.5", "sensor.offset_cos_mT"},     // mT offset on xmr
      {"--set sensor.field_min_mT=80 --set sensor.field_max_mT=40", "sensor.field_min_mT"},  // min > max
      {"--set sensor.plate_mm=-0.1", "sensor.plate_mm"},                              // negative plate
      {"--set sensor.plate_points=0", "sensor.plate_points"},
      {"--principle hall", "--principle"},
      {"--field linear --principle inplane", "linear"},                               // Bz-only source
      {"--principle inplane --paths p.vtp", "--paths"},
      {"--set sensor.prediction=ideal", "speed.rpm"},                                 // prediction at rest
      {"--set speed.rpm=6000 --set sensor.sample_hz=150", "sensor.sample_hz"},      // < 2 x 100 Hz
      {"--set speed.rpm=6000 --set sensor.delay_us=-1", "sensor.delay_us"},
      {"--set sensor.filter_hz=-5", "sensor.filter_hz"},
  };
  for (const auto& b : cases) {
    Scratch s;
    const RunResult r = s.run(b.args + " --steps 64 --out out.csv");
    CAPTURE(b.args, r.err, r.exit_code);
    CHECK(r.exit_code == 2);
    CHECK(count_lines(r.err) == 1);
    CHECK(r.err.find(b.names) != std::string::npos);
    CHECK(r.out.empty());
    CHECK(s.stray_files({}) == 0);
  }
}
