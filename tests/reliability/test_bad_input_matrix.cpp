// The bad-input matrix: every executable of build/bin (benchmarks aside) against every
// class of bad input. Each case must give: exit code != 0, exactly one line on stderr, naming the
// input (the key, file or flag), and no output file (nothing new in the scratch directory but the
// inputs the test wrote). The configuration keys are not hand-listed: each executable's key table is
// read from its --help (Config::describe(), one line per declared key with its allowed range) and
// every key gets the bad values of its type.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <cmath>
#include <map>
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
  double slowest = 0;  // s, the slowest case (a case that does work before it checks its input is slow)
  std::string slowest_cmd;
  std::string slowest_case() const { return "; slowest case " + std::to_string(slowest) + " s: " + slowest_cmd; }
  void check(const std::string& cls, const fs::path& exe, const std::vector<std::string>& args, const ScratchDir& s,
             const std::vector<std::string>& inputs, const std::vector<std::string>& must_name) {
    classes.insert(cls);
    ++cases;
    const ProcResult r = run(exe, args, s.dir, {}, s.dir.parent_path());
    std::string cmd = exe.filename().string();
    for (const auto& a : args) cmd += " '" + a + "'";
    if (r.seconds > slowest) {
      slowest = r.seconds;
      slowest_cmd = cmd;
    }
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

// A valid measured curve (theta_deg,error_deg, 72 rows over one turn) and a valid field table (Bz on a
// 5 x 3 plane): the inputs diagnose (--measured) and table_to_vti (--table) require before they read
// anything else, so that each case's one bad input is the one the error must name.
std::string good_curve() {
  std::string t = "theta_deg,error_deg\n";
  for (int i = 0; i < 72; ++i) {
    const double th = 5.0 * i;
    t += std::to_string(th) + "," + std::to_string(0.02 * std::sin(th * M_PI / 180)) + "\n";
  }
  return t;
}
std::string good_table() {
  std::string t = "x_mm,y_mm,Bz_T\n";
  for (int j = -1; j <= 1; ++j)
    for (int i = -2; i <= 2; ++i) t += std::to_string(0.5 * i) + "," + std::to_string(0.5 * j) + ",0.0" + std::to_string(i + 3) + "\n";
  return t;
}

// The required arguments of an executable and the files they name (written into the scratch dir).
struct Required {
  std::vector<std::string> args;
  std::vector<std::pair<std::string, std::string>> files;
};
Required required_inputs(const fs::path& exe) {
  const std::string n = exe.filename().string();
  if (n == "diagnose") return {{"--measured", "good_curve.csv"}, {{"good_curve.csv", good_curve()}}};
  if (n == "table_to_vti") return {{"--table", "good_table.csv"}, {{"good_table.csv", good_table()}}};
  if (n == "field_at") return {{"--points", "good_points.csv"}, {{"good_points.csv", "x_mm,y_mm,z_mm\n0,0,4.55\n"}}};
  if (n == "calibrate") return {{"--method", "harmonics:8"}, {}};  // (the default method none is refused first)
  if (n == "inspect")
    return {{"--scan", "good_scan.csv"},
            {{"good_scan.csv", "x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT\n0,0,4.55,-20,0,0\n1,0,4.55,-15,0,10\n0,1,4.55,-18,1,0\n"}}};
  return {};
}
// Writes exe's required files into s, adds their names to `inputs`, returns args preceded by the
// required arguments.
std::vector<std::string> with_required(const fs::path& exe, const ScratchDir& s, std::vector<std::string>& inputs,
                                       const std::vector<std::string>& args) {
  const Required r = required_inputs(exe);
  for (const auto& [name, text] : r.files) {
    s.write(name, text);
    if (std::find(inputs.begin(), inputs.end(), name) == inputs.end()) inputs.push_back(name);
  }
  std::vector<std::string> a = r.args;
  a.insert(a.end(), args.begin(), args.end());
  return a;
}

// The executables whose output is one file (--out FILE); all others write a directory (--out DIR).
bool file_output(const fs::path& exe) {
  return exe.filename() == "error_spectrum" || exe.filename() == "table_to_vti" || exe.filename() == "field_at";
}

}  // namespace

// The executables' keys, in four ctest entries that ctest -j runs in parallel: solve_field and
// fem_vs_exact each alone (the most keys: [fem] [mesh] [grid]), the other apps, and the studies.
namespace {
enum class Group { SolveField, FemVsExact, OtherApps, Studies };
Group group_of(const fs::path& exe) {
  const std::string n = exe.filename().string();
  if (n == "solve_field") return Group::SolveField;
  if (n == "fem_vs_exact") return Group::FemVsExact;
  if (n == "error_spectrum" || n == "diagnose" || n == "table_to_vti" || n == "field_at" || n == "inspect" ||
      n == "calibrate")
    return Group::OtherApps;
  return Group::Studies;
}
// Which bad values each key gets. Release: all of its type's. The instrumented build (ASan + UBSan, where
// each case costs a sanitized process start-up and exit, ~5x Release's): one --set and one TOML value per
// key, the keys of a type taking the type's values in turn across the group's executables, so that every
// key's error path and every bad value of every type still run under the sanitizers (the parsing is the
// one Config reader's; the Release matrix keeps every key x every value).
#if defined(MAGENC_SANITIZED_BUILD)
constexpr bool kEveryValueOfEveryKey = false;
#else
constexpr bool kEveryValueOfEveryKey = true;
#endif
struct ValuePicker {
  std::map<std::pair<int, int>, std::size_t> next;  // (kind, --set 0 / TOML 1) -> the next value's index
  std::vector<std::string> pick(const KeyInfo& k, int channel, const std::vector<std::string>& all) {
    if (kEveryValueOfEveryKey || all.empty()) return all;
    std::size_t& i = next[{static_cast<int>(k.kind), channel}];
    return {all[i++ % all.size()]};
  }
};

void key_matrix(Group group, std::size_t min_exes, const std::string& label) {
  std::vector<fs::path> exes;
  for (const auto& e : executables(kBin))
    if (group_of(e) == group) exes.push_back(e);
  REQUIRE(exes.size() >= min_exes);
  Matrix m;
  ValuePicker picker;  // one rotation over the group's executables: each bad value runs somewhere
  int keys_total = 0, array_keys = 0;
  for (const auto& exe : exes) {
    const auto keys = key_table(exe);
    for (const auto& k : keys)
      array_keys += k.kind == KeyInfo::Kind::NumberList || k.kind == KeyInfo::Kind::StringList;
    INFO(exe.filename().string());
    REQUIRE(keys.size() >= 10);  // at least the common [magnet]/[sensor]/[mount] keys
    keys_total += int(keys.size());
    ScratchDir s("magenc_matrix");
    std::vector<std::string> inputs{"bad.toml"};
    for (const auto& k : keys) {
      for (const auto& v : picker.pick(k, 0, bad_values(k)))
        m.check("--set " + std::string(k.kind == KeyInfo::Kind::Real                 ? "real"
                                       : k.kind == KeyInfo::Kind::NumberList ||
                                               k.kind == KeyInfo::Kind::StringList ? "array"
                                                                                   : "other") + " key", exe,
                with_required(exe, s, inputs, {"--set", k.key + "=" + v, "--out", "out"}), s, inputs, {k.key});
      const auto dot = k.key.rfind('.');
      for (const auto& v : picker.pick(k, 1, bad_toml_values(k))) {
        const std::string table = k.key.substr(0, dot);  // ("[" + substr(): GCC 12 -Wrestrict false positive)
        s.write("bad.toml", "[" + table + "]\n" + k.key.substr(dot + 1) + " = " + v + "\n");
        m.check("TOML value", exe, with_required(exe, s, inputs, {"--config", "bad.toml", "--out", "out"}), s, inputs,
                {k.key});
      }
    }
  }
  WARN("bad-input matrix (config keys, " << label << "): " << exes.size() << " executables, " << keys_total
                                          << " keys, " << m.cases << " cases, " << m.failures << " failures, "
                                          << array_keys << " array keys"
                                          << (kEveryValueOfEveryKey ? "" : " (one --set and one TOML value per key)")
                                          << m.slowest_case());
  if (group == Group::Studies) CHECK(array_keys > 0);  // the studies' list keys are arrays (study.arrays, ...)
  CHECK(m.failures == 0);
}
}  // namespace

TEST_CASE("bad-input matrix: solve_field x every declared key x its bad values (--set and TOML)",
          "[apps][bad-input][cli][slow]") {
  key_matrix(Group::SolveField, 1, "solve_field");
}

TEST_CASE("bad-input matrix: fem_vs_exact x every declared key x its bad values (--set and TOML)",
          "[apps][bad-input][cli][slow]") {
  key_matrix(Group::FemVsExact, 1, "fem_vs_exact");
}

TEST_CASE("bad-input matrix: error_spectrum diagnose table_to_vti field_at inspect calibrate x every declared key x its bad values",
          "[apps][bad-input][cli]") {
  key_matrix(Group::OtherApps, 6, "error_spectrum, diagnose, table_to_vti, field_at, inspect, calibrate");
}

TEST_CASE("bad-input matrix: every study x every declared key x its bad values (--set and TOML)",
          "[apps][bad-input][cli][slow]") {
  key_matrix(Group::Studies, 9, "studies");
}

// [[parts]]' offset_mm = [x, y] (a table field the key matrix above does not reach: parts has no section):
// every executable that declares parts refuses a bad offset with exit 2, one line naming the field and
// its allowed form, and no output; --set inline tables and, for solve_field, [[parts]] sections.
TEST_CASE("bad-input matrix: the parts' offset_mm x every executable that declares parts", "[apps][bad-input][cli]") {
  const std::string part = "name = \"s\", shape = \"cylinder\", r_outer_mm = 1, z_min_mm = -6, z_max_mm = -3, "
                           "material = \"mu_r:10\", offset_mm = ";
  const std::vector<std::pair<std::string, std::string>> offsets = {
      {"[1]", "has 1 element"},
      {"[1, 2, 3]", "has 3 elements"},
      {"[\"1\", 0]", "element 1 of 2 must be a number"},
      {"[0, nan]", "element 2 of 2 = nan is out of range"},
      {"[inf, 0]", "element 1 of 2 = inf is out of range"},
      {"[0, -1001]", "element 2 of 2 = -1001 is out of range"},
      {"2.5", "must be an array"},
      {"{ x = 1 }", "must be an array"},
  };
  const std::string form = "offset_mm = an array of 2 numbers, each [-1000, 1000] mm";
  ScratchDir s("magenc_matrix_parts");
  int cases = 0;
  auto check = [&](const std::string& exe, const std::vector<std::string>& args, const std::vector<std::string>& inputs,
                   const std::string& says) {
    ++cases;
    const ProcResult r = run(kBin / exe, args, s.dir);
    const auto stray = s.entries_except(inputs);
    INFO(exe << " " << args[1] << "\n  stderr: " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(count_lines(r.err) == 1);
    CHECK(r.err.find("parts element 1 of 1: field offset_mm " + says) != std::string::npos);
    CHECK(r.err.find(form) != std::string::npos);
    CHECK(stray.empty());
  };
  for (const char* exe : {"solve_field", "fem_vs_exact", "fem_convergence", "steel_parts"})
    for (const auto& [offset, says] : offsets)
      check(exe, {"--set", "parts=[{ " + part + offset + " }]", "--out", "out"}, {}, says);
  for (const auto& [offset, says] : offsets) {
    s.write("parts.toml", "[[parts]]\n" + std::regex_replace(part, std::regex(", "), "\n") + offset + "\n");
    check("solve_field", {"--config", "parts.toml", "--out", "out"}, {"parts.toml"}, says);
  }
  WARN("bad-input matrix (parts offset_mm): " << cases << " cases");
}

TEST_CASE("bad-input matrix: every executable x unusable files and output paths", "[apps][bad-input][cli]") {
  const auto exes = executables(kBin);
  REQUIRE(exes.size() >= 14);
  Matrix m;
  for (const auto& exe : exes) {
    INFO(exe.filename().string());
    ScratchDir s("magenc_matrix_files");
    std::vector<std::string> inputs;  // files this executable's cases wrote so far (not output)
    const auto check = [&](const std::string& cls, const std::vector<std::string>& args,
                           const std::vector<std::string>& names) {
      m.check(cls, exe, with_required(exe, s, inputs, args), s, inputs, names);
    };
    const auto add = [&](const std::string& name, const std::string& text) {
      s.write(name, text);
      inputs.push_back(name);
      return name;
    };
    // Configuration files: missing, a directory, truncated, binary garbage, deeply nested, too big.
    check("config missing", {"--config", "missing.toml", "--out", "out"}, {"missing.toml"});
    fs::create_directories(s.dir / "cfgdir.toml");
    inputs.push_back("cfgdir.toml");
    check("config is a directory", {"--config", "cfgdir.toml", "--out", "out"}, {"cfgdir.toml"});
    add("trunc.toml", "[magnet]\nradius_mm = 2.0\n[sens");
    check("config truncated", {"--config", "trunc.toml", "--out", "out"}, {"trunc.toml"});
    std::string garbage;
    for (int i = 0; i < 4096; ++i) garbage += char((i * 7919 + 13) % 256);
    add("garbage.toml", garbage);
    check("config corrupted", {"--config", "garbage.toml", "--out", "out"}, {"garbage.toml"});
    std::string deep = "[a";
    for (int i = 0; i < 50000; ++i) deep += ".a";
    add("deep.toml", deep + "]\n");
    check("config nested 50,000 deep", {"--config", "deep.toml", "--out", "out"}, {"deep.toml"});
    // Unknown key, malformed --set, unknown flag.
    check("unknown key", {"--set", "magnet.no_such_key=1", "--out", "out"}, {"magnet.no_such_key"});
    check("malformed --set", {"--set", "magnet.radius_mm", "--out", "out"}, {"magnet.radius_mm"});
    check("unknown flag", {"--no-such-flag", "--out", "out"}, {"--no-such-flag"});
  }
  WARN("bad-input matrix (files, flags): " << m.cases << " cases, " << m.failures << " failures" << m.slowest_case());
  CHECK(m.failures == 0);
}

TEST_CASE("bad-input matrix: every executable x an output path that is unusable", "[apps][bad-input][cli]") {
  const auto exes = executables(kBin);
  REQUIRE(exes.size() >= 14);
  Matrix m;
  for (const auto& exe : exes) {
    INFO(exe.filename().string());
    ScratchDir s("magenc_matrix_out");
    s.write("afile", "not a directory\n");
    fs::create_directories(s.dir / "adir");
    const bool to_file = file_output(exe);  // --out FILE; all others --out DIR
    std::vector<std::string> base;
    if (exe.filename() == "error_spectrum") base = {"--field", "analytic", "--array", "two", "--r0", "2.4", "--steps", "256"};
    if (exe.filename() == "diagnose") base = {"--starts", "1"};  // (the fit runs before the output is written)
    std::vector<std::string> inputs{"afile", "adir"};
    auto with = [&](const std::string& out) {
      auto a = base;
      a.insert(a.end(), {"--out", out});
      return with_required(exe, s, inputs, a);
    };
    if (to_file) m.check("--out is a directory", exe, with("adir"), s, inputs, {"adir"});
    else m.check("--out is a file", exe, with("afile"), s, inputs, {"afile"});
    m.check("--out not writable (below a file)", exe, with("afile/sub"), s, inputs, {"afile/sub"});
    m.check("--out not writable (/proc)", exe, with("/proc/magenc_no_such_dir/out"), s, inputs,
            {"/proc/magenc_no_such_dir/out"});
    CHECK(slurp(s.dir / "afile") == "not a directory\n");
  }
  WARN("bad-input matrix (output paths): " << m.cases << " cases, " << m.failures << " failures" << m.slowest_case());
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
                                                            << " classes, " << m.failures << " failures" << m.slowest_case());
  CHECK(m.failures == 0);
}

TEST_CASE("bad-input matrix: measured curves, field tables and the studies' free-string keys",
          "[apps][bad-input][cli]") {
  Matrix m;
  const fs::path dg = kBin / "diagnose", tv = kBin / "table_to_vti", es = kBin / "error_spectrum";
  ScratchDir s("magenc_matrix_curves");
  std::vector<std::string> inputs;
  auto add = [&](const std::string& name, const std::string& text) {
    s.write(name, text);
    inputs.push_back(name);
    return name;
  };
  fs::create_directories(s.dir / "dir.csv");
  inputs.push_back("dir.csv");
  const std::string curve = good_curve(), table = good_table();
  add("good_curve.csv", curve);
  add("good_table.csv", table);
  // Measured curves (diagnose --measured): each fails in the reader, before any fit.
  auto curve_case = [&](const std::string& cls, const std::string& file) {
    m.check("measured curve " + cls, dg, {"--measured", file, "--out", "out"}, s, inputs, {file});
  };
  curve_case("missing", "missing.csv");
  curve_case("is a directory", "dir.csv");
  curve_case("empty", add("empty.csv", ""));
  curve_case("truncated mid-row", add("trunc.csv", curve.substr(0, curve.find('\n', curve.size() / 2) + 4)));
  curve_case("truncated to 40 rows", add("short.csv", curve.substr(0, curve.find("200.000000"))));
  std::string garbage;
  for (int i = 0; i < 4096; ++i) garbage += char((i * 7919 + 13) % 256);
  curve_case("corrupted (binary)", add("garbage.csv", garbage));
  curve_case("NUL bytes", add("nul.csv", curve.substr(0, 200) + std::string(1, '\0') + curve.substr(200)));
  {
    std::string utf16;  // Excel's "Unicode Text" without the byte-order mark
    for (char c : curve) utf16 += std::string{c, '\0'};
    const std::string f = add("utf16.csv", utf16);
    m.check("measured curve UTF-16", dg, {"--measured", f, "--out", "out"}, s, inputs, {"save as \"CSV UTF-8\""});
  }
  REQUIRE(::mkfifo((s.dir / "pipe.csv").c_str(), 0600) == 0);  // read, it would wait for a writer
  inputs.push_back("pipe.csv");
  curve_case("a named pipe", "pipe.csv");
  for (const auto& [cls, v] : std::vector<std::pair<std::string, std::string>>{
           {"NaN", "nan"}, {"inf", "inf"}, {"overflow", "1e999"}, {"text", "abc"}, {"empty cell", ""}}) {
    std::string c = curve;
    const auto row = c.find("\n100.000000,") + 12;
    c.replace(row, c.find('\n', row) - row, v);
    curve_case(cls + " value", add("value_" + std::to_string(inputs.size()) + ".csv", c));
  }
  curve_case("unknown header", add("header.csv", "theta_deg,err\n" + curve.substr(curve.find('\n') + 1)));
  curve_case("gap of 60 deg", add("gap.csv", curve.substr(0, curve.find("\n100.000000,") + 1) +
                                                 curve.substr(curve.find("\n160.000000,") + 1)));
  curve_case("repeated angle, other value", add("repeat.csv", curve + "5.000000,0.3\n"));
  curve_case("theta out of range", add("theta.csv", curve + "1e12,0.0\n"));
  // A field table given to diagnose / error_spectrum (--field table:FILE) and table_to_vti (--table FILE).
  std::vector<std::pair<std::string, std::string>> tables;
  {
    std::string t = table;
    tables.push_back({"truncated mid-row", t.substr(0, t.size() - 5)});
    tables.push_back({"missing point", t.substr(0, t.rfind('\n', t.size() - 2) + 1)});
    tables.push_back({"repeated point", t + t.substr(t.find('\n') + 1, t.find('\n', t.find('\n') + 1) - t.find('\n'))});
    std::string nan = t;
    nan.replace(nan.rfind(",0.0"), 5, ",nan");
    tables.push_back({"NaN value", nan});
    std::string off = t;
    off.replace(off.find("\n0.000000,"), 10, "\n0.013000,");
    tables.push_back({"point off the lattice", off});
    tables.push_back({"unknown column", "x_mm,y_mm,Hz_A_per_m\n" + t.substr(t.find('\n') + 1)});
    tables.push_back({"corrupted (binary)", garbage});
    std::string zero = "x_mm,y_mm,Bz_T\n", huge = t;
    for (int j = -1; j <= 1; ++j)
      for (int i = -2; i <= 2; ++i) zero += std::to_string(0.5 * i) + "," + std::to_string(0.5 * j) + ",0\n";
    tables.push_back({"all zero", zero});
    huge.replace(huge.rfind(",0.0"), 5, ",1e300");
    tables.push_back({"one 1e300 T node", huge});
    tables.push_back({"mT values under Bz_T", "x_mm,y_mm,Bz_T\n0,0,20\n1,0,30\n0,1,40\n1,1,50\n"});
    tables.push_back({"T values under Bz_mT", "x_mm,y_mm,Bz_mT\n0,0,0.02\n1,0,0.03\n0,1,0.04\n1,1,0.05\n"});
    tables.push_back({"mm coordinates under x_m", "x_m,y_m,Bz_T\n-5,-5,0.02\n5,-5,0.03\n-5,5,0.04\n5,5,0.05\n"});
    tables.push_back({"empty", ""});
  }
  int k = 0;
  for (const auto& [cls, text] : tables) {
    const std::string f = add("table" + std::to_string(k++) + ".csv", text);
    m.check("table " + cls, tv, {"--table", f, "--out", "t.vti"}, s, inputs, {f});
    m.check("--field table: " + cls, es,
            {"--field", "table:" + f, "--array", "two", "--r0", "0.5", "--steps", "256", "--out", "o.csv"}, s, inputs,
            {f});
    m.check("--field table: " + cls, dg, {"--measured", "good_curve.csv", "--field", "table:" + f, "--out", "out"}, s,
            inputs, {f});
  }
  m.check("table missing", tv, {"--table", "missing.csv", "--out", "t.vti"}, s, inputs, {"missing.csv"});
  m.check("table is a directory", tv, {"--table", "dir.csv", "--out", "t.vti"}, s, inputs, {"dir.csv"});
  m.check("table --out is the table", tv, {"--table", "good_table.csv", "--out", "good_table.csv"}, s, inputs,
          {"good_table.csv"});
  m.check("table one plane off the sensing plane", es,
          {"--field", "table:" + add("plane3.csv", "x_mm,y_mm,z_mm,Bz_T\n0,0,3,0.1\n1,0,3,0.1\n0,1,3,0.1\n1,1,3,0.1\n"),
           "--array", "two", "--r0", "0.5", "--steps", "256", "--out", "o.csv"},
          s, inputs, {"plane3.csv"});
  // The studies' free-string keys (lists and names, checked where they are used).
  for (const auto& [study, set, name] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"error_sources", "study.arrays=two,ring:2", "study.arrays"},
           {"error_sources", "study.sources=tilt_x_deg,no_such_source", "study.sources"},
           {"error_sources", "study.field=grid:missing.vti", "missing.vti"},  // (its message says --field)
           {"error_sources", "sweep.coefs=c1_deg,zz_deg", "sweep.coefs"},
           {"diagnosis", "study.arrays=two,ring:2", "study.arrays"},
           {"diagnosis", "roundtrip.free=sx_mm,no_such_parameter", "roundtrip.free"},
           {"diagnosis", "roundtrip.randomized=no_such_parameter", "roundtrip.randomized"},
           {"diagnosis", "fem_field.dir=missing_dir", "missing_dir"}})
    m.check("study free-string key", kBin / study, {"--set", set, "--out", "study"}, s, inputs, {name});
  WARN("bad-input matrix (curves, tables, study strings): " << m.cases << " cases in " << m.classes.size()
                                                           << " classes, " << m.failures << " failures" << m.slowest_case());
  CHECK(m.failures == 0);
}
