// Field files as other tools write them (src/fields/field_table.*, docs/interfaces.md "Field files as other tools
// write them"): COMSOL's spreadsheet export and Ansys Maxwell's grid export (.fld), written here from the
// exact field (AnalyticField) on a grid, the way those tools write them (the test's own writers, not the
// library's), then read by `table:`.
//  1. Each file gives the grid of the same samples written in magenc's own table format (17 digits): nodes
//     to 1e-9 mm, values to their printed digits (12 for COMSOL, 15 for Ansys: <= 1e-11 T for |B| < 1 T).
//     So the spectra through the file equal those through the native table to rounding (1e-9 deg), and
//     reproduce the exact spectra within the interpolation error of the grid: cubic interpolation at
//     h = 0.05 mm, O(h^4), the bound of the native table's test (1e-5 deg for c1..c4 on the plane, 1e-4 deg
//     with dz and tilts on the 3-D box, h_z = 0.05 mm).
//  2. Bad files, one class each: a one-line InputError naming the file, the line and what was missing.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/errors.hpp"
#include "fields/analytic_field.hpp"
#include "fields/field_factory.hpp"
#include "fields/field_table.hpp"
#include "fields/magnet.hpp"
#include "probe/angle_error.hpp"
#include "probe/common_keys.hpp"
#include "support/spectrum_compare.hpp"

using namespace magenc;
namespace fs = std::filesystem;

namespace {

std::string g_fmt(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// Node (i, j, k) of a grid: position (mm) and B (T).
struct Node {
  Vec3 p;
  Vec3 B;
};
template <class F>
void for_nodes(const GridData& g, F f) {
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::size_t id = std::size_t(i) + std::size_t(g.dims[0]) * (std::size_t(j) + std::size_t(g.dims[1]) * k);
        const Vec3 p = g.origin_mm + Vec3(i * g.spacing_mm.x(), j * g.spacing_mm.y(), g.is_plane() ? 0.0 : k * g.spacing_mm.z());
        f(Node{p, Vec3(g.has_B() ? g.Bx_T[id] : 0.0, g.has_B() ? g.By_T[id] : 0.0, g.Bz_T[id])});
      }
}

// COMSOL 6 "Export > Data", spreadsheet format, grid points: '%' header lines, the length unit, the column
// names with their unit in parentheses, rows separated by runs of blanks (12 significant digits).
std::string comsol_text(const GridData& g, const std::string& length_unit, bool millitesla, bool vector) {
  const double ls = length_unit == "m" ? 1e-3 : 1.0, bs = millitesla ? 1e3 : 1.0;
  const std::string u = millitesla ? " (mT)" : " (T)";
  std::string t = "% Model:              encoder_magnet.mph\n% Version:            COMSOL 6.2.0.290\n"
                  "% Date:               Nov 25 2026, 21:40\n% Dimension:          3\n% Nodes:              " +
                  std::to_string(g.nodes()) + "\n% Expressions:        " + (vector ? "3" : "1") +
                  "\n% Description:        Magnetic flux density\n% Length unit:        " + length_unit + "\n";
  t += "% x                       y                        z                        ";
  t += vector ? "mf.Bx" + u + "               mf.By" + u + "               mf.Bz" + u + "\n" : "mf.Bz" + u + "\n";
  for_nodes(g, [&](const Node& n) {
    std::string row;
    for (int d = 0; d < 3; ++d) row += g_fmt(n.p[d] * ls, 12) + "    ";
    if (vector) row += g_fmt(n.B.x() * bs, 12) + "    " + g_fmt(n.B.y() * bs, 12) + "    ";
    t += row + g_fmt(n.B.z() * bs, 12) + "\n";
  });
  return t;
}

// Ansys Maxwell "Fields > Calculator > Export" on a grid (.fld): rows in metres and tesla, 15 digits.
// aedt: the one-line header of AEDT ("Grid Output Min: [..mm] Max: [..] Grid Size: [..]") and the quantity
// line; else the three lines of Maxwell 16 (Min:, Max:, Grid Size: in metres) and no quantity line.
std::string ansys_text(const GridData& g, bool aedt, bool vector) {
  const Vec3 lo = g.origin_mm;
  const Vec3 hi = lo + Vec3((g.dims[0] - 1) * g.spacing_mm.x(), (g.dims[1] - 1) * g.spacing_mm.y(),
                            g.is_plane() ? 0.0 : (g.dims[2] - 1) * g.spacing_mm.z());
  const Vec3 h(g.spacing_mm.x(), g.spacing_mm.y(), g.is_plane() ? 0.0 : g.spacing_mm.z());
  std::string t;
  auto triplet = [&](const Vec3& v, bool mm) {
    std::string s;
    for (int d = 0; d < 3; ++d) {  // appended piece by piece: GCC 12 -Wrestrict false positive (GCC bug 105651)
      if (d) s += ' ';
      s += mm ? g_fmt(v[d], 12) + "mm" : g_fmt(v[d] * 1e-3, 15);
    }
    return s;
  };
  if (aedt) {
    t = "Grid Output Min: [" + triplet(lo, true) + "] Max: [" + triplet(hi, true) + "] Grid Size: [" + triplet(h, true) + "]\n";
    t += vector ? "X,Y,Z,Vector data \"<Bx,By,Bz>\"\n" : "X,Y,Z,Scalar data \"Bz\"\n";
  } else {
    t = "Min: " + triplet(lo, false) + "\nMax: " + triplet(hi, false) + "\nGrid Size: " + triplet(h, false) + "\n\n";
  }
  for_nodes(g, [&](const Node& n) {
    std::string row;
    for (int d = 0; d < 3; ++d) row += g_fmt(n.p[d] * 1e-3, 15) + " ";
    if (vector) row += g_fmt(n.B.x(), 15) + " " + g_fmt(n.B.y(), 15) + " ";
    t += row + g_fmt(n.B.z(), 15) + "\n";
  });
  return t;
}

fs::path scratch() {
  auto d = fs::temp_directory_path() / ("magenc_test_field_files_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

// Largest differences of two grids of the same dims: nodes (mm) and values (T).
std::pair<double, double> grid_difference(const GridData& a, const GridData& b) {
  double dp = (a.origin_mm - b.origin_mm).norm(), db = 0;
  for (int d = 0; d < 3; ++d)
    if (a.dims[d] > 1) dp = std::max(dp, (a.dims[d] - 1) * std::abs(a.spacing_mm[d] - b.spacing_mm[d]));
  for (std::size_t i = 0; i < a.nodes(); ++i) {
    db = std::max(db, std::abs(a.Bz_T[i] - b.Bz_T[i]));
    if (a.has_B()) db = std::max({db, std::abs(a.Bx_T[i] - b.Bx_T[i]), std::abs(a.By_T[i] - b.By_T[i])});
  }
  return {dp, db};
}

std::string parse_error(const std::string& text) {
  try {
    parse_field_table(text, "f.txt", 4.55);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("COMSOL and Ansys exports of the exact field reproduce the exact spectra", "[fields][cross-check]") {
  const Config cfg(common_keys());
  const AnalyticField exact(Magnet::from_config(cfg));
  const double zs = sensing_plane_z_mm(cfg);
  // h = 0.05 mm over [-3.5, 3.5] mm; the box spans z_s +- 0.15 mm (as the native table's test).
  const GridData plane = sample_grid(exact, Vec3(-3.5, -3.5, zs), Vec3(0.05, 0.05, 0.05), {141, 141, 1}, true);
  const GridData box = sample_grid(exact, Vec3(-3.5, -3.5, zs - 0.15), Vec3(0.05, 0.05, 0.05), {141, 141, 7});
  const auto dir = scratch();
  FieldTableFormat native;
  write_text(dir / "plane_native.csv", field_table_text(plane, native));
  write_text(dir / "box_native.csv", field_table_text(box, native));
  struct File {
    std::string name, text;
    bool is_box;
  };
  const std::vector<File> files = {
      {"plane_comsol_mm_T.txt", comsol_text(plane, "mm", false, false), false},
      {"plane_comsol_m_mT.txt", comsol_text(plane, "m", true, false), false},
      {"plane_maxwell16_bz.fld", ansys_text(plane, false, false), false},
      {"plane_aedt_bz.fld", ansys_text(plane, true, false), false},
      {"box_comsol_B.txt", comsol_text(box, "mm", false, true), true},
      {"box_aedt_B.fld", ansys_text(box, true, true), true},
      {"box_maxwell16_B.fld", ansys_text(box, false, true), true},
  };
  FieldOptions cubic;
  cubic.interp = Interp::Cubic;
  const auto plane_native = make_field_source("table:" + (dir / "plane_native.csv").string(), cfg, cubic);
  const auto box_native = make_field_source("table:" + (dir / "box_native.csv").string(), cfg, cubic);
  for (const File& f : files) {
    CAPTURE(f.name);
    double worst_exact = 0, worst_native = 0;  // |c_n(file) - c_n(exact)|, |c_n(file) - c_n(native table)|
    write_text(dir / f.name, f.text);
    const GridData& truth = f.is_box ? box : plane;
    const GridData g = read_field_table(dir / f.name, zs);
    REQUIRE(g.dims == truth.dims);
    REQUIRE(g.has_B() == truth.has_B());
    const auto [dp, db] = grid_difference(g, truth);
    CHECK(dp < 1e-9);   // mm: coordinates printed with 12 (COMSOL) or 15 (Ansys) digits
    CHECK(db < 1e-11);  // T: |B| < 0.7 T printed with 12 or 15 digits
    const auto field = make_field_source("table:" + (dir / f.name).string(), cfg, cubic);
    const FieldSource& reference = f.is_box ? *box_native : *plane_native;
    for (const std::string array : {"two", "diff4"}) {
      ProbeSetup setup;
      setup.array = ProbeArray::parse(array);
      setup.plane_z_mm = zs;
      test::compare_spectra_per_eccentricity(exact, *field, setup, 0.1, [&](const std::string& off, const Spectrum& se,
                                                                            const Spectrum& sf) {
        const Mount m = [&] {
          Mount x;
          (off == "sx" ? x.sx_mm : off == "sy" ? x.sy_mm : off == "dx" ? x.dx_mm : x.dy_mm) = 0.1;
          return x;
        }();
        const Spectrum sn = error_spectrum(reference, setup, m);
        CHECK(std::abs(sf.a0_deg - se.a0_deg) < 1e-5);
        for (int n = 1; n <= 4; ++n) {
          CAPTURE(array, off, n, se.c_deg[n], sf.c_deg[n], sn.c_deg[n]);
          CHECK(std::abs(sf.c_deg[n] - sn.c_deg[n]) < 1e-9);  // the same grid: rounding only
          CHECK(std::abs(sf.c_deg[n] - se.c_deg[n]) < 1e-5);  // the grid's interpolation error
          worst_exact = std::max(worst_exact, std::abs(sf.c_deg[n] - se.c_deg[n]));
          worst_native = std::max(worst_native, std::abs(sf.c_deg[n] - sn.c_deg[n]));
        }
      });
    }
    WARN(f.name << ": grid vs written " << dp << " mm, " << db << " T; c1..c4 vs exact " << worst_exact
                << " deg, vs the native table " << worst_native << " deg");
    if (!f.is_box) continue;
    // The 3-D files serve dz and tilts (the full vector off the plane): within 1e-4 deg of the exact field.
    ProbeSetup setup;
    setup.array = ProbeArray::parse("two");
    setup.plane_z_mm = zs;
    Mount dz, tilt, magnet_tilt;
    dz.dx_mm = 0.1;
    dz.dz_mm = 0.1;
    tilt.tilt_x_deg = 1.0;
    magnet_tilt.magnet_tilt_deg = 1.0;
    for (const Mount& m : {dz, tilt, magnet_tilt}) {
      const Spectrum se = error_spectrum(exact, setup, m), sf = error_spectrum(*field, setup, m);
      for (int n = 1; n <= 4; ++n) {
        CAPTURE(m.dz_mm, m.tilt_x_deg, m.magnet_tilt_deg, n, se.c_deg[n], sf.c_deg[n]);
        CHECK(std::abs(sf.c_deg[n] - se.c_deg[n]) < 1e-4);
      }
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("bad COMSOL and Ansys files: one line saying what was missing", "[fields][bad-input]") {
  const std::string comsol_head = "% Model: m.mph\n% Length unit: mm\n% x  y  z  mf.Bz (T)\n";
  const std::string comsol_rows = "0 0 4.55 0.1\n1 0 4.55 0.2\n0 1 4.55 0.3\n1 1 4.55 0.4\n";
  const std::string fld_head = "Min: 0 0 0.00455\nMax: 0.001 0.001 0.00455\nGrid Size: 0.001 0.001 0\n\n";
  const std::string fld_rows = "0 0 0.00455 0.1\n0.001 0 0.00455 0.2\n0 0.001 0.00455 0.3\n0.001 0.001 0.00455 0.4\n";
  // The good ones parse: a 2 x 2 plane at z = 4.55 mm.
  CHECK(parse_field_table(comsol_head + comsol_rows, "f.txt", 4.55).Bz_T == std::vector<double>{0.1, 0.2, 0.3, 0.4});
  CHECK(parse_field_table(fld_head + fld_rows, "f.txt", 4.55).Bz_T == std::vector<double>{0.1, 0.2, 0.3, 0.4});
  // A COMSOL file with tabs between the values and blanks in its column line; mT; 2-D (no z column).
  const GridData tabs = parse_field_table(
      "% Length unit: m\n% x   y   mf.Bz (mT)\n0\t0\t100\n0.001\t0\t200\n0\t0.001\t300\n0.001\t0.001\t400\n",
      "f.txt", 4.55);
  CHECK(tabs.Bz_T == std::vector<double>{0.1, 0.2, 0.3, 0.4});
  CHECK(tabs.spacing_mm.x() == Approx(1.0));
  CHECK(tabs.origin_mm.z() == 4.55);
  auto replace = [](std::string s, const std::string& what, const std::string& with) {
    const auto p = s.find(what);
    REQUIRE(p != std::string::npos);
    return s.replace(p, what.size(), with);
  };
  struct Bad {
    std::string what, text, expect1, expect2;
  };
  const std::string good_comsol = comsol_head + comsol_rows, good_fld = fld_head + fld_rows;
  const std::vector<Bad> bad = {
      {"COMSOL: no length unit", replace(good_comsol, "% Length unit: mm\n", ""), "line 2:", "no '% Length unit:' line"},
      {"COMSOL: unknown length unit", replace(good_comsol, "unit: mm", "unit: ft"), "line 3:", "length unit 'ft'"},
      {"COMSOL: unknown column", replace(good_comsol, "mf.Bz (T)", "mf.normB (T)"), "line 3:",
       "unknown column 'mf.normB (T)'"},
      {"COMSOL: field without unit", replace(good_comsol, "mf.Bz (T)", "mf.Bz"), "line 3:", "'mf.Bz' has no unit"},
      {"COMSOL: field in gauss", replace(good_comsol, "(T)", "(G)"), "line 3:", "allowed T or mT"},
      {"COMSOL: no column line", replace(good_comsol, "% x  y  z  mf.Bz (T)\n", "% Description: B\n"), "line 3:",
       "does not name the columns"},
      {"COMSOL: no Bz", replace(good_comsol, "mf.Bz (T)", "mf.Bx (T)"), "line 3:", "no Bz column"},
      {"COMSOL: ragged row", replace(good_comsol, "1 0 4.55 0.2", "1 0 4.55"), "line 5:", "3 values, the header has 4"},
      {"COMSOL: non-finite value", replace(good_comsol, "0.3", "NaN"), "line 6:", "not finite"},
      {"COMSOL: not a grid", replace(good_comsol, "1 1 4.55", "1.5 1 4.55"), "line 7:", "off the regular grid"},
      {"Ansys: no Grid Size", replace(good_fld, "Grid Size: 0.001 0.001 0\n", ""), "no 'Grid Size:' line", "f.txt"},
      {"Ansys: no Min", replace(good_fld, "Min: 0 0 0.00455\n", ""), "no 'Min:' line", "f.txt"},
      {"Ansys: rows in mm, header in m", fld_head + "0 0 4.55 0.1\n1 0 4.55 0.2\n0 1 4.55 0.3\n1 1 4.55 0.4\n",
       "cannot tell the unit of the rows", "Min/Max x"},
      {"Ansys: header spacing differs", replace(good_fld, "Grid Size: 0.001 0.001", "Grid Size: 0.0005 0.001"),
       "Grid Size says 0.5 mm", "spacing in x"},
      {"Ansys: bad triplet", replace(good_fld, "Max: 0.001 0.001 0.00455", "Max: 0.001 0.001"), "line 2:",
       "'Max:' is followed by ' 0.001 0.001'"},
      {"Ansys: H, not B", replace(good_fld, "\n\n", "\nX,Y,Z,Vector data \"<Hx,Hy,Hz>\"\n"), "line 4:",
       "allowed the real B vector"},
      {"Ansys: complex data", replace(good_fld, "\n\n", "\nX,Y,Z,Complex data \"Bz\"\n"), "line 4:", "complex data"},
      {"Ansys: five columns", replace(good_fld, "0 0 0.00455 0.1\n", "0 0 0.00455 0.1 7\n"), "line 5:",
       "5 values: allowed x y z (m) and Bz"},
      {"Ansys: ragged row", replace(good_fld, "0.001 0 0.00455 0.2", "0.001 0 0.00455"), "line 6:",
       "3 values, the header has 4"},
      {"Ansys: non-finite value", replace(good_fld, "0.3", "inf"), "line 7:", "not finite"},
      {"Ansys: stray line", replace(good_fld, "\n\n", "\nhello\n"), "line 4:", "neither a grid header"},
      {"Ansys: rows separated by ','", fld_head + "0,0,0.00455,0.1\n0.001,0,0.00455,0.2\n", "line 5:",
       "separates its values by ','"},
      {"COMSOL: 'Length unit: m' with mm numbers", "% Length unit: m\n% x y mf.Bz (T)\n0 0 0.1\n5 0 0.2\n0 5 0.3\n5 5 0.4\n",
       "the grid spans 5000 mm in x (read in m)", "coordinates in mm under a m header"},
      {"Ansys: header only", fld_head, "no data rows", "f.txt"},
      {"table: decimal comma between ',' separators", "x_mm,y_mm,Bz_T\n0,0,0,1\n", "line 2:",
       "4 values, the header has 3 columns: allowed one number per column; a decimal comma"},
      {"table: ';' form with a non-finite value", "x_mm;y_mm;Bz_T\n0;0;0,1\n1;0;inf\n", "line 3:", "not finite"},
      {"table: number header", "% just a comment\n# another\n0 0 1\n", "line 3:", "expected the header row"},
  };
  for (const auto& b : bad) {
    CAPTURE(b.what, b.text);
    const std::string msg = parse_error(b.text);
    CAPTURE(msg);
    CHECK(msg.find("table f.txt") != std::string::npos);
    CHECK(msg.find(b.expect1) != std::string::npos);
    CHECK(msg.find(b.expect2) != std::string::npos);
    CHECK(msg.find("allowed") != std::string::npos);
    CHECK(msg.find('\n') == std::string::npos);
  }
}
