// Stiffness assembly (field_solver/assembly.cpp) against an independent reference on a
// mesh of meshes/coarse.toml's size: the CSR assembly (pattern from the cell dofs,
// element matrices in chunks, row-wise scatter in element order, Robin faces last)
// must give exactly the matrix of a plain std::map assembly that sums every entry's
// contributions in element order, then face order (what setFromTriplets did),
// pattern and values bitwise, and the same bits for 1 and 2 threads.
#include <catch2/catch.hpp>
#include <cstring>
#include <map>
#include <utility>

#include "assembly.hpp"
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
