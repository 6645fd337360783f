// The library of named part materials (fem_config.hpp, materials/README.md): every
// named material resolves; the steels with a B-H file load it (from the source
// tree, whatever the working directory), the curve is monotone, starts at (0, 0),
// keeps mu_r >= 1, passes through its source's rows, and its initial slope and
// its B at 10 kA/m lie in the ranges its source's rows give (the rows quoted
// below are the ones the file headers cite). A file edited away from its source,
// or a named material pointing at another file, fails here.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "field_solver/mesh/bh_curve.hpp"
#include "core/cli.hpp"
#include "core/config.hpp"
#include "core/errors.hpp"
#include "field_solver/solve/fem_config.hpp"

using namespace magenc::fem;

namespace {

std::vector<std::string> named_materials() {
  std::vector<std::string> out;
  std::stringstream ss(part_material_names());
  std::string name;
  while (std::getline(ss, name, ',')) out.push_back(name.substr(name.find_first_not_of(' ')));
  return out;
}

// What a curve's source states, as bounds the curve must meet. None of the sources has a row below
// 54 A/m, so none states an initial permeability: the initial slope is only held to the interpolation's
// bounds, mu0 (mu_r >= 1) to 3x the first row's secant; the first row's secant is the source's.
struct SourceRanges {
  std::string file;          // materials/..._bh.csv
  double h_row_A_per_m;      // a row of the source ...
  double b_row_T;            // ... and its B (to 1e-3 T)
  double h1_A_per_m, b1_T;   // its first row after (0, 0)
  double b10k_min_T, b10k_max_T;  // B at 10 kA/m: between the source rows around it
};

void check_curve(const SourceRanges& s) {
  CAPTURE(s.file);
  const BhCurve c = read_bh_csv(std::filesystem::path(MAGENC_SOURCE_DIR) / s.file);
  REQUIRE(c.H().size() >= 4);
  CHECK(c.H().front() == 0);
  CHECK(c.B().front() == 0);
  for (std::size_t i = 1; i < c.H().size(); ++i) {
    CHECK(c.H()[i] > c.H()[i - 1]);
    CHECK(c.B()[i] > c.B()[i - 1]);
  }
  double prev = -1;  // monotone between the rows too (the interpolation), and mu_r >= 1 everywhere
  for (double H = 0.25; H <= 4e5; H *= 1.01) {
    const double b = c.B_T(H);
    CHECK(b > prev);
    CHECK(c.mu_r(H) >= 1.0);
    prev = b;
  }
  CHECK(c.B_T(s.h_row_A_per_m) == Approx(s.b_row_T).margin(1e-3));
  CHECK(c.B_T(s.h1_A_per_m) == Approx(s.b1_T).margin(1e-3));
  const double mu_r0 = c.mu_r(0.0), b10k = c.B_T(1e4);
  const double secant = s.b1_T / (kMu0_T_m_per_A * s.h1_A_per_m);
  CAPTURE(mu_r0, secant, b10k);
  CHECK(mu_r0 >= 1.0);
  CHECK(mu_r0 <= 3.0 * secant);
  CHECK(b10k >= s.b10k_min_T);
  CHECK(b10k <= s.b10k_max_T);
}

}  // namespace

TEST_CASE("materials: every named material resolves, B-H files from the source tree", "[field_solver][contract]") {
  const std::vector<std::string> names = named_materials();
  REQUIRE(names.size() == 6);
  for (const std::string& n : names) {
    CAPTURE(n);
    CHECK(!part_material_source(n).empty());
    const double mu = part_material_mu_r(n, "t");
    CHECK(mu >= 1.0);
    const std::filesystem::path f = part_material_bh_file(n);
    if (!f.empty()) {
      CHECK(std::filesystem::exists(f));
      CHECK(part_material_source(n).find(f.filename().string()) != std::string::npos);  // the source names its file
      CHECK(mu == Approx(read_bh_csv(f).mu_r(0.0)));
    }
  }
  CHECK(part_material_bh_file("free_cutting_steel").filename() == "free_cutting_steel_bh.csv");
  CHECK(part_material_bh_file("electrical_steel").filename() == "electrical_steel_bh.csv");
  CHECK(part_material_bh_file("low_carbon_steel").filename() == "low_carbon_steel_hot_rolled_bh.csv");
  CHECK(part_material_bh_file("structural_steel").empty());  // linear (the steel_parts study's linear model)
  CHECK(part_material_bh_file("bh:x.csv") == std::filesystem::path("x.csv"));
  CHECK(part_material_mu_r("structural_steel", "t") == 1000.0);
  CHECK(part_material_mu_r("stainless_1.4305", "t") >= 1.003);  // annealed austenitic grades: 1.003-1.05 (BSSA)
  CHECK(part_material_mu_r("stainless_1.4305", "t") <= 1.05);
  CHECK(part_material_mu_r("brass", "t") == 1.0);
  CHECK_THROWS_AS(part_material_mu_r("unobtainium", "t"), magenc::InputError);
}

TEST_CASE("materials: the B-H curves keep their sources' values", "[field_solver][regression]") {
  // free_cutting_steel: FEMM 4.2 '1117 Steel': (238.7 A/m, 0.7004 T) first row (secant mu_r 2335),
  // (7957.75 A/m, 1.77 T) and (31831 A/m, 2.0 T) around 10 kA/m.
  check_curve({"materials/free_cutting_steel_bh.csv", 795.775, 1.351, 238.7325, 0.7004, 1.77, 2.0});
  // electrical_steel: M400-50A typical J(H) at 50 Hz, B = J + mu0 H: (75 A/m, 0.5 T) first row (secant
  // mu_r 5300), (6787 A/m, J 1.7 T) and (11712 A/m, J 1.8 T) around 10 kA/m; J(1284 A/m) = 1.5 T.
  check_curve({"materials/electrical_steel_bh.csv", 1284, 1.5 + kMu0_T_m_per_A * 1284, 75, 0.5 + kMu0_T_m_per_A * 75,
               1.7 + kMu0_T_m_per_A * 6787, 1.8 + kMu0_T_m_per_A * 11712});
  // Hot-rolled low-carbon steel, Metals Handbook Fig. 17 as digitized for FEMM: (54.4 A/m, 0.0554 T) first
  // row (secant mu_r 810), (6091.7 A/m, 1.734 T) and (12988 A/m, 1.866 T) around 10 kA/m.
  check_curve({"materials/low_carbon_steel_hot_rolled_bh.csv", 719.29, 1.36807, 54.3813, 0.0554013, 1.734, 1.866});
}

TEST_CASE("materials: a part of a named B-H material is a nonlinear part, the linear ones are not", "[field_solver][contract]") {
  magenc::CommonOptions o;
  o.sets = {"parts=[{name = \"a\", shape = \"disk\", r_outer_mm = 6, z_min_mm = -5, z_max_mm = -4, material = \"electrical_steel\"}, "
            "{name = \"b\", shape = \"disk\", r_outer_mm = 6, z_min_mm = -7, z_max_mm = -6, material = \"free_cutting_steel\"}, "
            "{name = \"c\", shape = \"disk\", r_outer_mm = 6, z_min_mm = -9, z_max_mm = -8, material = \"structural_steel\"}, "
            "{name = \"d\", shape = \"disk\", r_outer_mm = 6, z_min_mm = -11, z_max_mm = -10, material = \"brass\"}]"};
  const std::vector<PartSpec> parts = parts_from_config(magenc::load_config(solve_field_schema(), o));
  REQUIRE(parts.size() == 4);
  REQUIRE(parts[0].bh);
  REQUIRE(parts[1].bh);
  CHECK(parts[0].bh->B_T(1284) == Approx(1.5 + kMu0_T_m_per_A * 1284).margin(1e-3));  // the M400-50A row
  CHECK(parts[1].bh->B_T(7957.75) == Approx(1.77).margin(1e-3));                     // the 1117 row
  CHECK(parts[0].mu_r == Approx(parts[0].bh->mu_r(0.0)));
  CHECK(!parts[2].bh);
  CHECK(parts[2].mu_r == 1000.0);
  CHECK(!parts[3].bh);
  CHECK(parts[3].mu_r == 1.0);
}

TEST_CASE("materials: a B-H part starting at mu_r 1 is still a permeable part (fem.potential = auto)", "[field_solver][regression]") {
  // A part whose start value mu_r is 1 (as the hot-rolled steel's convex start once gave) once counted as
  // air, and fem.potential = auto took the reduced potential for a steel cup around the magnet. The curve
  // now starts with its first row's secant (0.0554013 T at 54.3813 A/m: mu_r 811); the part's start value
  // is set to 1 below.
  const BhCurve c = read_bh_csv(std::filesystem::path(MAGENC_SOURCE_DIR) / "materials/low_carbon_steel_hot_rolled_bh.csv");
  REQUIRE(c.mu_r(0.0) == Approx(0.0554013 / 54.3813 / kMu0_T_m_per_A).epsilon(1e-12));
  DomainSpec d;
  PartSpec cup;
  cup.shape = PartShape::Cup;
  cup.r_inner_mm = d.magnet.radius_mm;
  cup.r_outer_mm = d.magnet.radius_mm + 0.5;
  cup.z_min_mm = -0.5 * d.magnet.height_mm - 0.5;
  cup.z_max_mm = 0.25 * d.magnet.height_mm;
  cup.base_mm = 0.5;
  cup.mu_r = 1.0;
  cup.bh = std::make_shared<const BhCurve>(c);
  d.parts = {cup};
  CHECK(d.has_permeable_part());
  CHECK(d.has_permeable_part_touching_magnet());
  d.parts[0].bh = nullptr;  // the same cup with mu_r 1 and no curve is air
  CHECK(!d.has_permeable_part());
  CHECK(!d.has_permeable_part_touching_magnet());
}
