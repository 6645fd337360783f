// Permeable parts around the magnet ([[parts]], geometry.hpp): a holder cup,
// a tube, a disk, touching the magnet or each other, coaxial or off the axis.
//  - a cup with mu_r = 1 is air: the field equals the bare magnet's (to the
//    discretization error of two different meshes, and exactly with an
//    exact-field magnet);
//  - a steel cup around a diametric magnet short-circuits its poles: the
//    field on the sensing plane drops; split and total potentials agree to
//    the total potential's discretization error; the quadrant solve equals
//    the whole mesh;
//  - a part off the axis is never symmetrized: the solver meshes the whole
//    domain and says so, mesh_quadrant refuses it;
//  - bad parts (overlaps, outside the domain, in the refinement zone, bad
//    shapes or materials) are one-line InputErrors naming the part.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <string>
#include <unistd.h>
#include <vector>

#include "field_solver/mesh/bh_curve.hpp"
#include "core/errors.hpp"
#include "field_solver/field_io/field_outputs.hpp"
#include "fields/analytic_field.hpp"
#include "fields/grid.hpp"
#include "field_solver/mesh/geometry.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"
#include "solver_fixtures.hpp"
#include "field_solver/field_io/validation.hpp"
#include "field_solver/field_io/vtk_io.hpp"

using namespace magenc::fem;
using namespace magenc::fem::test;

namespace {

// The holder of docs/interfaces.md: a cup around the default magnet (R 2 mm,
// faces at z = +-2 mm), its bore touching the magnet's curved face.
std::string cup(const std::string& material, const std::string& extra = "") {
  return "parts=[{name = \"holder\", shape = \"cup\", r_inner_mm = 2.0, r_outer_mm = 2.5, z_min_mm = -2.5, "
         "z_max_mm = 1.5, base_mm = 0.5, material = \"" + material + "\"" + extra + "}]";
}

// Peak |B| (T) of a solve on the test plane.
double peak_B(const MagnetostaticSolver& s) {
  const Eigen::Matrix3Xd B = s.evaluator().B_T(plane(coarse_settings({})).points_mm());
  return B.colwise().norm().maxCoeff();
}

// The InputError text of fem_settings_from_config with `sets` ("" when none).
std::string input_error(const std::vector<std::string>& sets) {
  try {
    coarse_settings(sets);
  } catch (const magenc::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("parts: a cup with mu_r = 1 is air", "[field_solver][physics][cross-check]") {
  SECTION("exact-field magnet (mu_r = 1): no reaction at all, the exact field on both meshes") {
    const auto bare = solved({"magnet.mu_r=1"});
    const auto with_cup = solved({"magnet.mu_r=1", cup("mu_r:1")});
    CHECK(with_cup->stats().iterations == 0);
    CHECK(with_cup->mesh().num_tets() != bare->mesh().num_tets());  // the cup is meshed
    const auto [rms, max] = diff(with_cup->evaluator(), bare->evaluator(), plane(coarse_settings({})));
    CAPTURE(rms, max);
    CHECK(max < 1e-12);
  }
  SECTION("recoil permeability 1.05: equal to the two meshes' discretization difference") {
    const auto bare = solved({});
    const auto air_cup = solved({cup("brass")});
    const auto steel_cup = solved({cup("mu_r:1000")});
    const auto g = plane(coarse_settings({}));
    const auto [rms, max] = diff(air_cup->evaluator(), bare->evaluator(), g);
    const auto [rms_s, max_s] = diff(steel_cup->evaluator(), bare->evaluator(), g);
    CAPTURE(rms, max, rms_s, max_s);
    // The magnet's reaction (mu_r - 1 = 0.05) is itself a ~1e-2 correction whose FE
    // error on this coarse mesh is 8.2e-5 RMS (docs/fem.md): two meshes differ by up to
    // twice that (measured 9.4e-5), while the steel cup changes the field by 73 %.
    CHECK(rms_s > 100 * rms);
  }
}

TEST_CASE("parts: a steel cup short-circuits the diametric magnet's poles", "[field_solver][physics][cross-check]") {
  const auto bare = solved({});
  // The holder touching the magnet: fem.potential = auto takes the total potential (the split is refused).
  const auto touching = solved({cup("mu_r:1000"), "fem.tolerance=1e-10"});
  REQUIRE(touching->options().potential == Potential::Total);
  CHECK_THROWS_AS(solved({cup("mu_r:1000")}, "split"), magenc::InputError);
  // A cup with a 0.2 mm gap around the magnet: split (auto) and total.
  const std::string gap = "parts=[{name = \"h\", shape = \"cup\", r_inner_mm = 2.2, r_outer_mm = 2.7, z_min_mm = -2.7, "
                          "z_max_mm = 1.5, base_mm = 0.5, material = \"mu_r:1000\"}]";
  const auto split = solved({gap, "fem.tolerance=1e-10"});
  REQUIRE(split->options().potential == Potential::Split);
  REQUIRE(split->solution().split());
  const double b0 = peak_B(*bare), b_touch = peak_B(*touching), b_gap = peak_B(*split);
  CAPTURE(b0, b_touch, b_gap);
  // Flux returns through the steel instead of over the sensing plane; more of it with contact.
  CHECK(b_gap < 0.5 * b0);
  CHECK(b_touch < b_gap);
  CHECK(b_touch > 0.01 * b0);
  // A weaker cup takes less flux: the drop grows with mu_r.
  const double b10 = peak_B(*solved({cup("mu_r:10")}));
  CAPTURE(b10);
  CHECK(b10 < b0);
  CHECK(b10 > b_touch);
  // Total potential on the gap cup's mesh: the same field to its own discretization error.
  const auto total = solved({gap, "fem.tolerance=1e-10"}, "total");
  const auto g = plane(coarse_settings({}));
  const auto [rms, max] = diff(split->evaluator(), total->evaluator(), g);
  CAPTURE(rms, max);
  CHECK(rms < 0.05);
  // The quadrant solve equals the solve of the whole mirrored mesh: total to the CG tolerance;
  // split measured 2.0e-6 of the peak (max): its phi_s is integrated along other edge paths
  // (roots on the symmetry plane vs one root), whose quadrature errors differ at that level.
  for (const std::string pot : {"split", "total"}) {
    const auto q = solved({gap, "fem.tolerance=1e-10"}, pot);
    const auto whole = solved({gap, "fem.tolerance=1e-10", "fem.quadrant_solve=false"}, pot);
    const auto [rq, mq] = diff(q->evaluator(), whole->evaluator(), g);
    CAPTURE(pot, rq, mq);
    CHECK(mq < (pot == "total" ? 1e-7 : 1e-5));
  }
}

TEST_CASE("parts: touching parts share their faces (a cup flush with the magnet's top on a disk)", "[field_solver][physics]") {
  const std::string parts =
      "parts=[{name = \"holder\", shape = \"cup\", r_inner_mm = 2.0, r_outer_mm = 2.5, z_min_mm = -2.5, z_max_mm = 2.0, "
      "base_mm = 0.5, material = \"structural_steel\"}, {name = \"plate\", shape = \"disk\", r_inner_mm = 1.0, "
      "r_outer_mm = 6.0, z_min_mm = -3.0, z_max_mm = -2.5, material = \"mu_r:200\"}]";
  // With a zone core down to the magnet's top face the flush cup's rim is part of the zone's bottom.
  const auto s = solved({parts, "mesh.core_radius_mm=3.0", "mesh.h_core_mm=0.6", "mesh.core_top_above_plane_mm=0.4"});
  CHECK(s->mesh_layout() == "symmetric D2 mesh");
  int cells[2] = {0, 0};
  for (int t = 0; t < s->mesh().num_tets(); ++t)
    if (s->mesh().region[t] >= kRegionPartFirst) ++cells[s->mesh().region[t] - kRegionPartFirst];
  CHECK(cells[0] > 0);
  CHECK(cells[1] > 0);
  const double b = peak_B(*s), b0 = peak_B(*solved({"mesh.core_radius_mm=3.0", "mesh.h_core_mm=0.6", "mesh.core_top_above_plane_mm=0.4"}));
  CAPTURE(b, b0);
  CHECK(b < b0);
  CHECK(std::isfinite(b));
}

TEST_CASE("parts: a part off the axis is never symmetrized", "[field_solver][physics]") {
  const std::string screw =
      "parts=[{name = \"screw\", shape = \"cylinder\", r_outer_mm = 1.0, z_min_mm = -6.0, z_max_mm = 1.0, "
      "offset_mm = [4.0, 0.0], material = \"mu_r:1000\"}]";
  const FemSettings fs = coarse_settings({screw});
  REQUIRE(fs.domain.mesh.symmetric);
  REQUIRE(fs.domain.parts.size() == 1);
  CHECK(fs.domain.parts[0].offset_x_mm == 4.0);
  CHECK(fs.domain.parts[0].offset_y_mm == 0.0);
  CHECK_THROWS_AS(mesh_quadrant(fs.domain), magenc::InputError);
  CHECK_THROWS_WITH(mesh_quadrant(fs.domain), Catch::Contains("part 'screw' is off the axis (offset_mm = [4, 0] mm)"));
  CHECK_THROWS_AS(mesh_domain(fs.domain), magenc::InputError);
  const auto s = solved({screw});
  CHECK(s->mesh_layout().rfind("whole domain: a part off the axis", 0) == 0);
  CHECK_FALSE(s->domain().mesh.symmetric);
  // The screw at +x pulls the field towards it: Bz at (+x, 0) and (-x, 0) differ
  // (on a mirrored mesh they could not), while the coaxial case is symmetric.
  const double z = fs.plane_z_mm;
  const double bp = (*s->evaluator().B_T(Eigen::Vector3d(1.5, 0, z))).norm(), bm = (*s->evaluator().B_T(Eigen::Vector3d(-1.5, 0, z))).norm();
  CAPTURE(bp, bm);
  CHECK(std::abs(bp - bm) > 1e-3 * bp);
}

TEST_CASE("parts: bad parts are one-line input errors naming the part", "[field_solver][bad-input]") {
  const std::string ok_disk = "{name = \"d\", shape = \"disk\", r_inner_mm = 0, r_outer_mm = 3, z_min_mm = -4, z_max_mm = -3, material = \"mu_r:100\"";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"parts=[{name = \"in_magnet\", shape = \"cylinder\", r_outer_mm = 1, z_min_mm = -1, z_max_mm = 1, material = \"mu_r:10\"}]",
       "overlaps the magnet"},
      {"parts=[" + ok_disk + "}, {name = \"e\", shape = \"tube\", r_inner_mm = 1, r_outer_mm = 4, z_min_mm = -3.5, "
       "z_max_mm = -2.5, material = \"mu_r:10\"}]", "overlaps parts element 1"},
      {"parts=[{name = \"far\", shape = \"tube\", r_inner_mm = 30, r_outer_mm = 50, z_min_mm = -1, z_max_mm = 1, "
       "material = \"mu_r:10\"}]", "outside the domain"},
      {"parts=[{name = \"hat\", shape = \"disk\", r_inner_mm = 0, r_outer_mm = 3, z_min_mm = 4.5, z_max_mm = 5, "
       "material = \"mu_r:10\"}]", "refinement zone"},
      {"parts=[{name = \"c\", shape = \"cylinder\", r_inner_mm = 1, r_outer_mm = 3, z_min_mm = -4, z_max_mm = -3, "
       "material = \"mu_r:10\"}]", "r_inner_mm"},
      {"parts=[{name = \"t\", shape = \"tube\", r_inner_mm = 3, r_outer_mm = 3, z_min_mm = -4, z_max_mm = -3, "
       "material = \"mu_r:10\"}]", "r_inner_mm"},
      {"parts=[{name = \"cup\", shape = \"cup\", r_inner_mm = 2, r_outer_mm = 3, z_min_mm = -4, z_max_mm = -3, "
       "base_mm = 1, material = \"mu_r:10\"}]", "base_mm"},
      {"parts=[{name = \"z\", shape = \"disk\", r_outer_mm = 3, z_min_mm = -3, z_max_mm = -4, material = \"mu_r:10\"}]",
       "z_max_mm"},
      {"parts=[" + ok_disk + ", material = \"mu_r:0.5\"}]", "material"},
      {"parts=[{name = \"m\", shape = \"disk\", r_outer_mm = 3, z_min_mm = -4, z_max_mm = -3, material = \"unobtainium\"}]",
       "material"},
      {"parts=[{name = \"m\", shape = \"disk\", r_outer_mm = 3, z_min_mm = -4, z_max_mm = -3, material = \"mu_r:12x\"}]",
       "material"},
      {"parts=[{name = \"s\", shape = \"cylinder\", r_outer_mm = 1, z_min_mm = -6, z_max_mm = 1, offset_mm = [2.5, 0], "
       "material = \"mu_r:10\"}]", "off the axis"},
      {"parts=[{name = \"s\", shape = \"cylinder\", r_outer_mm = 1, z_min_mm = -6, z_max_mm = 1, offset_mm = [0, -2.5], "
       "material = \"mu_r:10\"}]", "a part off the axis (offset_mm != [0, 0]) must keep a gap"},
      {"parts=[{name = \"p\", shape = \"pyramid\", r_outer_mm = 1, z_min_mm = -6, z_max_mm = -5, material = \"mu_r:10\"}]",
       "shape"},
      // Walls and gaps below what the mesher resolves (TetGen crashed at 1e-9 mm, never ended at 1e-6..0.01 mm).
      {"parts=[{name = \"t\", shape = \"tube\", r_inner_mm = 2.000000001, r_outer_mm = 3, z_min_mm = -2, z_max_mm = 1, "
       "material = \"mu_r:10\"}]", "parts element 1 of 1 ('t') is 1e-09 mm from the magnet: allowed touching it"},
      {"parts=[{name = \"a\", shape = \"tube\", r_inner_mm = 2.5, r_outer_mm = 3, z_min_mm = -2, z_max_mm = 1, "
       "material = \"mu_r:10\"}, {name = \"b\", shape = \"tube\", r_inner_mm = 3.000000001, r_outer_mm = 4, z_min_mm = -2, "
       "z_max_mm = 1, material = \"mu_r:10\"}]", "('b') is 1e-09 mm from parts element 1 of 2 ('a')"},
      {"parts=[{name = \"w\", shape = \"tube\", r_inner_mm = 2.5, r_outer_mm = 2.51, z_min_mm = -2, z_max_mm = 1, "
       "material = \"mu_r:10\"}]", "has a wall of 0.01 mm: allowed at least 0.05 mm"},
      {"parts=[{name = \"g\", shape = \"disk\", r_outer_mm = 3, z_min_mm = -3.01, z_max_mm = -2.01, "
       "material = \"mu_r:10\"}]", "is 0.01 mm from the magnet"},
  };
  for (const auto& [set, needle] : cases) {
    const std::string e = input_error({set});
    CAPTURE(set, e);
    CHECK(e.find(needle) != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
  }
  // offset_mm is [x, y]: an array of two finite numbers in [-1000, 1000] mm; the earlier scalar keys are unknown.
  const std::string form = "offset_mm = an array of 2 numbers, each [-1000, 1000] mm";
  for (const auto& [offset, needle] : std::vector<std::pair<std::string, std::string>>{
           {"offset_mm = [1]", "parts element 1 of 1: field offset_mm has 1 element"},
           {"offset_mm = [1, 2, 3]", "parts element 1 of 1: field offset_mm has 3 elements"},
           {"offset_mm = [\"1\", 2]", "field offset_mm element 1 of 2 must be a number"},
           {"offset_mm = [0, nan]", "field offset_mm element 2 of 2 = nan is out of range"},
           {"offset_mm = [inf, 0]", "field offset_mm element 1 of 2 = inf is out of range"},
           {"offset_mm = [0, -1000.5]", "field offset_mm element 2 of 2 = -1000.5 is out of range"},
           {"offset_mm = 2.5", "parts element 1 of 1: field offset_mm must be an array"},
           {"offset_x_mm = 2.5", "parts element 1 of 1: unknown field 'offset_x_mm'"},
       }) {
    const std::string e = input_error({"parts=[" + ok_disk + ", " + offset + "}]"});
    CAPTURE(offset, e);
    CHECK(e.find(needle) != std::string::npos);
    CHECK(e.find(form) != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
  }
  // The same geometry, valid: no error.
  CHECK(input_error({"parts=[" + ok_disk + "}]"}).empty());
  CHECK(input_error({cup("mu_r:1000")}).empty());
  // The reduced potential alone cannot carry a permeable part.
  CHECK(input_error({cup("mu_r:1000"), "fem.potential=reduced"}).find("fem.potential") != std::string::npos);
}

TEST_CASE("parts: a cylinder part under the magnet is the shaft", "[field_solver][cross-check]") {
  // shaft.* (legacy PLC) and the same cylinder as a part (the bodies-of-revolution PLC): the same field
  // to the two meshes' discretization difference.
  const auto shaft = solved({"shaft.enabled=true", "shaft.radius_mm=3", "shaft.length_mm=8", "shaft.gap_mm=1"});
  const auto part = solved({"parts=[{name = \"shaft\", shape = \"cylinder\", r_outer_mm = 3, z_min_mm = -11, "
                            "z_max_mm = -3, material = \"mu_r:1000\"}]"});
  REQUIRE(part->options().potential == Potential::Split);
  const auto [rms, max] = diff(part->evaluator(), shaft->evaluator(), plane(coarse_settings({})));
  CAPTURE(rms, max);
  CHECK(rms < 1e-3);  // measured 2.8e-4
  // ... and the shaft's reaction is not small: the bare magnet differs by much more.
  const auto [rb, mb] = diff(solved({})->evaluator(), shaft->evaluator(), plane(coarse_settings({})));
  CAPTURE(rb);
  CHECK(rb > 10 * rms);
}

namespace {

std::string gap_cup(const std::string& material) {
  return "parts=[{name = \"h\", shape = \"cup\", r_inner_mm = 2.2, r_outer_mm = 2.7, z_min_mm = -2.7, z_max_mm = 1.5, "
         "base_mm = 0.5, material = \"" + material + "\"}]";
}

}  // namespace

TEST_CASE("parts: a straight-line B-H curve equals the linear solve", "[field_solver][cross-check]") {
  const double mu0 = kMu0_T_m_per_A;
  // mu_r 5: the line reaches 590 kA/m with a polarization (5 - 1) mu0 H of 2.97 T, below a plausible curve's
  // 3 T, and H in the cup stays below its last row (a line of mu_r 500 would end at 4.8 kA/m, which the
  // cup's edges exceed).
  const std::string f = bh_file("bh_line", {{0, 0}, {1e4, 1e4 * 5 * mu0}, {1e5, 1e5 * 5 * mu0}, {5.9e5, 5.9e5 * 5 * mu0}});
  // Whole mesh and quadrant (the nonlinear solve on the quadrant with x's parity).
  for (const char* quadrant : {"fem.quadrant_solve=false", "fem.quadrant_solve=true"}) {
    const std::vector<std::string> common = {"fem.order=1", "fem.tolerance=1e-10", quadrant};
    const auto nl = solved(with(common, {gap_cup("bh:" + f)}));
    const auto lin = solved(with(common, {gap_cup("mu_r:5")}));
    // mu_r(H) = 5 everywhere: one fixed-point step, then the residual is the CG's.
    CAPTURE(quadrant);
    CHECK(nl->stats().solved_dofs == lin->stats().solved_dofs);
    CHECK(nl->stats().nonlinear_iterations == 1);
    REQUIRE(nl->stats().nonlinear_residuals.size() == 1);
    CHECK(nl->stats().nonlinear_residuals[0] < 1e-8);
    CHECK(lin->stats().nonlinear_iterations == 0);
    const auto [rms, max] = diff(nl->evaluator(), lin->evaluator(), plane(coarse_settings({})));
    CAPTURE(rms, max);
    CHECK(max < 1e-8);
  }
  std::filesystem::remove(f);
}

TEST_CASE("parts: a saturating B-H curve lets more flux over the sensing plane than its initial slope", "[field_solver][physics]") {
  const double mu0 = kMu0_T_m_per_A;
  // Initial mu_r ~ 1000, saturation at ~0.3 T (a thin, weak steel): the cup saturates near the magnet.
  const std::string f = bh_file("bh_sat", {{0, 0}, {100, 100 * 1000 * mu0}, {300, 0.3}, {1e4, 0.32}, {1e6, 0.32 + 1e6 * mu0}});
  const std::vector<std::string> common = {"fem.order=1", "fem.nonlinear_tolerance=1e-4", "fem.nonlinear_max_iterations=200"};
  const auto nl = solved(with(common, {gap_cup("bh:" + f)}));
  std::filesystem::remove(f);
  const double b_nl = peak_B(*nl), b_lin = peak_B(*solved(with(common, {gap_cup("mu_r:1000")}))),
               b0 = peak_B(*solved(common));
  const auto& h = nl->stats().nonlinear_residuals;
  CAPTURE(b_nl, b_lin, b0, nl->stats().nonlinear_iterations, h.front(), h.back());
  CHECK(h.back() < 1e-4);
  CHECK(b_lin < b_nl);
  CHECK(b_nl < b0);
}

TEST_CASE("parts: a B-H part whose start value is mu_r 1 carries the total potential in the split (split = total)", "[field_solver][regression]") {
  // The split potential once chose its total-potential cells by their start mu_r: a B-H part starting at mu_r 1
  // (as a curve's convex start was once clamped to) stayed in the reduced potential while its permeability
  // changed in the nonlinear iteration: 100-200 T inside a saturating cup, and nearly air on the sensing plane.
  const std::string curve = std::string(MAGENC_SOURCE_DIR) + "/materials/structural_steel_bh.csv";
  auto solve = [&](const std::string& potential) {
    FemSettings s = coarse_settings({"fem.order=1", "fem.nonlinear_tolerance=1e-6", gap_cup("bh:" + curve),
                                     "fem.potential=" + potential});
    REQUIRE(s.domain.parts.size() == 1);
    REQUIRE(s.domain.parts[0].bh != nullptr);
    s.domain.parts[0].mu_r = 1.0;  // the start value
    auto solver = std::make_unique<MagnetostaticSolver>(s.domain, s.solver);
    solver->run();
    return solver;
  };
  const auto split = solve("split");
  const auto total = solve("total");
  REQUIRE(split->options().potential == Potential::Split);
  REQUIRE(split->stats().nonlinear_iterations >= 2);  // the permeability moved
  const magenc::GridData g = plane(coarse_settings({}));
  const auto [rms, max] = diff(split->evaluator(), total->evaluator(), g);
  const auto [rb, mb] = diff(solved({"fem.order=1"})->evaluator(), total->evaluator(), g);
  CAPTURE(rms, max, rb, mb);
  // The two potentials differ by their discretization errors on the coarse mesh (as for the linear cup);
  // the steel's effect on the plane is far larger.
  CHECK(rms < 0.2 * rb);
}

TEST_CASE("parts: bodies.vtu holds the magnet's and the part's cells, B on a grid is the solve's", "[field_solver][contract]") {
  const auto s = solved({cup("mu_r:1000")}, "total");
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("magenc_test_bodies_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_bodies_vtu(dir / "bodies.vtu", *s);
  const FeSolution b = read_solution_vtu(dir / "bodies.vtu");
  // Exactly the cells of regions 1 and 10, as linear tets, with their region, mu_r and B.
  const FeSolution& sol = s->solution();
  std::vector<int> kept;  // the solve's cells of the magnet and the part, in order
  int n_part = 0;
  for (int c = 0; c < sol.num_cells(); ++c)
    if (sol.region[c] == kRegionMagnet || sol.region[c] == kRegionPartFirst) {
      kept.push_back(c);
      n_part += sol.region[c] == kRegionPartFirst;
    }
  REQUIRE(n_part > 0);
  REQUIRE(n_part < static_cast<int>(kept.size()));
  CHECK(b.order == 1);
  REQUIRE(b.num_cells() == static_cast<int>(kept.size()));
  CHECK(b.points_mm.cols() < sol.points_mm.cols() / 4);  // the air is left out
  int bad = 0;
  for (int i = 0; i < b.num_cells(); ++i) {
    const int c = kept[static_cast<std::size_t>(i)];
    bad += b.region[i] != sol.region[c] || b.mu_r[i] != sol.mu_r[c];
    for (int k = 0; k < 4; ++k)
      bad += b.points_mm.col(b.cell_dofs(k, i)) != sol.points_mm.col(sol.cell_dofs(k, c));
  }
  CHECK(bad == 0);
  // B on a grid of the plane y = 0: the evaluator's values, B only.
  const magenc::GridData g = magenc::GridData::from_range({-3, 0, -3}, {3, 0, 5}, {0.5, 0.5, 0.5});
  write_B_grid_vti(dir / "slice.vti", g, *s);
  const magenc::GridData r = magenc::read_grid_vti(dir / "slice.vti");
  REQUIRE(r.dims == (std::array<int, 3>{13, 1, 17}));
  const Eigen::Matrix3Xd B = s->evaluator().B_T(g.points_mm());
  for (std::size_t i = 0; i < r.nodes(); ++i) {
    CHECK(r.Bx_T[i] == B(0, static_cast<Eigen::Index>(i)));
    CHECK(r.Bz_T[i] == B(2, static_cast<Eigen::Index>(i)));
  }
  std::filesystem::remove_all(dir);
}
