#include "assembly.hpp"

#include <omp.h>

#include <algorithm>

#include "element.hpp"

namespace magenc::fem {

SparseMatrix assemble_stiffness(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r_cell,
                                bool robin, int threads) {
  using Triplet = Eigen::Triplet<double>;
  const int nt = mesh.num_tets();
  const int order = space.order();
  const int nd = space.dofs_per_cell();
  threads = std::max(1, threads);
  std::vector<std::vector<Triplet>> local(static_cast<size_t>(threads));
  // 1. Element matrices, thread-local triplets; static schedule gives each thread
  //    one contiguous block of elements in thread order.
#pragma omp parallel num_threads(threads)
  {
    auto& trip = local[static_cast<size_t>(omp_get_thread_num())];
    Eigen::Matrix<double, 3, 10> G;
    Eigen::Matrix<double, 10, 10> Ke;
#pragma omp for schedule(static)
    for (int t = 0; t < nt; ++t) {
      if (trip.empty()) trip.reserve(static_cast<size_t>(nt / threads + 1) * nd * nd);
      const TetGeometry g = tet_geometry(mesh.nodes, mesh.tets.col(t));
      Ke.setZero();
      if (order == 1) {
        // Constant gradients: K = V mu G^T G.
        basis_gradients(1, g, Eigen::Vector4d::Constant(0.25), G);
        Ke.topLeftCorner<4, 4>() = g.volume_mm3 * G.leftCols<4>().transpose() * G.leftCols<4>();
      } else {
        for (const auto& L : tet_quadrature_points()) {
          basis_gradients(2, g, L, G);
          Ke.noalias() += (kTetQuadratureWeight * g.volume_mm3) * G.transpose() * G;
        }
      }
      Ke *= mu_r_cell[t];
      for (int i = 0; i < nd; ++i)
        for (int j = 0; j < nd; ++j) trip.emplace_back(space.cell_dofs()(i, t), space.cell_dofs()(j, t), Ke(i, j));
    }
  }
  // 2. Merge in thread order (= element order), freeing each block once copied.
  size_t total = 0;
  for (const auto& v : local) total += v.size();
  std::vector<Triplet> all;
  all.reserve(total + (robin ? static_cast<size_t>(mesh.boundary_faces.cols()) * 36 : 0));
  for (auto& v : local) {
    all.insert(all.end(), v.begin(), v.end());
    std::vector<Triplet>().swap(v);
  }
  // 3. Robin term on the truncation sphere: Int (2/r) N_i N_j dS (mu_r = 1 in air).
  if (robin) {
    const auto& q = tri_quadrature();
    const int nf = order == 1 ? 3 : 6;
    for (Eigen::Index f = 0; f < mesh.boundary_faces.cols(); ++f) {
      int v[3];
      int dofs[6];
      for (int k = 0; k < 3; ++k) dofs[k] = v[k] = mesh.boundary_faces(k, f);
      if (order == 2)
        for (int e = 0; e < 3; ++e) dofs[3 + e] = space.edge_dof(v[kTriEdges[e][0]], v[kTriEdges[e][1]]);
      const Eigen::Vector3d x0 = mesh.nodes.col(v[0]), x1 = mesh.nodes.col(v[1]), x2 = mesh.nodes.col(v[2]);
      const double area = 0.5 * (x1 - x0).cross(x2 - x0).norm();
      Eigen::Matrix<double, 6, 6> Me = Eigen::Matrix<double, 6, 6>::Zero();
      double N[6];
      for (int k = 0; k < 6; ++k) {
        const Eigen::Vector3d& l = q.points[k];
        const double r = (l[0] * x0 + l[1] * x1 + l[2] * x2).norm();
        tri_basis_values(order, l, N);
        const double w = q.weights[k] * area * 2.0 / r;
        for (int i = 0; i < nf; ++i)
          for (int j = 0; j < nf; ++j) Me(i, j) += w * N[i] * N[j];
      }
      for (int i = 0; i < nf; ++i)
        for (int j = 0; j < nf; ++j) all.emplace_back(dofs[i], dofs[j], Me(i, j));
    }
  }
  // 4. One merge: duplicates summed in list order (deterministic).
  SparseMatrix K(space.num_dofs(), space.num_dofs());
  K.setFromTriplets(all.begin(), all.end());
  return K;
}

Eigen::VectorXd assemble_rhs(const TetMesh& mesh, const FeSpace& space, const Eigen::Matrix3Xd& br_cell) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(space.num_dofs());
  const int order = space.order();
  const int nd = space.dofs_per_cell();
  Eigen::Matrix<double, 3, 10> G;
  // Serial: only magnet cells contribute, and a fixed order keeps f bitwise reproducible.
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector3d br = br_cell.col(t);
    if (br.squaredNorm() == 0.0) continue;
    const TetGeometry g = tet_geometry(mesh.nodes, mesh.tets.col(t));
    Eigen::Matrix<double, 10, 1> fe = Eigen::Matrix<double, 10, 1>::Zero();
    if (order == 1) {
      basis_gradients(1, g, Eigen::Vector4d::Constant(0.25), G);
      fe.head<4>() = g.volume_mm3 * G.leftCols<4>().transpose() * br;
    } else {
      for (const auto& L : tet_quadrature_points()) {
        basis_gradients(2, g, L, G);
        fe += (kTetQuadratureWeight * g.volume_mm3) * G.transpose() * br;
      }
    }
    for (int i = 0; i < nd; ++i) f[space.cell_dofs()(i, t)] += fe[i];
  }
  return f;
}

std::vector<int> boundary_dofs(const TetMesh& mesh, const FeSpace& space) {
  std::vector<int> d;
  for (Eigen::Index f = 0; f < mesh.boundary_faces.cols(); ++f)
    for (int k = 0; k < 3; ++k) {
      d.push_back(mesh.boundary_faces(k, f));
      if (space.order() == 2)
        d.push_back(space.edge_dof(mesh.boundary_faces(kTriEdges[k][0], f), mesh.boundary_faces(kTriEdges[k][1], f)));
    }
  std::sort(d.begin(), d.end());
  d.erase(std::unique(d.begin(), d.end()), d.end());
  return d;
}

void apply_zero_dirichlet(SparseMatrix& K, Eigen::VectorXd& f, const std::vector<int>& dofs) {
  std::vector<char> fixed(static_cast<size_t>(K.rows()), 0);
  for (int d : dofs) fixed[static_cast<size_t>(d)] = 1;
  for (Eigen::Index r = 0; r < K.outerSize(); ++r)
    for (SparseMatrix::InnerIterator it(K, r); it; ++it)
      if (fixed[static_cast<size_t>(it.row())] || fixed[static_cast<size_t>(it.col())])
        it.valueRef() = it.row() == it.col() ? 1.0 : 0.0;
  for (int d : dofs) f[d] = 0.0;
}

}  // namespace magenc::fem
