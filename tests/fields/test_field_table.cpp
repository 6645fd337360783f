// Field tables from other tools (src/fields/field_table.*, docs/interfaces.md):
//  1. Round trip: a GridData written as a table (any separator, m or mm, T or
//     mT, rows shuffled, comments, CRLF) reads back to the same grid (nodes
//     and values to 1e-12 relative: the table holds 17 significant digits).
//  2. Physics through the table: the exact field written as a table at
//     h = 0.05 mm, read by `--field table:` with cubic interpolation, gives the
//     exact spectra within 1e-5 deg (c1..c4, two and diff4, 0.1 mm offsets);
//     a 3-D table gives the exact dz spectra within 1e-4 deg (h_z = 0.05 mm).
//     These are the tolerances of the .vti grid path at the same spacing
//     (test_grid_pipeline.cpp): cubic interpolation error O(h^4).
//  3. Bad tables, one class each: one-line InputError naming the problem and
//     the first offending line (or the first missing point).
//  4. CLIs: error_spectrum --field table:, table_to_vti (atomic, one-line errors).
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <unistd.h>

#include "core/errors.hpp"
#include "fields/analytic_field.hpp"
#include "fields/field_factory.hpp"
#include "fields/field_table.hpp"
#include "fields/magnet.hpp"
#include "probe/angle_error.hpp"
#include "probe/common_keys.hpp"
#include "support/spreadsheet_text.hpp"
#include "support/spectrum_compare.hpp"
#include "support/study_test_util.hpp"

using namespace magenc;
namespace fs = std::filesystem;

namespace {

fs::path scratch() {
  auto d = fs::temp_directory_path() / ("magenc_test_table_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// The table's header (comment lines kept on top) and its data rows shuffled with a fixed seed.
std::string shuffle_rows(const std::string& text, unsigned seed) {
  std::istringstream is(text);
  std::vector<std::string> top, rows;
  bool header_seen = false;
  for (std::string l; std::getline(is, l);) {
    if (!header_seen) {
      top.push_back(l);
      if (!l.empty() && l[0] != '#') header_seen = true;
    } else {
      rows.push_back(l);
    }
  }
  std::mt19937 rng(seed);
  std::shuffle(rows.begin(), rows.end(), rng);
  std::string out;
  for (const auto& l : top) out += l + "\n";
  for (const auto& l : rows) out += l + "\n";
  return out;
}

// Message of the InputError parse_field_table throws (empty if none).
std::string parse_error(const std::string& text, const FieldTableLimits& limits = {}) {
  try {
    parse_field_table(text, "t.csv", 4.55, limits);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A small 2-D table: x = 0..3 (step 1), y = 0..2 (step 0.5), Bz = x + 10 y (mT), in row order.
std::string small_table(const std::string& header = "x_mm,y_mm,Bz_mT") {
  std::string t = header + "\n";
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 4; ++i) t += std::to_string(i) + "," + std::to_string(0.5 * j) + "," + std::to_string(i + 5 * j) + "\n";
  return t;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

GridData sample_exact(const Config& cfg, bool box, bool bz_only) {
  const AnalyticField exact(Magnet::from_config(cfg));
  const double zs = sensing_plane_z_mm(cfg);
  // h = 0.05 mm over [-3.5, 3.5] mm (solve_field's plane spacing); the box spans z_s +- 0.15 mm.
  return box ? sample_grid(exact, Vec3(-3.5, -3.5, zs - 0.15), Vec3(0.05, 0.05, 0.05), {141, 141, 7}, bz_only)
             : sample_grid(exact, Vec3(-3.5, -3.5, zs), Vec3(0.05, 0.05, 0.05), {141, 141, 1}, bz_only);
}

}  // namespace

TEST_CASE("a grid written as a table reads back to the same grid in every format", "[fields][contract]") {
  const Config cfg(common_keys());
  // A small exact-field box with B (3-D) and a Bz-only plane.
  const AnalyticField exact(Magnet::from_config(cfg));
  const double zs = sensing_plane_z_mm(cfg);
  const GridData box = sample_grid(exact, Vec3(-3, -2, zs - 0.2), Vec3(0.25, 0.2, 0.1), {25, 21, 5});
  const GridData plane = sample_grid(exact, Vec3(-3, -2, zs), Vec3(0.25, 0.2, 1), {25, 21, 1}, true);
  struct Case {
    const GridData* g;
    FieldTableFormat f;
    bool crlf;
  };
  std::vector<Case> cases;
  for (char sep : {',', '\t', ' '})
    for (bool metres : {false, true})
      for (bool milli : {false, true}) {
        FieldTableFormat f;
        f.separator = sep;
        f.metres = metres;
        f.millitesla = milli;
        f.comment = "exported by a test\nunits as in the header";
        cases.push_back({&box, f, sep == ' '});
        f.with_z = false;
        cases.push_back({&plane, f, false});
      }
  for (const auto& c : cases) {
    std::string text = shuffle_rows(field_table_text(*c.g, c.f), 7);
    text = "% COMSOL-style comment\n\n" + text;
    if (c.crlf) {
      std::string t;
      for (char ch : text) t += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
      text = t;
    }
    CAPTURE(int(c.f.separator), c.f.metres, c.f.millitesla, c.g->is_plane(), c.crlf);
    const GridData r = parse_field_table(text, "roundtrip", zs);
    REQUIRE(r.dims == c.g->dims);
    CHECK(r.has_B() == c.g->has_B());
    CHECK((r.origin_mm - c.g->origin_mm).norm() < 1e-12);
    CHECK((r.spacing_mm.head<2>() - c.g->spacing_mm.head<2>()).norm() < 1e-12);
    if (!r.is_plane()) CHECK(std::abs(r.spacing_mm.z() - c.g->spacing_mm.z()) < 1e-12);
    double worst = 0;
    for (std::size_t i = 0; i < r.nodes(); ++i) {
      worst = std::max(worst, std::abs(r.Bz_T[i] - c.g->Bz_T[i]));
      if (r.has_B()) worst = std::max({worst, std::abs(r.Bx_T[i] - c.g->Bx_T[i]), std::abs(r.By_T[i] - c.g->By_T[i])});
    }
    CHECK(worst < 1e-12);  // |B| <= 0.6 T here: 1e-12 T is ~1e-12 relative
  }
  // A table with a z column and one level is the plane at that height.
  FieldTableFormat with_z;
  with_z.with_z = true;
  const GridData r = parse_field_table(field_table_text(plane, with_z), "plane with z", 0.0);
  CHECK(r.is_plane());
  CHECK(r.origin_mm.z() == Approx(zs).margin(1e-12));
  // Coordinates printed with 6 significant digits (as FEMM or a spreadsheet may) still form the grid.
  std::string six = "x_mm y_mm Bz_T\n";
  for (int j = 0; j < 30; ++j)
    for (int i = 0; i < 30; ++i) {
      char line[96];
      std::snprintf(line, sizeof line, "%.6g %.6g %.6g\n", -1.234567 + i * 0.0912345, 0.1 + j * 0.0712345, 0.001 * i);
      six += line;
    }
  const GridData s6 = parse_field_table(six, "six digits", zs);
  CHECK(s6.dims == std::array<int, 3>{30, 30, 1});
  CHECK(s6.spacing_mm.x() == Approx(0.0912345).epsilon(1e-5));
}

TEST_CASE("a table as spreadsheet programs save it reads as the plain table", "[fields][regression]") {
  const Config cfg(common_keys());
  const AnalyticField exact(Magnet::from_config(cfg));
  const double zs = sensing_plane_z_mm(cfg);
  const GridData box = sample_grid(exact, Vec3(-1, -1, zs - 0.1), Vec3(0.25, 0.5, 0.1), {9, 5, 3});
  const std::string plain = field_table_text(box);
  const GridData ref = parse_field_table(plain, "plain", zs);
  for (const std::string& text : {test::european(plain), test::with_bom(test::with_crlf(test::european(plain))),
                                  test::european(plain, '\t'), test::with_crlf(plain, true)}) {
    const GridData g = parse_field_table(text, "spreadsheet", zs);
    REQUIRE(g.dims == ref.dims);
    CHECK(g.origin_mm == ref.origin_mm);
    CHECK(g.spacing_mm == ref.spacing_mm);
    CHECK(g.Bz_T == ref.Bz_T);
    CHECK(g.Bx_T == ref.Bx_T);
    CHECK(g.By_T == ref.By_T);
  }
}

TEST_CASE("the exact field as a table reproduces the exact spectra", "[fields][cross-check]") {
  const Config cfg(common_keys());
  const AnalyticField exact(Magnet::from_config(cfg));
  const double zs = sensing_plane_z_mm(cfg);
  const auto dir = scratch();
  // 2-D table, Bz only, CSV in mm and T, rows shuffled; 3-D table with B, whitespace, m and mT, shuffled.
  FieldTableFormat csv;
  csv.with_z = false;
  write_text(dir / "plane.csv", shuffle_rows(field_table_text(sample_exact(cfg, false, true), csv), 1));
  FieldTableFormat ws;
  ws.separator = ' ';
  ws.metres = true;
  ws.millitesla = true;
  ws.comment = "3-D box, metres and millitesla";
  write_text(dir / "box.txt", shuffle_rows(field_table_text(sample_exact(cfg, true, false), ws), 2));
  for (const std::string table : {"plane.csv", "box.txt"}) {
    FieldOptions opts;
    opts.interp = Interp::Cubic;
    const auto field = make_field_source("table:" + (dir / table).string(), cfg, opts);
    CHECK(field->name() == "table");
    for (const std::string array : {"two", "diff4"}) {
      ProbeSetup setup;
      setup.array = ProbeArray::parse(array);
      setup.plane_z_mm = zs;
      test::compare_spectra_per_eccentricity(exact, *field, setup, 0.1, [&](const std::string& off, const Spectrum& se,
                                                                            const Spectrum& st) {
        CHECK(std::abs(st.a0_deg - se.a0_deg) < 1e-5);
        for (int n = 1; n <= 4; ++n) {
          CAPTURE(table, array, off, n, se.c_deg[n], st.c_deg[n]);
          CHECK(std::abs(st.c_deg[n] - se.c_deg[n]) < 1e-5);
        }
      });
    }
  }
  // dz on the 3-D table: dz = 0.1 mm with dx = 0.1 mm, two array.
  {
    const auto box = make_field_source("table:" + (dir / "box.txt").string(), cfg);
    ProbeSetup setup;
    setup.array = ProbeArray::parse("two");
    setup.plane_z_mm = zs;
    Mount m;
    m.dx_mm = 0.1;
    m.dz_mm = 0.1;
    const Spectrum se = error_spectrum(exact, setup, m), st = error_spectrum(*box, setup, m);
    for (int n = 1; n <= 4; ++n) {
      CAPTURE(n, se.c_deg[n], st.c_deg[n]);
      CHECK(std::abs(st.c_deg[n] - se.c_deg[n]) < 1e-4);
    }
  }
  // Tilts need the full vector off the plane: the 3-D table with Bx, By, Bz serves them (sensor tilt 1 deg and
  // magnet tilt 1 deg, two array: within 1e-4 deg of the exact field); the Bz-only plane refuses them.
  {
    const auto box = make_field_source("table:" + (dir / "box.txt").string(), cfg);
    const auto plane = make_field_source("table:" + (dir / "plane.csv").string(), cfg);
    CHECK(box->gives_full_vector());
    CHECK_FALSE(plane->gives_full_vector());
    ProbeSetup setup;
    setup.array = ProbeArray::parse("two");
    setup.plane_z_mm = zs;
    Mount tx;
    tx.tilt_x_deg = 1.0;
    Mount mt;
    mt.magnet_tilt_deg = 1.0;
    for (const Mount& m : {tx, mt}) {
      const Spectrum se = error_spectrum(exact, setup, m), st = error_spectrum(*box, setup, m);
      CAPTURE(m.tilt_x_deg, m.magnet_tilt_deg, se.a0_deg, st.a0_deg, se.c_deg[1], st.c_deg[1], se.c_deg[2], st.c_deg[2]);
      CHECK(std::abs(st.a0_deg - se.a0_deg) < 1e-4);
      for (int n = 1; n <= 4; ++n) CHECK(std::abs(st.c_deg[n] - se.c_deg[n]) < 1e-4);
    }
    CHECK(std::abs(error_spectrum(*box, setup, tx).c_deg[2] - 0.754) < 1e-3);  // docs/physics.md reference value
    CHECK_THROWS_AS(error_spectrum(*plane, setup, tx), InputError);
  }
  // dz on the 2-D table names the missing z column.
  try {
    make_field_source("table:" + (dir / "plane.csv").string(), cfg)->Bz_T(Vec3(2.4, 0, zs + 0.1));
    FAIL("no error off the plane");
  } catch (const InputError& e) {
    CHECK(contains(e.what(), "z column"));
  }
  fs::remove_all(dir);
}

TEST_CASE("bad tables: one line naming the problem and the first offending line", "[fields][bad-input]") {
  // small_table(): header on line 1, row (i, j) on line 2 + i + 4 j.
  SECTION("a good small table parses") {
    const GridData g = parse_field_table(small_table(), "t.csv", 4.55);
    CHECK(g.dims == std::array<int, 3>{4, 5, 1});
    CHECK(g.Bz_T[3 + 4 * 2] == Approx(13e-3));
  }
  struct Bad {
    std::string what, text, expect1, expect2;
  };
  std::string t = small_table();
  auto replace_line = [](std::string text, int line_no, const std::string& line) {
    std::istringstream is(text);
    std::string out;
    int n = 0;
    for (std::string l; std::getline(is, l);) out += (++n == line_no ? line : l) + "\n";
    return out;
  };
  const std::vector<Bad> bad = {
      {"irregular: x = 2.3 instead of 2 on line 4", replace_line(t, 4, "2.3,0,2"), "line 4:", "off the regular grid"},
      {"irregular level on a later line", replace_line(t, 12, "2.3,1,12"), "line 12:", "x = 2.3"},
      {"missing point (1, 1)", replace_line(t, 11, ""), "(1, 1, 4.55) mm is missing", "19 rows for a grid of 4 x 5 x 1"},
      {"duplicate point", t + "2,1.5,99\n", "line 22:", "repeats line 16"},
      {"extra point far away", replace_line(t, 9, "10,0,1\n3,0.5,8"), "line 9:", "extra point"},
      // So far that it would have widened the printing-noise merge of x to all of 0..3 ("line 3 repeats line 2").
      {"extra point very far away", t + "1e12,0,1\n", "line 22:", "is an extra point, apart from the grid"},
      {"extra point very far away in y", t + "0,-1e15,1\n", "line 22:", "is an extra point, apart from the grid"},
      {"extra point off the lattice", t + "1.5,0.25,1\n", "line 22:", "off the regular grid"},
      {"NaN", replace_line(t, 7, "1,0.5,nan"), "line 7:", "not finite"},
      {"inf", replace_line(t, 7, "1,0.5,-inf"), "line 7:", "not finite"},
      {"overflow", replace_line(t, 7, "1,0.5,1e999"), "line 7:", "not finite"},
      {"non-numeric", replace_line(t, 8, "2,0.5,abc"), "line 8:", "'abc' is not a number"},
      {"decimal comma", replace_line(t, 8, "2,0.5,1,5"), "line 8:", "4 values, the header has 3"},
      {"empty cell", replace_line(t, 8, "2,,1"), "line 8:", "not a number"},
      {"too few cells", replace_line(t, 5, "3 0 3"), "line 5:", "1 values"},
      {"unknown column", small_table("x_mm,y_mm,Bq_mT"), "line 1:", "unknown column 'Bq_mT'"},
      {"unknown unit", small_table("x_mm,y_mm,Bz_G"), "line 1:", "unknown column 'Bz_G'"},
      {"mixed coordinate units", small_table("x_mm,y_m,Bz_mT"), "line 1:", "mixes units"},
      {"mixed field units", "x_mm,y_mm,Bz_T,Bx_mT,By_mT\n0,0,1,1,1\n", "line 1:", "mixes units"},
      {"duplicate column", "x_mm,x_mm,Bz_T\n", "line 1:", "appears twice"},
      {"no Bz column", "x_mm,y_mm,Bx_T\n", "line 1:", "no Bz column"},
      {"Bx without By", "x_mm,y_mm,Bz_T,Bx_T\n", "line 1:", "Bx but no By"},
      {"no header row", "# comment\n0,0,1\n1,0,1\n", "line 2:", "expected the header row"},
      {"empty file", "", "is empty", "header row"},
      {"only comments", "# a\n% b\n\n", "is empty", "header row"},
      {"header only", "# c\nx_mm,y_mm,Bz_T\n", "no data rows", "t.csv"},
      {"one y level", "x_mm,y_mm,Bz_T\n0,0,1\n1,0,1\n2,0,1\n", "all rows have y = 0", "at least 2 x 2"},
  };
  for (const auto& b : bad) {
    CAPTURE(b.what, b.text);
    const std::string msg = parse_error(b.text);
    CAPTURE(msg);
    CHECK(contains(msg, "table t.csv"));
    CHECK(contains(msg, b.expect1));
    CHECK(contains(msg, b.expect2));
    CHECK(msg.find('\n') == std::string::npos);
  }
  SECTION("huge sizes: rows spanning a grid beyond the node limit, too many rows, too many bytes") {
    // 5000 points on a diagonal: no extra point, but a 5000 x 5000 grid (25 M nodes > 16.8 M).
    std::string diag = "x_mm,y_mm,Bz_T\n";
    for (int i = 0; i < 5000; ++i) diag += std::to_string(i) + "," + std::to_string(i) + ",1\n";
    const std::string msg = parse_error(diag);
    CAPTURE(msg);
    CHECK(contains(msg, "span a grid of 5000 x 5000 x 1 nodes: allowed at most 16777216"));
    FieldTableLimits small;
    small.max_nodes = 10;
    CHECK(contains(parse_error(small_table(), small), "line 12: more than 10 data rows"));
    const auto dir = scratch();
    write_text(dir / "t.csv", small_table());
    small.max_bytes = 50;
    try {
      read_field_table(dir / "t.csv", 4.55, small);
      FAIL("no size error");
    } catch (const InputError& e) {
      CHECK(contains(e.what(), "bytes: allowed at most 50"));
    }
    fs::remove_all(dir);
  }
  SECTION("factory: missing file, empty name, a single plane away from z_s, too few nodes for cubic") {
    const Config cfg(common_keys());
    const auto dir = scratch();
    CHECK_THROWS_WITH(make_field_source("table:", cfg), Catch::Contains("needs a file"));
    CHECK_THROWS_WITH(make_field_source("table:" + (dir / "none.csv").string(), cfg),
                      Catch::Contains("does not exist"));
    write_text(dir / "z1.csv", "x_mm,y_mm,z_mm,Bz_T\n0,0,1,1\n1,0,1,1\n0,1,1,1\n1,1,1,1\n");
    CHECK_THROWS_WITH(make_field_source("table:" + (dir / "z1.csv").string(), cfg),
                      Catch::Contains("one plane at z = 1 mm but the sensing plane is z_s = 4.55 mm"));
    write_text(dir / "three.csv", "x_mm,y_mm,Bz_T\n0,0,1\n1,0,1\n2,0,1\n0,1,1\n1,1,1\n2,1,1\n0,2,1\n1,2,1\n2,2,1\n");
    FieldOptions cubic;
    CHECK_THROWS_WITH(make_field_source("table:" + (dir / "three.csv").string(), cfg, cubic),
                      Catch::Contains("too few for --interp cubic"));
    write_text(dir / "small.csv", small_table());
    FieldOptions linear;
    linear.interp = Interp::Linear;
    const auto f = make_field_source("table:" + (dir / "small.csv").string(), cfg, linear);
    CHECK(f->Bz_T(Vec3(1.5, 0.75, 4.55)) == Approx(1e-3 * (1.5 + 7.5)));  // Bz = x + 10 y is linear: exact
    fs::remove_all(dir);
  }
}

namespace {
struct Run {
  int code;
  std::string err;
};
Run run_cmd(const std::string& cmd, const fs::path& dir) {
  const int rc = std::system((cmd + " >" + (dir / "stdout.txt").string() + " 2>" + (dir / "err.txt").string()).c_str());
  std::ifstream e(dir / "err.txt");
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, std::string((std::istreambuf_iterator<char>(e)), {})};
}
}  // namespace

TEST_CASE("error_spectrum --field table: and table_to_vti", "[fields][cli]") {
  const Config cfg(common_keys());
  const auto dir = scratch();
  const std::string bin = MAGENC_BIN_DIR;
  FieldTableFormat f;
  f.separator = '\t';
  f.with_z = false;
  const GridData plane = sample_exact(cfg, false, false);
  write_text(dir / "plane.tsv", shuffle_rows(field_table_text(plane, f), 3));
  // error_spectrum: table: and analytic agree (cubic, h = 0.05 mm: 1e-5 deg, as above).
  REQUIRE(run_cmd(bin + "/error_spectrum --field table:" + (dir / "plane.tsv").string() + " --dx 0.1 --out " +
                      (dir / "table.csv").string(), dir).code == 0);
  REQUIRE(run_cmd(bin + "/error_spectrum --field analytic --dx 0.1 --out " + (dir / "exact.csv").string(), dir).code == 0);
  // Column col of the first row of an error_spectrum CSV (throws when missing: the test fails).
  auto column = [&](const std::string& file, const std::string& col) {
    return test::read_csv(dir / file).at(0).at(col);
  };
  CHECK(column("table.csv", "field") == "table");
  CHECK(std::abs(std::stod(column("table.csv", "c1_deg")) - std::stod(column("exact.csv", "c1_deg"))) < 1e-5);
  CHECK(std::abs(std::stod(column("table.csv", "c3_deg")) - std::stod(column("exact.csv", "c3_deg"))) < 1e-5);
  // A bad table: one line, exit 2, no output.
  write_text(dir / "bad.csv", small_table("x_mm,y_m,Bz_mT"));
  Run r = run_cmd(bin + "/error_spectrum --field table:" + (dir / "bad.csv").string() + " --out " +
                      (dir / "bad_out.csv").string(), dir);
  CHECK(r.code == 2);
  CHECK(contains(r.err, "mixes units"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "bad_out.csv"));

  // table_to_vti: --help, conversion (read back equal), default --out name, bad table.
  CHECK(run_cmd(bin + "/table_to_vti --help", dir).code == 0);
  REQUIRE(run_cmd(bin + "/table_to_vti --table " + (dir / "plane.tsv").string() + " --out " +
                      (dir / "plane.vti").string(), dir).code == 0);
  const GridData back = read_grid_vti(dir / "plane.vti");
  CHECK(back.dims == plane.dims);
  CHECK(back.has_B());
  CHECK((back.origin_mm - plane.origin_mm).norm() < 1e-12);
  double worst = 0;
  for (std::size_t i = 0; i < back.nodes(); ++i)
    worst = std::max({worst, std::abs(back.Bz_T[i] - plane.Bz_T[i]), std::abs(back.Bx_T[i] - plane.Bx_T[i])});
  CHECK(worst < 1e-12);
  write_text(dir / "small.csv", small_table());
  REQUIRE(run_cmd(bin + "/table_to_vti --table " + (dir / "small.csv").string(), dir).code == 0);
  CHECK(fs::exists(dir / "small.vti"));
  r = run_cmd(bin + "/table_to_vti --table " + (dir / "bad.csv").string() + " --out " + (dir / "bad.vti").string(), dir);
  CHECK(r.code == 2);
  CHECK(contains(r.err, "table " + (dir / "bad.csv").string() + " line 1:"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "bad.vti"));
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename().string().find(".tmp.") == std::string::npos);
  r = run_cmd(bin + "/table_to_vti", dir);  // --table is required
  CHECK(r.code == 2);
  fs::remove_all(dir);
}

TEST_CASE("tables in other units than their header claims are refused, naming the column and the range",
          "[fields][bad-input]") {
  // small_table(): Bz = x + 10 y in mT on x 0..3 mm, y 0..2 mm.
  auto scaled = [](const std::string& header, double coord, double field, double at_origin = 0) {
    std::string t = header + "\n";
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 4; ++i) {
        const double b = (i == 0 && j == 0) ? at_origin : field * (i + 5 * j);
        t += std::to_string(coord * i) + "," + std::to_string(coord * 0.5 * j) + "," + std::to_string(b) + "\n";
      }
    return t;
  };
  struct Bad {
    std::string what, text, expect1, expect2;
  };
  const std::vector<Bad> bad = {
      {"all zero", scaled("x_mm,y_mm,Bz_T", 1, 0), "every field value is zero", "above 0"},
      {"one 1e300 node", scaled("x_mm,y_mm,Bz_mT", 1, 1, 1e300), "column 'Bz_mT' holds |B| = 1e+300 mT",
       "between 1 mT and 1 T"},
      {"tesla under Bz_mT", scaled("x_mm,y_mm,Bz_mT", 1, 1e-3), "largest |B| of the table is 0.023 mT",
       "values in T under a mT header?"},
      {"mT under Bz_T", scaled("x_mm,y_mm,Bz_T", 1, 1), "column 'Bz_T' holds |B| = 23 T", "values in mT under a T header?"},
      {"mm under x_m", scaled("x_m,y_m,Bz_mT", 1, 1), "the grid spans 3000 mm in x (read in m)",
       "coordinates in mm under a m header"},
      {"m under x_mm", scaled("x_mm,y_mm,Bz_mT", 5e-4, 1), "the grid spacing in x is 0.0005 mm",
       "coordinates in m under a mm header"},
  };
  for (const auto& b : bad) {
    CAPTURE(b.what, b.text);
    const std::string msg = parse_error(b.text);
    CAPTURE(msg);
    CHECK(contains(msg, "table t.csv: "));
    CHECK(contains(msg, b.expect1));
    CHECK(contains(msg, b.expect2));
    CHECK(contains(msg, "allowed"));
    CHECK(msg.find('\n') == std::string::npos);
  }
  // Realistic encoder fields, largest |B| 1.5 to 500 mT: tesla under Bz_mT and mT under Bz_T are refused
  // over the whole range, each in its right unit is read.
  for (const double largest_mT : {1.5, 5.0, 20.0, 50.0, 100.0, 200.0, 500.0}) {
    CAPTURE(largest_mT);
    const double per = largest_mT / 23;  // small_table's largest x + 5 y is 23
    const std::string t_under_mT = parse_error(scaled("x_mm,y_mm,Bz_mT", 1, per * 1e-3));
    CHECK(contains(t_under_mT, "values in T under a mT header?"));
    const std::string mT_under_T = parse_error(scaled("x_mm,y_mm,Bz_T", 1, per));
    CHECK(contains(mT_under_T, "values in mT under a T header?"));
    CHECK(parse_error(scaled("x_mm,y_mm,Bz_mT", 1, per)).empty());
    CHECK(parse_error(scaled("x_mm,y_mm,Bz_T", 1, per * 1e-3)).empty());
  }
  // Near the edges is allowed: |B| of 1 mT and 1 T, a 990 mm grid, a 0.002 mm spacing; trailing separators.
  CHECK(parse_error(scaled("x_mm,y_mm,Bz_T", 1, 1e-3 / 23)).empty());
  CHECK(parse_error(scaled("x_mm,y_mm,Bz_T", 1, 1.0 / 23)).empty());
  // A legitimate table outside the window (points at a magnet's face, 1.3 T; a weak field, 0.4 mT) is read
  // with the window of checks.largest_field_max_T / checks.largest_field_min_mT, and refused without it.
  CHECK(contains(parse_error(scaled("x_mm,y_mm,Bz_T", 1, 1.3 / 23)), "raise checks.largest_field_max_T"));
  CHECK(contains(parse_error(scaled("x_mm,y_mm,Bz_mT", 1, 0.4 / 23)), "lower checks.largest_field_min_mT"));
  FieldTableLimits wide;
  wide.largest_field_max_T = 2;
  wide.largest_field_min_T = 1e-4;
  CHECK(parse_error(scaled("x_mm,y_mm,Bz_T", 1, 1.3 / 23), wide).empty());
  CHECK(parse_error(scaled("x_mm,y_mm,Bz_mT", 1, 0.4 / 23), wide).empty());
  Config cfg(common_keys());
  cfg.set("checks.largest_field_max_T=2");
  cfg.set("checks.largest_field_min_mT=0.1");
  CHECK(field_table_limits(cfg).largest_field_max_T == 2);
  CHECK(field_table_limits(cfg).largest_field_min_T == Approx(1e-4).epsilon(1e-15));
  cfg.set("checks.largest_field_min_mT=3000");
  CHECK_THROWS_WITH(field_table_limits(cfg), Catch::Contains("checks.largest_field_min_mT = 3000 mT is out of range"));
  CHECK(parse_error(scaled("x_m,y_m,Bz_mT", 0.33, 1)).empty());
  CHECK(parse_error(scaled("x_mm,y_mm,Bz_mT", 4e-3, 1)).empty());
  CHECK(parse_error(test::trailing_separators(test::european(small_table()), ';', 2)).empty());
}
