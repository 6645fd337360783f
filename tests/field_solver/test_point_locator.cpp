// Point location in a graded tetrahedral mesh (PointLocator) and B at a batch of points (FieldEvaluator):
//  - the located cell contains the point and is the lowest-numbered cell that does (brute force over
//    all cells), for random points inside and outside the mesh, mesh vertices, edge midpoints and
//    points on shared faces; the same cell from a cold start and from warm starts anywhere;
//  - B at a batch of points equals B point by point, bit for bit, for 1 and 2 threads.
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "field_solver/fe/element.hpp"
#include "field_solver/fe/fe_solution.hpp"
#include "field_solver/fe/fe_space.hpp"
#include "field_solver/mesh/mesh.hpp"
#include "fem_test_util.hpp"

using namespace magenc::fem;

namespace {

// Graded: 0.4 mm cells in the refinement zone, 6 mm in the air of a 15 mm ball, so that some top
// buckets hold many small cells (nested grids).
const TetMesh& graded_mesh() {
  static const TetMesh mesh = [] {
    DomainSpec d = test::coarse_domain(0.4, 1.0, 16);
    d.mesh.outer_radius_mm = 15.0;
    d.mesh.h_air_mm = 6.0;
    d.zone.half_width_mm = 2.0;
    return mesh_domain(d);
  }();
  return mesh;
}

// The lowest-numbered cell containing p within the locator's tolerance, by trying every cell.
std::optional<int> brute_force(const TetMesh& m, const Eigen::Vector3d& p) {
  for (int c = 0; c < m.num_tets(); ++c)
    if (barycentric(m.nodes, m.tets.col(c), p).minCoeff() >= PointLocator::kInsideTol) return c;
  return std::nullopt;
}

// Random points in and around the ball, mesh vertices, edge midpoints, points on faces (seeded).
std::vector<Eigen::Vector3d> test_points(const TetMesh& m) {
  std::mt19937 rng(36);
  std::uniform_real_distribution<double> box(-17.0, 17.0), zone(-2.5, 2.5), unit(0.0, 1.0);
  std::uniform_int_distribution<int> cell(0, m.num_tets() - 1), node(0, m.num_nodes() - 1), vertex(0, 3);
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 300; ++i) p.emplace_back(box(rng), box(rng), box(rng));                        // in and outside
  for (int i = 0; i < 300; ++i) p.emplace_back(zone(rng), zone(rng), test::kPlaneZ + 0.2 * zone(rng));  // small cells
  for (int i = 0; i < 100; ++i) p.emplace_back(m.nodes.col(node(rng)));                              // vertices
  for (int i = 0; i < 100; ++i) {
    const int c = cell(rng), a = vertex(rng), b = (a + 1 + vertex(rng) % 3) % 4;
    p.emplace_back(0.5 * (m.nodes.col(m.tets(a, c)) + m.nodes.col(m.tets(b, c))));  // edge midpoints
  }
  for (int i = 0; i < 200; ++i) {  // on the face opposite vertex k: barycentric weights on the other three
    const int c = cell(rng), k = vertex(rng);
    double w[3] = {unit(rng), unit(rng), unit(rng)};
    const double s = w[0] + w[1] + w[2];
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int j = 0, n = 0; j < 4; ++j)
      if (j != k) x += (w[n++] / s) * m.nodes.col(m.tets(j, c));
    p.push_back(x);
  }
  return p;
}

}  // namespace

TEST_CASE("PointLocator: cold and warm starts find the lowest-numbered cell containing the point, as brute force",
          "[field_solver][cross-check]") {
  const TetMesh& m = graded_mesh();
  const PointLocator loc(m.nodes, m.tets);
  const std::vector<Eigen::Vector3d> points = test_points(m);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> any_cell(0, m.num_tets() - 1);
  int inside = 0, outside = 0, previous = -1, shared = 0;
  for (const Eigen::Vector3d& p : points) {
    const std::optional<int> expected = brute_force(m, p);
    const auto cold = loc.locate(p);
    REQUIRE(cold.has_value() == expected.has_value());
    if (!expected) {
      ++outside;
      continue;
    }
    ++inside;
    // The hit contains p, its coordinates are the cell's own (same bits), and it is the lowest such cell.
    CHECK(cold->cell == *expected);
    CHECK(cold->L.minCoeff() >= PointLocator::kInsideTol);
    CHECK(cold->L == barycentric(m.nodes, m.tets.col(cold->cell), p));
    CHECK(std::abs(cold->L.sum() - 1.0) < 1e-12);
    // Warm starts: the previous point's cell, a random cell anywhere, the start_near cell.
    for (int start : {previous, any_cell(rng), loc.start_near(p)}) {
      const auto warm = loc.locate(p, start);
      REQUIRE(warm.has_value());
      CHECK(warm->cell == cold->cell);
      CHECK(warm->L == cold->L);
    }
    previous = cold->cell;
    // Points held by more than one cell (vertices, edges, faces) exercise the lowest-cell rule.
    int holders = 0;
    for (int c = 0; c < m.num_tets() && holders < 2; ++c)
      holders += barycentric(m.nodes, m.tets.col(c), p).minCoeff() >= PointLocator::kInsideTol;
    shared += holders > 1;
  }
  CHECK(inside > 500);
  CHECK(outside > 100);
  CHECK(shared > 250);
}

TEST_CASE("PointLocator: consecutive points of a probe circle are found in few cells from a warm start",
          "[field_solver][regression]") {
  const TetMesh& m = graded_mesh();
  const PointLocator loc(m.nodes, m.tets);
  int previous = -1, visited_warm = 0, visited_cold = 0, n = 0;
  for (int i = 0; i < 3600; ++i, ++n) {
    const double a = 2.0 * M_PI * i / 3600.0;
    const Eigen::Vector3d p(1.8 * std::cos(a), 1.8 * std::sin(a), test::kPlaneZ);
    int cold_cells = 0, warm_cells = 0;
    const auto cold = loc.locate(p, -1, &cold_cells);
    const auto warm = loc.locate(p, previous, &warm_cells);
    REQUIRE(cold.has_value());
    REQUIRE(warm.has_value());
    REQUIRE(warm->cell == cold->cell);
    previous = warm->cell;
    visited_cold += cold_cells;
    visited_warm += i > 0 ? warm_cells : 0;
  }
  // Steps of 3 um in 0.4 mm cells: almost always the previous cell; cold starts from the nested grid
  // within a few cells (the default mesh's probe circles: 1.19 warm, 2.74 cold; docs/benchmarks.md).
  CHECK(visited_warm < 1.2 * (n - 1));
  CHECK(visited_cold < 5 * n);
}

TEST_CASE("FieldEvaluator: B at a batch of points equals B point by point for 1 and 2 threads",
          "[field_solver][determinism]") {
  const TetMesh& m = graded_mesh();
  const FeSpace space(m, 2);
  FeSolution sol;
  sol.order = 2;
  sol.points_mm = space.dof_points();
  sol.cell_dofs = space.cell_dofs();
  // A smooth potential with a non-linear gradient, so that cells differ in B.
  sol.psi_Tmm = (sol.points_mm.row(0).array() * sol.points_mm.row(1).array() +
                 0.3 * sol.points_mm.row(2).array().square() + sol.points_mm.row(0).array().sin())
                    .matrix()
                    .transpose();
  sol.region = m.region;
  sol.mu_r = Eigen::VectorXd::Ones(m.num_tets());
  sol.br_T = Eigen::Matrix3Xd::Zero(3, m.num_tets());
  sol.recover_gradient();
  const FieldEvaluator ev(std::move(sol));
  // Probe circles (consecutive points) followed by vertices, faces and random points inside the ball.
  std::vector<Eigen::Vector3d> pts;
  for (double r : {1.2, 2.4})
    for (int i = 0; i < 1000; ++i)
      pts.emplace_back(r * std::cos(2 * M_PI * i / 1000), r * std::sin(2 * M_PI * i / 1000), test::kPlaneZ);
  for (const Eigen::Vector3d& p : test_points(m))
    if (p.norm() < 14.0) pts.push_back(p);
  Eigen::Matrix3Xd P(3, static_cast<Eigen::Index>(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) P.col(static_cast<Eigen::Index>(i)) = pts[i];
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const Eigen::Matrix3Xd B1 = ev.B_T(P);
  omp_set_num_threads(2);
  const Eigen::Matrix3Xd B2 = ev.B_T(P);
  omp_set_num_threads(threads);
  bool same = true;
  for (Eigen::Index i = 0; i < P.cols(); ++i) {
    const auto b = ev.B_T(Eigen::Vector3d(P.col(i)));
    REQUIRE(b.has_value());
    same = same && B1.col(i) == *b && B2.col(i) == *b;
  }
  CHECK(same);
  CHECK(B1.cwiseAbs().maxCoeff() > 0.1);  // B is not trivially zero
}
