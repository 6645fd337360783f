// Stiffness assembly (field_solver/fe/assembly.cpp) against an independent reference on a
// mesh of meshes/coarse.toml's size: the CSR assembly (pattern from the cell dofs,
// element matrices in chunks, row-wise scatter in element order, Robin faces last)
// must give exactly the matrix of a plain std::map assembly that sums every entry's
// contributions in element order, then face order (what setFromTriplets did),
// pattern and values bitwise, and the same bits for 1 and 2 threads. Also: the
// closed-form element matrices against the 4-point quadrature they replaced, and the
// mesh numbering for locality (reorder_for_locality) against a shuffled mesh.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <random>
#include <utility>

#include "field_solver/fe/assembly.hpp"
#include "field_solver/fe/element.hpp"
#include "fem_test_util.hpp"

using namespace magenc::fem;

namespace {

// The sizes of meshes/coarse.toml (h_zone 0.8 mm, zone half width 4 mm, 40 mm sphere).
const TetMesh& coarse_size_mesh() {
  static const TetMesh mesh = [] {
    DomainSpec d = test::coarse_domain(0.8, 1.0, 32);
    d.zone.half_width_mm = 4.0;
    return mesh_domain(d);
  }();
  return mesh;
}

Eigen::VectorXd varied_mu(const TetMesh& mesh) {
  Eigen::VectorXd mu = Eigen::VectorXd::LinSpaced(mesh.num_tets(), 1.0, 3.0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.region[t] == kRegionMagnet) mu[t] = 1.05;
  return mu;
}

// Reference: (row, col) -> value; first contribution stored, later ones added in order.
std::map<std::pair<int, int>, double> reference_assembly(const TetMesh& mesh, const FeSpace& space,
                                                         const Eigen::VectorXd& mu, bool robin) {
  std::map<std::pair<int, int>, double> m;
  auto add = [&m](int r, int c, double v) {
    auto [it, inserted] = m.emplace(std::make_pair(r, c), v);
    if (!inserted) it->second += v;
  };
  const int nd = space.dofs_per_cell();
  Eigen::Matrix<double, 10, 10> Ke;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    cell_stiffness(mesh, space.order(), t, mu[t], Ke);
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) add(space.cell_dofs()(i, t), space.cell_dofs()(j, t), Ke(i, j));
  }
  if (robin) {
    int dofs[6];
    Eigen::Matrix<double, 6, 6> Me;
    for (Eigen::Index f = 0; f < mesh.boundary_faces.cols(); ++f) {
      const int nf = robin_face_matrix(mesh, space, f, dofs, Me);
      for (int i = 0; i < nf; ++i)
        for (int j = 0; j < nf; ++j) add(dofs[i], dofs[j], Me(i, j));
    }
  }
  return m;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Number of entries where K and the reference differ in position or bits (-1: sizes differ).
long long mismatches(const SparseMatrix& K, const std::map<std::pair<int, int>, double>& ref) {
  if (!K.isCompressed() || K.nonZeros() != static_cast<Eigen::Index>(ref.size())) return -1;
  long long bad = 0;
  Eigen::Index k = 0;
  int row = 0;
  for (const auto& [rc, v] : ref) {  // map order = row-major, columns ascending = CSR order
    while (K.outerIndexPtr()[row + 1] <= k) ++row;
    if (row != rc.first || K.innerIndexPtr()[k] != rc.second || !same_bits(K.valuePtr()[k], v)) ++bad;
    ++k;
  }
  return bad;
}

long long bit_differences(const SparseMatrix& A, const SparseMatrix& B) {
  if (A.nonZeros() != B.nonZeros() || A.rows() != B.rows()) return -1;
  long long bad = 0;
  for (Eigen::Index r = 0; r <= A.outerSize(); ++r) bad += A.outerIndexPtr()[r] != B.outerIndexPtr()[r];
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    bad += A.innerIndexPtr()[k] != B.innerIndexPtr()[k] || !same_bits(A.valuePtr()[k], B.valuePtr()[k]);
  return bad;
}

}  // namespace

TEST_CASE("stiffness assembly equals an element-order std::map reference exactly on a coarse-size mesh",
          "[field_solver][regression]") {
  const int order = GENERATE(1, 2);
  const bool robin = GENERATE(false, true);
  CAPTURE(order, robin);
  const TetMesh& mesh = coarse_size_mesh();
  REQUIRE(mesh.num_tets() > 10000);
  FeSpace space(mesh, order);
  const Eigen::VectorXd mu = varied_mu(mesh);
  const auto ref = reference_assembly(mesh, space, mu, robin);
  // One chunk (as with the default, larger than this mesh), and many: chunk boundaries inside rows.
  const int chunk = GENERATE(32768, 1000, 7);
  CAPTURE(chunk);
  const SparseMatrix K = assemble_stiffness(mesh, space, mu, robin, 2, chunk);
  CHECK(K.rows() == space.num_dofs());
  CHECK(K.cols() == space.num_dofs());
  CHECK(mismatches(K, ref) == 0);
}

TEST_CASE("stiffness assembly on a coarse-size mesh has the same bits for 1 and 2 threads",
          "[field_solver][determinism]") {
  const int order = GENERATE(1, 2);
  const bool robin = GENERATE(false, true);
  CAPTURE(order, robin);
  const TetMesh& mesh = coarse_size_mesh();
  FeSpace space(mesh, order);
  const Eigen::VectorXd mu = varied_mu(mesh);
  const int chunk = GENERATE(32768, 1000);
  CAPTURE(chunk);
  const SparseMatrix K1 = assemble_stiffness(mesh, space, mu, robin, 1, chunk);
  const SparseMatrix K2 = assemble_stiffness(mesh, space, mu, robin, 2, chunk);
  CHECK(K1.nonZeros() > 0);
  CHECK(bit_differences(K1, K2) == 0);
}

TEST_CASE("closed-form element stiffness equals the 4-point quadrature of grad N_i . grad N_j on random tets",
          "[field_solver][closed-form]") {
  // The 4-point rule is exact for the degree-2 integrand of P2 (degree 0 for P1): the two
  // agree to round-off. Tolerance 1e-13 of the largest entry: ~100 terms of O(max) each,
  // rounded in a different order (measured: below 2e-15).
  const int order = GENERATE(1, 2);
  CAPTURE(order);
  const int nd = order == 1 ? 4 : 10;
  std::mt19937 rng(20261125);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    TetMesh m;
    m.nodes = Eigen::Matrix3Xd(3, 4);
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d) m.nodes(d, k) = u(rng) * (trial % 3 == 0 ? 1e-3 : 5.0);  // tiny and large tets
    m.tets = Eigen::Matrix4Xi(4, 1);
    m.tets.col(0) << 0, 1, 2, 3;
    m.region = Eigen::VectorXi::Constant(1, kRegionAir);
    const TetGeometry g0 = tet_geometry(m.nodes, m.tets.col(0));
    if (g0.volume_mm3 < 0) std::swap(m.tets(2, 0), m.tets(3, 0));
    const TetGeometry g = tet_geometry(m.nodes, m.tets.col(0));
    if (std::abs(g.volume_mm3) < 1e-6 * std::pow(m.nodes.cwiseAbs().maxCoeff(), 3)) continue;  // near-degenerate
    const double mu = 1.0 + 999.0 * (trial % 2);
    Eigen::Matrix<double, 10, 10> Ke;
    cell_stiffness(m, order, 0, mu, Ke);
    Eigen::Matrix<double, 10, 10> Kq = Eigen::Matrix<double, 10, 10>::Zero();
    Eigen::Matrix<double, 3, 10> G = Eigen::Matrix<double, 3, 10>::Zero();
    for (const auto& L : tet_quadrature_points()) {
      basis_gradients(order, g, L, G);
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) Kq(i, j) += mu * kTetQuadratureWeight * g.volume_mm3 * G.col(i).dot(G.col(j));
    }
    const double scale = Kq.topLeftCorner(nd, nd).cwiseAbs().maxCoeff();
    const double diff = (Ke - Kq).topLeftCorner(nd, nd).cwiseAbs().maxCoeff() / scale;
    worst = std::max(worst, diff);
    CHECK(diff < 1e-13);
    CHECK(Ke.bottomRows(10 - nd).isZero(0.0));
    for (int i = 0; i < nd; ++i)
      for (int j = 0; j < nd; ++j) CHECK(same_bits(Ke(i, j), Ke(j, i)));  // exactly symmetric
  }
  INFO("worst relative difference " << worst);  // 0 (P1 under clang -O1) to 6e-16 seen
  CHECK(worst < 1e-13);
}

TEST_CASE("reorder_for_locality keeps the mesh and numbers neighbours closely", "[field_solver][regression]") {
  // A copy of the coarse-size mesh with nodes and tets shuffled (seeded): reordering must give
  // back the same tets (as coordinate sets, with region and orientation), the same boundary,
  // be idempotent, and cut the median |i - j| over tet edges far below the shuffled mesh's.
  const TetMesh& ordered = coarse_size_mesh();
  TetMesh m = ordered;
  const int nn = m.num_nodes(), nt = m.num_tets();
  std::mt19937 rng(7);
  std::vector<int> perm(static_cast<size_t>(nn)), tperm(static_cast<size_t>(nt));
  std::iota(perm.begin(), perm.end(), 0);
  std::iota(tperm.begin(), tperm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), rng);
  std::shuffle(tperm.begin(), tperm.end(), rng);
  for (int i = 0; i < nn; ++i) m.nodes.col(perm[static_cast<size_t>(i)]) = ordered.nodes.col(i);
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) m.tets(k, tperm[static_cast<size_t>(t)]) = perm[static_cast<size_t>(ordered.tets(k, t))];
    m.region[tperm[static_cast<size_t>(t)]] = ordered.region[t];
  }
  for (Eigen::Index f = 0; f < m.boundary_faces.cols(); ++f)
    for (int k = 0; k < 3; ++k) m.boundary_faces(k, f) = perm[static_cast<size_t>(ordered.boundary_faces(k, f))];
  auto spread = [](const TetMesh& x) {  // median |i - j| over the tets' edges
    std::vector<int> d;
    for (int t = 0; t < x.num_tets(); ++t)
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) d.push_back(std::abs(x.tets(a, t) - x.tets(b, t)));
    std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
    return static_cast<double>(d[d.size() / 2]);
  };
  using Tet = std::array<std::array<double, 3>, 5>;  // sorted vertex coordinates + region
  auto tet_set = [](const TetMesh& x) {
    std::vector<Tet> s;
    for (int t = 0; t < x.num_tets(); ++t) {
      Tet v{};
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 3; ++d) v[static_cast<size_t>(k)][static_cast<size_t>(d)] = x.nodes(d, x.tets(k, t));
      std::sort(v.begin(), v.begin() + 4);
      v[4] = {static_cast<double>(x.region[t]), 0, 0};
      s.push_back(v);
    }
    std::sort(s.begin(), s.end());
    return s;
  };
  auto face_set = [](const TetMesh& x) {
    std::vector<std::array<double, 9>> s;
    for (Eigen::Index f = 0; f < x.boundary_faces.cols(); ++f) {
      std::array<double, 9> v{};
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) v[static_cast<size_t>(3 * k + d)] = x.nodes(d, x.boundary_faces(k, f));
      s.push_back(v);
    }
    std::sort(s.begin(), s.end());
    return s;
  };
  const double shuffled = spread(m);
  TetMesh r = m;
  reorder_for_locality(r);
  CHECK(r.num_nodes() == nn);
  CHECK(r.num_tets() == nt);
  CHECK(tet_set(r) == tet_set(ordered));
  CHECK(face_set(r) == face_set(ordered));
  for (int t = 0; t < nt; ++t) REQUIRE(tet_geometry(r.nodes, r.tets.col(t)).volume_mm3 > 0);
  // Tets by smallest vertex id, nondecreasing.
  int prev = -1, unsorted = 0;
  for (int t = 0; t < nt; ++t) {
    const int m0 = r.tets.col(t).minCoeff();
    unsorted += m0 < prev;
    prev = m0;
  }
  CHECK(unsorted == 0);
  INFO("median |i - j| over tet edges: shuffled " << shuffled << ", reordered " << spread(r) << " of "
                                                  << nn << " nodes");
  CHECK(spread(r) < 0.05 * shuffled);
  TetMesh again = r;
  reorder_for_locality(again);
  CHECK(again.nodes == r.nodes);
  CHECK(again.tets == r.tets);
  CHECK(again.boundary_faces == r.boundary_faces);
}
