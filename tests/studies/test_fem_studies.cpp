// End-to-end tests of the FEM-driven probe studies: real_field, airgap and
// harmonic_provenance as tiny-config smoke runs, and error_spectrum with --field fem:DIR / grid:DIR/box.vti (dz != 0),
// all against a COARSE solve made here: meshes/coarse.toml with fem.order = 2
// and magnet.mu_r = 1 (so the exact field is the reference), ~17k tets, ~1 s.
//
// Tolerance for FEM vs exact on this coarse mesh (measured before setting it,
// r0 = 2.4, `two`, 360 steps; cases dx 0.1, dy 0.1, sx 0.1, dx 0.1 with
// dz = +-0.3 and -0.45, sx = dx = 0.05 with dz = 0.4): the largest
// |c1 - c1_exact| was 0.066 deg (fem) and 0.094 deg (grid, 0.25 mm box step),
// the largest |c3 - c3_exact| 0.079 deg (fem, dz = -0.45) and 0.048 deg (grid).
// The coarse mesh's own artefacts (ideal-mount harmonics up to ~0.3 deg in c4)
// set that scale. kCoarseTolDeg = 0.15 deg keeps a 1.6x margin over the worst
// measurement while still failing for a lost dz (c1 moves 0.165 deg from
// dz = -0.3 to +0.3), a wrong-sign offset (c1 and c3 of dx vs dy differ by
// 1.6 deg) or a field of the wrong magnet. c4 is not checked against exact here:
// on this mesh it is dominated by artefacts.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "support/study_test_util.hpp"

using namespace magenc::test;

namespace {

constexpr double kCoarseTolDeg = 0.15;

// solve_field on meshes/coarse.toml, order 2, mu_r = 1, plus `extra` settings, into temp_out(name).
// fem.tolerance 1e-10, as harmonic_provenance's in-process variants (fem_variant_config), which the
// provenance test compares with this solve to 1e-6 deg.
fs::path solve_coarse_config(const std::string& name, const std::string& extra) {
  const fs::path d = temp_out(name);
  const std::string cmd = std::string(MAGENC_BIN_DIR) + "/solve_field --config '" + MAGENC_SOURCE_DIR +
                          "/meshes/coarse.toml' --set fem.order=2 --set magnet.mu_r=1 --set fem.potential=total "
                          "--set fem.tolerance=1e-10 "
                          "--set output.mesh_vtu=true " + extra + " --out '" +
                          d.string() + "' >/dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("solve_field failed: " + cmd);
  return d;
}

// A coarse order-2, mu_r = 1 solve in a temp directory (made once per process). The total potential:
// these fields stand for FE solutions with discretization error (with mu_r = 1 the default reduced
// potential is the exact field).
const fs::path& coarse_field() {
  static const fs::path dir = solve_coarse_config("coarse_field", "");
  return dir;
}

// A finer solve (zone h 0.4 mm, D16 mesh; ~150k dofs, seconds) for checks of small
// differences of large harmonics, which the coarse field's discretization error
// (|c1 - exact| up to ~0.01-0.08 deg, varying between meshes) can swamp.
const fs::path& medium_field() {
  static const fs::path dir = solve_coarse_config(
      "medium_field", "--set mesh.h_zone_mm=0.4 --set mesh.h_magnet_mm=0.5 --set mesh.symmetry_order=16");
  return dir;
}

// Runs error_spectrum with the given arguments; spectra rows (header + rows) or empty on failure.
struct CliRun {
  int code;
  std::string err;
  std::vector<std::map<std::string, std::string>> rows;
};
CliRun error_spectrum(const std::string& args) {
  const fs::path out = temp_out("es_csv");
  const fs::path err = temp_out("es_err");
  const std::string cmd = std::string(MAGENC_BIN_DIR) + "/error_spectrum " + args + " --out '" + out.string() +
                          "' 2>'" + err.string() + "' >/dev/null";
  const int rc = std::system(cmd.c_str());
  CliRun r{WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(err), {}};
  if (fs::exists(out)) r.rows = read_csv(out);
  fs::remove(out);
  fs::remove(err);
  return r;
}

int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n + (!s.empty() && s.back() != '\n');
}

int count(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

// comparison.csv row of (array, sweep, x_mm, source, coef).
const std::map<std::string, std::string>* find_cmp(const std::vector<std::map<std::string, std::string>>& rows,
                                                   const std::string& array, const std::string& sweep, double x,
                                                   const std::string& source, const std::string& coef) {
  for (const auto& r : rows)
    if (r.at("array") == array && r.at("sweep") == sweep && std::abs(num(r, "x_mm") - x) < 1e-9 &&
        r.at("source") == source && r.at("coef") == coef)
      return &r;
  return nullptr;
}

}  // namespace

TEST_CASE("error_spectrum: fem:DIR and grid:DIR/box.vti with dz agree with the exact field on a coarse solve",
          "[studies][physics][cli]") {
  // The medium field: the dz effect on c1 checked below (0.165 deg between dz = -0.3 and
  // +0.3 mm) is a 7 % change of c1, and on the coarse field it came out 0.08-0.17 deg
  // depending on the mesh draw (Release vs Debug floating point gave different meshes).
  const fs::path dir = medium_field();
  const std::string cases = (temp_out("cases") += ".csv").string();
  {
    std::ofstream f(cases);
    f << "dx_mm,dy_mm,dz_mm\n0.1,0,0.3\n0.1,0,-0.3\n0,0.1,0.2\n";
  }
  const std::string common = " --array two --r0 2.4 --steps 360 --cases '" + cases + "'";
  const CliRun ex = error_spectrum("--field analytic" + common);
  REQUIRE(ex.code == 0);
  REQUIRE(ex.rows.size() == 3);
  for (const std::string& field : {"fem:" + dir.string(), "grid:" + (dir / "box.vti").string()}) {
    const CliRun r = error_spectrum("--field " + field + common);
    INFO(field << ": " << r.err);
    REQUIRE(r.code == 0);
    REQUIRE(r.rows.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(num(r.rows[i], "dz_mm") == Approx(num(ex.rows[i], "dz_mm")));
      for (const char* c : {"c1_deg", "c3_deg"}) {
        INFO("case " << i << " " << c << ": " << num(r.rows[i], c) << " vs exact " << num(ex.rows[i], c));
        CHECK(std::abs(num(r.rows[i], c) - num(ex.rows[i], c)) < kCoarseTolDeg);
      }
    }
    // dz moves c1 the exact field's way (exact: +0.165 deg from dz = -0.3 to +0.3).
    const double dc1 = num(r.rows[0], "c1_deg") - num(r.rows[1], "c1_deg");
    const double dc1_exact = num(ex.rows[0], "c1_deg") - num(ex.rows[1], "c1_deg");
    CHECK(dc1_exact > 0.1);
    CHECK(dc1 == Approx(dc1_exact).epsilon(0.3));
  }
  fs::remove(cases);
}

TEST_CASE("error_spectrum: tilts on fem:DIR and grid:DIR/box.vti agree with the exact field and plane.vti refuses them",
          "[studies][physics][bad-input][cli]") {
  // Tilted probes read n.B of the full vector off the sensing plane: the FE solution and the 3-D box serve
  // that, the 2-D plane grid does not. Cases (r0 2.4, `two`, 360 steps): sensor tilt_x 1 deg (exact: a0 -0.403,
  // c2 0.754), magnet tilt 1 deg at azimuth 0 (c1 2.476, c3 0.259) and at 90 deg with dx 0.05 (mixed).
  // Tolerance kCoarseTolDeg (0.15 deg, the coarse mesh's FEM-vs-exact scale set above) on a0, c1, c2, c3;
  // a wrong tilt sign moves a0 by 0.8 deg, an ignored magnet tilt c1 by 2.5 deg.
  const fs::path dir = coarse_field();
  const std::string cases = (temp_out("tilt_cases") += ".csv").string();
  {
    std::ofstream f(cases);
    f << "dx_mm,tilt_x_deg,magnet_tilt_deg,magnet_tilt_azimuth_deg\n0,1,0,0\n0,0,1,0\n0.05,0,1,90\n";
  }
  const std::string common = " --array two --r0 2.4 --steps 360 --cases '" + cases + "'";
  const CliRun ex = error_spectrum("--field analytic" + common);
  INFO(ex.err);
  REQUIRE(ex.code == 0);
  REQUIRE(ex.rows.size() == 3);
  CHECK(num(ex.rows[0], "tilt_x_deg") == 1.0);  // the tilt columns are written when a case is tilted
  CHECK(num(ex.rows[0], "a0_deg") == Approx(-0.403).margin(0.001));
  CHECK(num(ex.rows[1], "c1_deg") == Approx(2.476).margin(0.001));
  for (const std::string& field : {"fem:" + dir.string(), "grid:" + (dir / "box.vti").string()}) {
    const CliRun r = error_spectrum("--field " + field + common);
    INFO(field << ": " << r.err);
    REQUIRE(r.code == 0);
    REQUIRE(r.rows.size() == 3);
    for (std::size_t i = 0; i < 3; ++i)
      for (const char* c : {"a0_deg", "c1_deg", "c2_deg", "c3_deg"}) {
        const double got = num(r.rows[i], c), want = num(ex.rows[i], c);
        INFO("case " << i << " " << c << ": " << got << " vs exact " << want);
        WARN(field << " case " << i << " " << c << ": " << got << " vs exact " << want << " (diff " << got - want
                   << ")");
        CHECK(std::abs(got - want) < kCoarseTolDeg);
      }
  }
  const CliRun plane = error_spectrum("--field grid:" + (dir / "plane.vti").string() + common);
  INFO(plane.err);
  CHECK(plane.code != 0);
  CHECK(lines(plane.err) == 1);
  CHECK(plane.err.find("tilt_x_deg") != std::string::npos);
  CHECK(plane.rows.empty());
  fs::remove(cases);
}

TEST_CASE("magnetization elevation: FEM (quadrant solve, axial load) vs exact on a coarse solve", "[studies][physics][cli]") {
  // solve_field with magnet.magnetization_elevation_deg = 5: the quadrant solve adds the axial component as
  // a third load (even across both symmetry planes); solve.json records the solves and the elevation.
  // Exact: `two` c1 7.70 deg (a common offset on both probes), diff4 ~ 0. Tolerance kCoarseTolDeg.
  const fs::path dir = solve_coarse_config("coarse_elev5", "--set magnet.magnetization_elevation_deg=5");
  const std::string json = slurp(dir / "solve.json");
  CHECK(json.find("\"magnetization_elevation_deg\": 5") != std::string::npos);
  CHECK(json.find("\"solves\": 2") != std::string::npos);  // x and z components
  for (const char* array : {"two", "diff4"}) {
    const std::string common = std::string(" --array ") + array + " --r0 2.4 --steps 360 --set magnet.magnetization_elevation_deg=5";
    const CliRun ex = error_spectrum("--field analytic" + common);
    const CliRun fe = error_spectrum("--field fem:" + dir.string() + common);
    INFO(ex.err << fe.err);
    REQUIRE(ex.code == 0);
    REQUIRE(fe.code == 0);
    for (const char* c : {"a0_deg", "c1_deg", "c2_deg", "c3_deg"}) {
      const double got = num(fe.rows[0], c), want = num(ex.rows[0], c);
      WARN(array << " " << c << ": fem " << got << " vs exact " << want);
      CHECK(std::abs(got - want) < kCoarseTolDeg);
    }
    if (std::string(array) == "two") CHECK(num(ex.rows[0], "c1_deg") == Approx(7.70).margin(0.005));
  }
}

TEST_CASE("error_spectrum: a missing fem: directory is a one-line error", "[studies][bad-input][cli]") {
  const CliRun r = error_spectrum("--field fem:/nonexistent/field_dir --array two --r0 2.4");
  INFO(r.err);
  CHECK(r.code != 0);
  CHECK(lines(r.err) == 1);
  CHECK(r.rows.empty());
}

TEST_CASE("real_field study: tiny run on a coarse solve", "[studies][cli]") {
  const fs::path dir = coarse_field();
  const fs::path out = temp_out("real_field");
  const StudyRun r = run_study_exe("real_field", out,
                                   "--set fem_field.dir='" + dir.string() +
                                       "' --set sensor.steps=360 --set sweep.points=6 --set study.arrays=two,diff4");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"spectra.csv", "comparison.csv", "fits.csv", "summary.md", "config.toml", "run.json",
                          "eps.png", "harmonics.png", "coefficients_dx.png", "differences_dx.png",
                          "coefficients_sy.png"});
  CHECK(fs::file_size(out / "differences_dx.png") > 1000);
  // 2 arrays x 3 sources (grid, fem, exact) x (ideal + 4 offsets x 6 points).
  const auto rows = read_csv(out / "spectra.csv");
  CHECK(rows.size() == 2 * 3 * (1 + 4 * 6));
  const auto cmp = read_csv(out / "comparison.csv");
  for (const std::string src : {"grid", "fem"}) {
    INFO(src);
    const auto* c1 = find_cmp(cmp, "two", "dx", 0.1, src, "c1_deg");
    const auto* c3 = find_cmp(cmp, "two", "dx", 0.1, src, "c3_deg");
    REQUIRE(c1);
    REQUIRE(c3);
    CHECK(num(*c1, "exact_deg") == Approx(2.5088).margin(2e-3));  // exact field, 360 steps
    CHECK(num(*c1, "diff_deg") == Approx(num(*c1, "value_deg") - num(*c1, "exact_deg")).margin(1e-9));
    CHECK(std::abs(num(*c1, "diff_deg")) < kCoarseTolDeg);
    CHECK(std::abs(num(*c3, "diff_deg")) < kCoarseTolDeg);
    // diff4 cancels the 1st harmonic of dx on any field symmetric in y.
    const auto* d1 = find_cmp(cmp, "diff4", "dx", 0.1, src, "c1_deg");
    REQUIRE(d1);
    CHECK(std::abs(num(*d1, "value_deg")) < 1e-9);
  }
  // The acceptance table judges 4 offsets x 2 arrays x 2 sources x 4 coefficients, and the tally matches it.
  const std::string md = slurp(out / "summary.md");
  const int pass = count(md, "| pass |"), fail = count(md, "| **FAIL** |");
  CHECK(pass + fail == 64);
  CHECK(md.find("**Acceptance: " + std::to_string(pass) + " of 64 cells pass") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("airgap study: tiny run on a coarse solve", "[studies][cli]") {
  const fs::path dir = coarse_field();
  const fs::path out = temp_out("airgap");
  const StudyRun r = run_study_exe("airgap", out,
                                   "--set fem_field.dir='" + dir.string() +
                                       "' --set sensor.steps=360 --set dz_sweep.points=5 --set study.arrays=two,diff4");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"spectra.csv", "comparison.csv", "fits.csv", "summary.md", "eps.png", "coefficients_alone.png",
                          "coefficients_dx.png", "differences_sxdx.png"});
  const auto rows = read_csv(out / "spectra.csv");
  CHECK(rows.size() == 2 * 3 * 4 * 5);  // arrays x sources x cases x dz values
  // dz alone on the exact field: no error at any dz.
  int alone = 0;
  for (const auto& row : rows)
    if (row.at("source") == "exact" && row.at("sweep") == "dz alone") {
      ++alone;
      CHECK(num(row, "pp_deg") < 1e-9);
    }
  CHECK(alone == 2 * 5);
  // The 'dx' case: exact slopes at dz = 0 (p1 of the cubic, deg/mm) against the default-magnet values of
  // the airgap study (0.137, -0.137 at 3600 steps); every FEM value within the coarse tolerance of exact,
  // and c1 rising / c3 falling from dz = -0.5 to +0.5 as on the exact field. (FEM slopes themselves are
  // not compared: on this coarse mesh the artefacts change with dz and 5-point slopes of the FEM are off
  // by up to 85 % for c3 via grid; on the default mesh, this case, within 12 %: see the airgap summary.)
  const auto fits = read_csv(out / "fits.csv");
  auto slope = [&](const std::string& coef) {
    for (const auto& f : fits)
      if (f.at("field") == "analytic" && f.at("array") == "two" && f.at("sweep") == "dz with dx=0.05" &&
          f.at("coef") == coef)
        return num(f, "p1");
    FAIL("no fit of " << coef);
    return 0.0;
  };
  CHECK(slope("c1_deg") == Approx(0.137).margin(0.01));
  CHECK(slope("c3_deg") == Approx(-0.137).margin(0.01));
  const auto cmp = read_csv(out / "comparison.csv");
  for (const std::string src : {"fem", "grid"})
    for (const std::string coef : {"c1_deg", "c3_deg"}) {
      const auto* lo = find_cmp(cmp, "two", "dz with dx=0.05", -0.5, src, coef);
      const auto* hi = find_cmp(cmp, "two", "dz with dx=0.05", 0.5, src, coef);
      REQUIRE(lo);
      REQUIRE(hi);
      INFO(src << " " << coef << ": " << num(*lo, "value_deg") << " -> " << num(*hi, "value_deg") << ", exact "
               << num(*lo, "exact_deg") << " -> " << num(*hi, "exact_deg"));
      CHECK(std::abs(num(*lo, "diff_deg")) < kCoarseTolDeg);
      CHECK(std::abs(num(*hi, "diff_deg")) < kCoarseTolDeg);
      const double d = num(*hi, "value_deg") - num(*lo, "value_deg");
      const double d_exact = num(*hi, "exact_deg") - num(*lo, "exact_deg");
      CHECK(std::abs(d_exact) > 0.1);
      CHECK(d * d_exact > 0);
    }
  CHECK(slurp(out / "summary.md").find("dz alone gives no error at any dz") != std::string::npos);
  fs::remove_all(out);
}

// The study solves its FE variants in-process (field_solver/field_io/fem_variant.hpp); the variant "coarse P2" below has the
// settings of coarse_field() (coarse.toml, order 2, mu_r = 1), so both paths must give the same spectra: the
// in-process solve evaluated directly against fem:DIR (mesh.vtu written and read back), and its in-memory plane grid
// against DIR/plane.vti. Same mesh (TetGen is deterministic), same CG up to OpenMP summation order: agreement to
// 1e-6 deg, while P1 and P2 on this mesh differ by ~1.6 deg in pp (measured 2.64 vs 1.04 deg, symmetric mesh).
// The variants' dx harmonics are held to kCoarseTolDeg like the directory's (coarse P1 measured 0.082 in c1,
// 0.094 in c3).
TEST_CASE("harmonic_provenance study: FE variants solved in-process beside a coarse solve_field directory",
          "[studies][cli]") {
  const fs::path dir = coarse_field();
  const fs::path out = temp_out("harmonic_provenance");
  const std::string coarse = std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml";
  const StudyRun r = run_study_exe(
      "harmonic_provenance", out,
      "--set sensor.steps=360 --set provenance.spacings_mm=0.2,0.1 --set provenance.interps=nearest,cubic "
      "--set 'provenance.fem_variants=[{ label = \"coarse P1\", config = \"" + coarse + "\", set = { fem.order = 1 } }, "
      "{ label = \"coarse P2\", config = \"" + coarse + "\", set = { fem.order = 2 } }]' "
      "--set provenance.fem_dirs='" + dir.string() + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  check_files_exist(out, {"provenance.csv", "summary.md", "artefacts_vs_h.png", "ideal_harmonics.png", "fem_artefacts.png",
                          "run.json"});
  const auto rows = read_csv(out / "provenance.csv");
  // exact rows + cases x spacings x modes + 3 FE solutions x (direct + via plane grid) x cases.
  CHECK(rows.size() == 3 + 3 * 2 * 2 + 3 * 2 * 3);
  auto find = [&](const std::string& source, const std::string& variant, const std::string& c) {
    for (const auto& row : rows)
      if (row.at("source") == source && row.at("variant") == variant && row.at("case") == c) return &row;
    FAIL("no row " << source << " / " << variant << " / " << c);
    return static_cast<const std::map<std::string, std::string>*>(nullptr);
  };
  for (const auto& row : rows) {
    if (row.at("source") == "exact" && row.at("case") == "ideal") CHECK(num(row, "pp_deg") < 1e-9);
    // Cubic on a 0.1 mm grid: ideal-mount artefacts far below the nearest-neighbour ones.
    if (row.at("source") == "grid" && row.at("case") == "ideal" && row.at("interp") == "cubic")
      CHECK(num(row, "pp_deg") < 0.05);
  }
  const auto* exact_dx = find("exact", "exact", "dx=0.10");
  for (const std::string& v : std::vector<std::string>{"coarse P1", "coarse P2", dir.string()}) {
    INFO(v);
    const auto* fem_dx = find("fem", v, "dx=0.10");
    CHECK(std::abs(num(*fem_dx, "c1_deg") - num(*exact_dx, "c1_deg")) < kCoarseTolDeg);
    CHECK(std::abs(num(*fem_dx, "c3_deg") - num(*exact_dx, "c3_deg")) < kCoarseTolDeg);
    // Ideal mount: the FE solution's own harmonics are numerical, non-zero on these meshes.
    CHECK(num(*find("fem", v, "ideal"), "pp_deg") > 1e-6);
    CHECK(find("fem_grid", v + " via plane grid", "ideal")->at("interp") == "cubic");
  }
  // In-process solve == solve_field + fem:DIR, directly and through the plane grid.
  for (const std::string c : {"ideal", "sx=0.10", "dx=0.10"})
    for (const char* col : {"c1_deg", "c2_deg", "c3_deg", "c4_deg", "c8_deg", "pp_deg"}) {
      INFO(c << " " << col);
      CHECK(num(*find("fem", "coarse P2", c), col) == Approx(num(*find("fem", dir.string(), c), col)).margin(1e-6));
      CHECK(num(*find("fem_grid", "coarse P2 via plane grid", c), col) ==
            Approx(num(*find("fem_grid", dir.string() + " via plane grid", c), col)).margin(1e-6));
    }
  // ... and the order matters: P1 on the same mesh is not the P2 solution.
  CHECK(std::abs(num(*find("fem", "coarse P1", "ideal"), "pp_deg") - num(*find("fem", "coarse P2", "ideal"), "pp_deg")) > 0.1);
  const std::string md = slurp(out / "summary.md");
  CHECK(md.find("## FE artefacts against mesh size and element order") != std::string::npos);
  CHECK(md.find("| coarse P1 | solved here | 1.000 | P1 |") != std::string::npos);
  CHECK(md.find("| coarse P2 | solved here | 1.000 | P2 |") != std::string::npos);
  CHECK(md.find("FE: worst artefact") != std::string::npos);
  CHECK(md.find("Verdict per harmonic") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("harmonic_provenance study: a bad FE variant is one line naming provenance.fem_variants, exit 2, no output",
          "[studies][bad-input][cli]") {
  const std::string coarse = std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml";
  // --set: the inline-array form; the old 'LABEL: key=value; ...' text is refused with the form to use.
  for (const std::string& bad : std::vector<std::string>{
           "a: config=" + coarse + " fem.order=1",                          // the retired mini-language
           "[{ config = \"" + coarse + "\" }]",                             // no label
           "[{ label = \"a\", order = 1 }]",                                // unknown field
           "[{ label = 1 }]",                                               // wrong type
           "[{ label = \"a\" }, { label = \"a\" }]",                        // duplicate label
           "[{ label = \"a,b\" }]",                                         // a CSV cell
           "[{ label = \"a\", set = \"fem.order=1\" }]",                    // set is a table
           "[{ label = \"a\", set = { fem.order = 3 } }]",                  // out of range
           "[{ label = \"a\", set = { fem.order = \"2\" } }]",              // wrong value type
           "[{ label = \"a\", set = { mesh.h_zone_mm = nan } }]",           // non-finite
           "[{ label = \"a\", set = { mesh.bogus = 1 } }]",                 // unknown solve_field key
           "[{ label = \"a\", set = { magnet.mu_r = 1.05 } }]",             // not settable per variant
           "[{ label = \"a\", config = \"/nonexistent/mesh.toml\" }]",     // missing file
           "[{ label = \"a\", config = \"" + coarse + "\", set = { mesh.h_zone_mm = -1 } }]"}) {
    const fs::path out = temp_out("provenance_badvariant");
    const StudyRun r = run_study_exe("harmonic_provenance", out,
                                     "--set sensor.steps=360 --set provenance.spacings_mm=0.2 "
                                     "--set 'provenance.fem_variants=" + bad + "'");
    INFO(bad << ": " << r.err);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find("provenance.fem_variants") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(leftovers(out));
  }
}

TEST_CASE("harmonic_provenance study: provenance.fem_variants tables in a TOML file are read and checked",
          "[studies][bad-input][cli]") {
  const fs::path dir = temp_out("provenance_variant_files");
  fs::create_directories(dir);
  const std::string head = "[sensor]\nsteps = 360\n[provenance]\nspacings_mm = [0.2]\ninterps = [\"nearest\"]\n"
                           "fem_grid_interp = \"none\"\n";
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << head << text;
    return (dir / name).string();
  };
  // Good: one small variant (P1 on the coarse mesh, coarser zone) from [[...]] sections.
  const std::string good = write("good.toml", "\n[[provenance.fem_variants]]\nlabel = \"tiny P1\"\n"
                                              "config = \"meshes/coarse.toml\"\nset = { fem.order = 1 }\n");
  const fs::path out = dir / "out";
  const StudyRun ok = run_study_exe("harmonic_provenance", out, "--config " + good);
  INFO(ok.err);
  REQUIRE(ok.code == 0);
  const auto rows = read_csv(out / "provenance.csv");
  CHECK(std::count_if(rows.begin(), rows.end(), [](const auto& row) {
          return row.at("source") == "fem" && row.at("variant") == "tiny P1";
        }) == 3);
  // The echoed config.toml holds the tables and runs again as --config.
  const std::string echoed = slurp(out / "config.toml");
  CHECK(echoed.find("label = \"tiny P1\"") != std::string::npos);
  CHECK(echoed.find("set = { fem.order = 1 }") != std::string::npos);
  // Bad: each one line naming the key, exit 2, no output.
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"nolabel.toml", "\n[[provenance.fem_variants]]\nconfig = \"meshes/coarse.toml\"\n"},
           {"unknown.toml", "\n[[provenance.fem_variants]]\nlabel = \"a\"\nmesh = \"coarse\"\n"},
           {"type.toml", "\n[[provenance.fem_variants]]\nlabel = \"a\"\nset = { fem.order = true }\n"},
           {"twice.toml", "\n[[provenance.fem_variants]]\nlabel = \"a\"\n[[provenance.fem_variants]]\nlabel = \"a\"\n"},
           {"oldform.toml", "fem_variants = \"coarse P1: config=meshes/coarse.toml fem.order=1\"\n"},
           {"onetable.toml", "\n[provenance.fem_variants]\nlabel = \"a\"\n"}}) {
    const fs::path bad_out = dir / ("out_" + name);
    const StudyRun r = run_study_exe("harmonic_provenance", bad_out, "--config " + write(name, text));
    INFO(name << ": " << r.err);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find("provenance.fem_variants") != std::string::npos);
    CHECK_FALSE(fs::exists(bad_out));
  }
  fs::remove_all(dir);
}

TEST_CASE("FEM-driven studies: a missing field directory exits non-zero, one line naming solve_field, no output",
          "[studies][bad-input][cli]") {
  for (const std::string study : {"real_field", "airgap"}) {
    const fs::path out = temp_out(study + "_nofield");
    const StudyRun r = run_study_exe(study, out, "--set fem_field.dir=/nonexistent/field_dir");
    INFO(study << ": " << r.err);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find("solve_field") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    CHECK_FALSE(leftovers(out));
  }
  const fs::path out = temp_out("provenance_nofield");
  const StudyRun r = run_study_exe("harmonic_provenance", out,
                                   "--set sensor.steps=360 --set provenance.spacings_mm=0.2 "
                                   "--set provenance.fem_dirs=/nonexistent/field_dir");
  INFO(r.err);
  CHECK(r.code != 0);
  CHECK(lines(r.err) == 1);
  CHECK_FALSE(fs::exists(out));
}
