// The bad-input matrix (issue 13): every executable of build/bin (benchmarks aside) against every
// class of bad input. Each case must give: exit code != 0, exactly one line on stderr, naming the
// input (the key, file or flag), and no output file (nothing new in the scratch directory but the
// inputs the test wrote). The configuration keys are not hand-listed: each executable's key table is
// read from its --help (Config::describe(), one line per declared key with its allowed range) and
// every key gets the bad values of its type.
#include <catch2/catch.hpp>

#include <cmath>
#include <set>
#include <regex>
#include <tuple>

#include "reliability/run_process.hpp"

using namespace magenc_test;

namespace {

struct KeyInfo {
  std::string key, allowed;
  enum class Kind { Real, Int, Choice, String, Bool, NumberList, StringList } kind;
  int min_elements = 0;  // array keys: fewest elements allowed
  double min = -1e300, max = 1e300;
  bool min_exclusive = false, max_exclusive = false;
};

// Keys of an executable, from the "Configuration keys" block of its --help.
std::vector<KeyInfo> key_table(const fs::path& exe) {
  ScratchDir tmp("magenc_keys");
  const ProcResult r = run(exe, {"--help"}, tmp.dir);
  std::vector<KeyInfo> keys;
  const std::regex line_re(R"(^  ([a-z0-9_]+\.[a-z0-9_.]+) +default (.*?), allowed (.*?)\. )");
  const std::regex range_re(R"(^(integer in )?([\[(])([^,]+), ([^\])]+)([\])]))");
  // Array keys (TOML arrays or comma-separated text): "an array of N or more numbers, each ...".
  const std::regex array_re(R"(^an array of ([0-9]+) or more (numbers|integers|non-empty strings|strings))");
  std::stringstream ss(r.out);
  for (std::string line; std::getline(ss, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, line_re)) continue;
    KeyInfo k;
    k.key = m[1];
    k.allowed = m[3];
    std::smatch rm;
    if (std::regex_search(k.allowed, rm, range_re)) {
      k.kind = rm[1].matched ? KeyInfo::Kind::Int : KeyInfo::Kind::Real;
      k.min = std::stod(rm[3]);
      k.max = std::stod(rm[4]);
      k.min_exclusive = rm[2] == "(";
      k.max_exclusive = rm[5] == ")";
    } else if (std::smatch am; std::regex_search(k.allowed, am, array_re)) {
      k.kind = am[2] == "strings" || am[2] == "non-empty strings" ? KeyInfo::Kind::StringList : KeyInfo::Kind::NumberList;
      k.min_elements = std::stoi(am[1]);
    } else if (k.allowed == "true or false") {
      k.kind = KeyInfo::Kind::Bool;
    } else if (k.allowed.rfind("one of ", 0) == 0) {
      k.kind = KeyInfo::Kind::Choice;
    } else {
      k.kind = KeyInfo::Kind::String;
    }
    keys.push_back(k);
  }
  return keys;
}

std::string text(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

// The bad values of a key's type: non-finite, out of range on either side, not a number, too big
// for the type. Free strings (paths, lists) are checked where they are used, not here.
std::vector<std::string> bad_values(const KeyInfo& k) {
  std::vector<std::string> v;
  switch (k.kind) {
    case KeyInfo::Kind::Real:
      v = {"nan", "inf", "-inf", "1e999", "abc", ""};
      if (k.min > -1e300) v.push_back(text(k.min_exclusive ? k.min : k.min - std::max(1.0, std::abs(k.min))));
      if (k.max < 1e300) v.push_back(text(k.max_exclusive ? k.max : k.max + std::max(1.0, std::abs(k.max))));
      break;
    case KeyInfo::Kind::Int:
      v = {"nan", "1.5", "1e300", "99999999999999999999999", "abc"};
      v.push_back(text(k.min - 1));
      v.push_back(text(k.max + 1));
      break;
    case KeyInfo::Kind::Bool:
      v = {"maybe", "2"};
      break;
    case KeyInfo::Kind::Choice:
      v = {"no-such-choice"};
      break;
    case KeyInfo::Kind::String:
      break;
    // Array keys: a non-finite element, an element of the wrong type, a nested array, an empty element or
    // an empty array where elements are required; TOML array syntax and comma-separated text.
    case KeyInfo::Kind::NumberList:
      v = {"[nan]", "[inf]", "1,nan", "[\"abc\"]", "1,abc", "[[1]]"};
      if (k.min_elements > 0) v.push_back("[]");
      break;
    case KeyInfo::Kind::StringList:
      v = {"[1]", "[true]", "[[\"a\"]]", "[\"\"]"};
      if (k.min_elements > 0) v.push_back("[]");
      break;
  }
  return v;
}

// TOML spellings of bad values for numeric keys (TOML has nan/inf literals; 1e300 is a float where
// an integer is expected; a string where a number is expected).
std::vector<std::string> bad_toml_values(const KeyInfo& k) {
  if (k.kind == KeyInfo::Kind::Real) {
    std::vector<std::string> v{"nan", "-inf", "\"1.0\""};
    if (k.max < 1e300) v.push_back("1e300");
    if (k.min > -1e300) v.push_back("-1e300");
    return v;
  }
  if (k.kind == KeyInfo::Kind::Int) return {"1e300", "-1e300", "nan", "9223372036854775807", "\"7\""};
  if (k.kind == KeyInfo::Kind::Bool) return {"1", "\"true\""};
  if (k.kind == KeyInfo::Kind::Choice) return {"\"no-such-choice\"", "3"};
  if (k.kind == KeyInfo::Kind::NumberList) {
    std::vector<std::string> v{"[nan]", "[1.0, -inf]", "[\"1.0\"]", "[[1.0]]", "1.0", "\"1,nan\""};
    if (k.min_elements > 0) v.push_back("[]");
    return v;
  }
  if (k.kind == KeyInfo::Kind::StringList) {
    std::vector<std::string> v{"[1]", "[\"a\", 2.5]", "[{ x = 1 }]", "[\"\"]", "true"};
    if (k.min_elements > 0) v.push_back("[]");
    return v;
  }
  return {};
}

// One bad-input case: run, then check the contract. Returns true when it holds.
struct Matrix {
  int cases = 0, failures = 0;
  std::set<std::string> classes;
  void check(const std::string& cls, const fs::path& exe, const std::vector<std::string>& args, const ScratchDir& s,
             const std::vector<std::string>& inputs, const std::vector<std::string>& must_name) {
    classes.insert(cls);
    ++cases;
    const ProcResult r = run(exe, args, s.dir, {}, s.dir.parent_path());
    std::string cmd = exe.filename().string();
    for (const auto& a : args) cmd += " '" + a + "'";
    const auto stray = s.entries_except(inputs);
    bool named = false;
    for (const auto& n : must_name) named = named || r.err.find(n) != std::string::npos;
    const bool ok = r.exit_code > 0 && count_lines(r.err) == 1 && named && stray.empty();
    if (!ok) {
      ++failures;
      std::string strays;
      for (const auto& e : stray) strays += e + " ";
      FAIL_CHECK("[" << cls << "] " << cmd << "\n  exit " << r.exit_code << ", " << count_lines(r.err)
                     << " stderr lines, stray files: " << strays << "\n  stderr: " << r.err);
    }
  }
};

const fs::path kBin = MAGENC_BIN_DIR;

}  // namespace

TEST_CASE("bad-input matrix: every executable x every declared key x its bad values (--set and TOML)",
          "[apps][bad-input][cli][slow]") {
  const auto exes = executables(kBin);
  REQUIRE(exes.size() >= 10);
  Matrix m;
  int keys_total = 0, array_keys = 0;
  for (const auto& exe : exes) {
    const auto keys = key_table(exe);
    for (const auto& k : keys)
      array_keys += k.kind == KeyInfo::Kind::NumberList || k.kind == KeyInfo::Kind::StringList;
    INFO(exe.filename().string());
    REQUIRE(keys.size() >= 10);  // at least the common [magnet]/[sensor]/[mount] keys
    keys_total += int(keys.size());
    ScratchDir s("magenc_matrix");
    for (const auto& k : keys) {
      for (const auto& v : bad_values(k))
        m.check("--set " + std::string(k.kind == KeyInfo::Kind::Real                 ? "real"
                                       : k.kind == KeyInfo::Kind::NumberList ||
                                               k.kind == KeyInfo::Kind::StringList ? "array"
                                                                                   : "other") + " key", exe,
                {"--set", k.key + "=" + v, "--out", "out"}, s, {"bad.toml"}, {k.key});
      const auto dot = k.key.rfind('.');
      for (const auto& v : bad_toml_values(k)) {
        s.write("bad.toml", "[" + k.key.substr(0, dot) + "]\n" + k.key.substr(dot + 1) + " = " + v + "\n");
        m.check("TOML value", exe, {"--config", "bad.toml", "--out", "out"}, s, {"bad.toml"}, {k.key});
      }
    }
  }
  WARN("bad-input matrix (config keys): " << exes.size() << " executables, " << keys_total << " keys, " << m.cases
                                           << " cases, " << m.failures << " failures, " << array_keys
                                           << " array keys");
  CHECK(array_keys > 0);  // the studies' list keys are arrays (study.arrays, sweep.coefs, ...)
  CHECK(m.failures == 0);
}

TEST_CASE("bad-input matrix: every executable x unusable files and output paths", "[apps][bad-input][cli]") {
  const auto exes = executables(kBin);
  REQUIRE(exes.size() >= 10);
  Matrix m;
  for (const auto& exe : exes) {
    INFO(exe.filename().string());
    ScratchDir s("magenc_matrix_files");
    // Configuration files: missing, a directory, truncated, binary garbage, deeply nested, too big.
    m.check("config missing", exe, {"--config", "missing.toml", "--out", "out"}, s, {}, {"missing.toml"});
    fs::create_directories(s.dir / "cfgdir.toml");
    m.check("config is a directory", exe, {"--config", "cfgdir.toml", "--out", "out"}, s, {"cfgdir.toml"},
            {"cfgdir.toml"});
    fs::remove(s.dir / "cfgdir.toml");
    s.write("trunc.toml", "[magnet]\nradius_mm = 2.0\n[sens");
    m.check("config truncated", exe, {"--config", "trunc.toml", "--out", "out"}, s, {"trunc.toml"}, {"trunc.toml"});
    std::string garbage;
    for (int i = 0; i < 4096; ++i) garbage += char((i * 7919 + 13) % 256);
    s.write("garbage.toml", garbage);
    m.check("config corrupted", exe, {"--config", "garbage.toml", "--out", "out"}, s, {"garbage.toml", "trunc.toml"},
            {"garbage.toml"});
    std::string deep = "[a";
    for (int i = 0; i < 50000; ++i) deep += ".a";
    s.write("deep.toml", deep + "]\n");
    m.check("config nested 50,000 deep", exe, {"--config", "deep.toml", "--out", "out"}, s,
            {"deep.toml", "garbage.toml", "trunc.toml"}, {"deep.toml"});
    // Unknown key, malformed --set, unknown flag.
    m.check("unknown key", exe, {"--set", "magnet.no_such_key=1", "--out", "out"}, s,
            {"deep.toml", "garbage.toml", "trunc.toml"}, {"magnet.no_such_key"});
    m.check("malformed --set", exe, {"--set", "magnet.radius_mm", "--out", "out"}, s,
            {"deep.toml", "garbage.toml", "trunc.toml"}, {"magnet.radius_mm"});
    m.check("unknown flag", exe, {"--no-such-flag", "--out", "out"}, s, {"deep.toml", "garbage.toml", "trunc.toml"},
            {"--no-such-flag"});
  }
  WARN("bad-input matrix (files, flags): " << m.cases << " cases, " << m.failures << " failures");
  CHECK(m.failures == 0);
}

TEST_CASE("bad-input matrix: every executable x an output path that is unusable", "[apps][bad-input][cli]") {
  const auto exes = executables(kBin);
  Matrix m;
  for (const auto& exe : exes) {
    INFO(exe.filename().string());
    ScratchDir s("magenc_matrix_out");
    s.write("afile", "not a directory\n");
    fs::create_directories(s.dir / "adir");
    const bool file_output = exe.filename() == "error_spectrum";  // --out FILE.csv; all others --out DIR
    std::vector<std::string> base;
    if (file_output) base = {"--field", "analytic", "--array", "two", "--r0", "2.4", "--steps", "256"};
    auto with = [&](const std::string& out) {
      auto a = base;
      a.insert(a.end(), {"--out", out});
      return a;
    };
    if (file_output) m.check("--out is a directory", exe, with("adir"), s, {"afile", "adir"}, {"adir"});
    else m.check("--out is a file", exe, with("afile"), s, {"afile", "adir"}, {"afile"});
    m.check("--out not writable (below a file)", exe, with("afile/sub"), s, {"afile", "adir"}, {"afile/sub"});
    m.check("--out not writable (/proc)", exe, with("/proc/magenc_no_such_dir/out"), s, {"afile", "adir"},
            {"/proc/magenc_no_such_dir/out"});
    CHECK(slurp(s.dir / "afile") == "not a directory\n");
  }
  WARN("bad-input matrix (output paths): " << m.cases << " cases, " << m.failures << " failures");
  CHECK(m.failures == 0);
}

namespace {
// A small .vti (ascii) of Bz on [-1, 1]^2 at z = 4.55 mm, or a variant of it.
std::string vti(const std::string& whole = "0 2 0 2 0 0", const std::string& piece = "0 2 0 2 0 0",
                bool closed = true) {
  std::string t = "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                  "  <ImageData WholeExtent=\"" + whole + "\" Origin=\"-1 -1 4.55\" Spacing=\"1 1 1\">\n"
                  "    <Piece Extent=\"" + piece + "\">\n      <PointData>\n"
                  "        <DataArray type=\"Float64\" Name=\"Bz\" format=\"ascii\">\n"
                  "          0.1 0.2 0.1 0.2 0.3 0.2 0.1 0.2 0.1\n        </DataArray>\n      </PointData>\n    </Piece>\n";
  if (closed) t += "  </ImageData>\n</VTKFile>\n";
  return t;
}
}  // namespace

TEST_CASE("bad-input matrix: grid, FE and cases files, geometry, absurd sizes", "[apps][bad-input][cli]") {
  Matrix m;
  const fs::path es = kBin / "error_spectrum", sf = kBin / "solve_field";
  ScratchDir s("magenc_matrix_inputs");
  // A real coarse solve to corrupt: solve_field's own outputs, written zlib-compressed (output.compress) so
  // that corrupted bytes are detectable (the default raw binary data has no checksum: a flipped byte there is
  // just another field value), with mesh.vtu (output.mesh_vtu) for the fem:DIR cases.
  {
    const ProcResult r = run(sf, {"--config", std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml", "--set",
                                  "output.compress=true", "--set", "output.mesh_vtu=true", "--out", "field"},
                             s.dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  const std::string plane = slurp(s.dir / "field/plane.vti"), json = slurp(s.dir / "field/solve.json"),
                    mesh = slurp(s.dir / "field/mesh.vtu");
  std::vector<std::string> inputs = {"field"};
  auto add = [&](const std::string& name, const std::string& text) {
    s.write(name, text);
    inputs.push_back(name);
    return name;
  };
  auto grid_case = [&](const std::string& cls, const std::string& file) {
    m.check(cls, es, {"--field", "grid:" + file, "--array", "two", "--r0", "0.5", "--steps", "256", "--out", "o.csv"}, s,
            inputs, {file});
  };
  // .vti: truncated at several places, corrupted bytes, empty, a directory, absurd extent, piece smaller
  // than the whole extent, closing tags missing, no B/Bz, a grid too small for the probe circle.
  for (const double frac : {0.1, 0.5, 0.9, 0.999})
    grid_case("vti truncated", add("trunc" + std::to_string(int(frac * 1000)) + ".vti",
                                   plane.substr(0, std::size_t(frac * double(plane.size())))));
  {
    std::string bad = plane;
    for (std::size_t i = bad.size() / 2; i < bad.size() / 2 + 64 && i < bad.size(); ++i) bad[i] = char(~bad[i]);
    grid_case("vti corrupted (compressed data)", add("corrupt.vti", bad));
  }
  grid_case("vti empty", add("empty.vti", ""));
  // fuzz_vti's finding: a mangled header_type made VTK read a block header claiming 5.4 GB (malloc).
  grid_case("vti block header claims gigabytes",
            add("fuzz_oom.vti", slurp(std::string(MAGENC_SOURCE_DIR) +
                                      "/tests/fuzz/regressions/vti_block_header_claims_5GB.vti")));
  fs::create_directories(s.dir / "dir.vti");
  inputs.push_back("dir.vti");
  grid_case("vti is a directory", "dir.vti");
  grid_case("vti absurd extent", add("huge.vti", vti("0 1999999999 0 1999999999 0 0", "0 1999999999 0 1999999999 0 0")));
  grid_case("vti piece smaller than whole extent", add("piece.vti", vti("0 4 0 4 0 0", "0 2 0 2 0 0")));
  grid_case("vti closing tags missing", add("open.vti", vti("0 2 0 2 0 0", "0 2 0 2 0 0", false)));
  {
    std::string no_bz = vti();
    no_bz.replace(no_bz.find("Name=\"Bz\""), 9, "Name=\"Hx\"");
    grid_case("vti without B or Bz", add("nobz.vti", no_bz));
  }
  m.check("grid too small for the probe path", es,
          {"--field", "grid:" + add("small.vti", vti()), "--array", "two", "--r0", "2.4", "--steps", "256", "--out",
           "o.csv"},
          s, inputs, {"small.vti"});
  // fem:DIR with a truncated mesh.vtu / corrupted solve.json.
  for (const auto& [cls, file, text] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"mesh.vtu truncated", "mesh.vtu", mesh.substr(0, mesh.size() / 2)},
           {"solve.json corrupted", "solve.json", json.substr(0, json.size() / 3)}}) {
    fs::create_directories(s.dir / "badfem");
    fs::copy(s.dir / "field", s.dir / "badfem", fs::copy_options::overwrite_existing);
    std::ofstream(s.dir / "badfem" / file, std::ios::binary | std::ios::trunc) << text;
    inputs.push_back("badfem");
    if (file == "mesh.vtu")  // fem:DIR reads mesh.vtu only
      m.check("fem:DIR " + cls, es, {"--field", "fem:badfem", "--array", "two", "--r0", "2.4", "--steps", "256",
                                     "--out", "o.csv"},
              s, inputs, {"badfem"});
    m.check("study fem_field.dir " + cls, kBin / "real_field",
            {"--set", "fem_field.dir=badfem", "--set", "sensor.steps=256", "--out", "study"}, s, inputs, {"badfem"});
    fs::remove_all(s.dir / "badfem");
  }
  // --cases: truncated, binary garbage, a non-finite value, a directory.
  auto cases_case = [&](const std::string& cls, const std::string& file) {
    m.check(cls, es, {"--field", "analytic", "--array", "two", "--r0", "2.4", "--steps", "256", "--cases", file, "--out",
                      "o.csv"},
            s, inputs, {file});
  };
  cases_case("cases truncated", add("trunc.csv", "sx_mm,dy_mm\n0.1,0.0\n0.2,"));
  cases_case("cases corrupted", add("garbage.csv", std::string("\x00\xff\x13sx_mm\x00,\x80\n1,2\n", 17)));
  cases_case("cases non-finite", add("nan.csv", "sx_mm\nnan\n"));
  fs::create_directories(s.dir / "dir.csv");
  inputs.push_back("dir.csv");
  cases_case("cases is a directory", "dir.csv");
  // Geometry: a probe path inside the magnet (plane 3 mm lower, r0 = 1 mm < R = 2 mm).
  m.check("probe inside the magnet", es,
          {"--field", "analytic", "--array", "two", "--r0", "1.0", "--dz", "-3", "--steps", "256", "--out", "o.csv"}, s,
          inputs, {"magnet"});
  // (linear_model is not here: its field is the linear model, which has no magnet volume.)
  for (const char* study : {"exact_field"})
    m.check("probe inside the magnet", kBin / study,
            {"--set", "mount.dz_mm=-3", "--set", "sensor.r0_mm=1.0", "--set", "sensor.steps=256", "--out", "study"}, s,
            inputs, {"magnet"});
  // fem_vs_exact --other-bz (another solver's Bz table, scripts/bench_getdp.sh): read before the solve.
  for (const auto& [cls, file] : std::vector<std::pair<std::string, std::string>>{
           {"other-bz missing", "nosuch_bz.txt"},
           {"other-bz not numbers", add("bz_text.txt", "-4 -4 4.55 -0.0138\n-4 -3.9 4.55 abc\n")},
           {"other-bz too few columns", add("bz_cols.txt", "-4 -4 4.55\n")},
           {"other-bz empty", add("bz_empty.txt", "")}})
    m.check(cls, kBin / "fem_vs_exact",
            {"--other-bz", file, "--config", std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml", "--out", "fve"}, s,
            inputs, {"--other-bz"});
  // Absurd sizes: refused up front with an estimate (seconds, not the minutes or the memory they'd take).
  for (const auto& set : {"mesh.h_core_mm=0.011", "mesh.h_zone_mm=0.011", "mesh.h_air_mm=0.011",
                          "grid.plane_step_mm=0.000001", "grid.box_step_mm=0.0001"}) {
    const std::string key = std::string(set).substr(0, std::string(set).find('='));
    for (const auto& exe : {sf, kBin / "fem_vs_exact"}) {
      const auto t0 = std::chrono::steady_clock::now();
      m.check("absurd size", exe, {"--set", set, "--out", "big"}, s, inputs, {key});
      CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 20);
    }
  }
  WARN("bad-input matrix (input files, geometry, sizes): " << m.cases << " cases in " << m.classes.size()
                                                            << " classes, " << m.failures << " failures");
  CHECK(m.failures == 0);
}
