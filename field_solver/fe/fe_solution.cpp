#include "field_solver/fe/fe_solution.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "field_solver/fe/element.hpp"
#include "field_solver/mesh/mesh.hpp"
#include "core/errors.hpp"

namespace magenc::fem {

Eigen::Vector3d FeSolution::B_in_cell(int c, const Eigen::Vector4d& L) const {
  Eigen::Vector3d grad = Eigen::Vector3d::Zero();
  if (grad_recovered.cols() > 0 && cell_uses_recovery[static_cast<size_t>(c)]) {
    double N[10];
    basis_values(order, L, N);
    for (int i = 0; i < dofs_per_cell(order); ++i) grad += N[i] * grad_recovered.col(cell_dofs(i, c));
  } else {
    const TetGeometry g = tet_geometry(points_mm, cell_dofs.col(c).head<4>());
    Eigen::Matrix<double, 3, 10> G;
    basis_gradients(order, g, L, G);
    const int nd = dofs_per_cell(order);
    for (int i = 0; i < nd; ++i) grad += cell_dof_value(c, i) * G.col(i);
  }
  if (!source || (split() && cell_total[static_cast<size_t>(c)])) return -mu_r[c] * grad + br_T.col(c);
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) x += L[k] * points_mm.col(cell_dofs(k, c));
  return reduced_B(*source, mu_r[c], x, grad);
}

Eigen::Vector3d source_remanence_T(const AnalyticField& source, const Eigen::Vector3d& x_mm) {
  if (!source.inside_or_on_magnet(x_mm)) return Eigen::Vector3d::Zero();
  return source.magnet().remanence_T();
}

Eigen::Vector3d source_H_T(const AnalyticField& source, const Eigen::Vector3d& x_mm) {
  return source.B_T(x_mm) - source_remanence_T(source, x_mm);
}

Eigen::Vector3d reduced_B(const AnalyticField& source, double mu_r, const Eigen::Vector3d& x_mm,
                          const Eigen::Vector3d& grad_phi) {
  const Eigen::Vector3d br = source_remanence_T(source, x_mm);
  return mu_r * (source.B_T(x_mm) - br - grad_phi) + br;
}

void FeSolution::recover_gradient() {
  const int nd = dofs_per_cell(order);
  const Eigen::Index ndofs = points_mm.cols();
  grad_recovered.setZero(3, ndofs);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(ndofs);
  std::vector<int> material(static_cast<size_t>(ndofs), -1);  // first cell seen; -2: mixed
  // Split: the total and reduced cells count as different materials (their potentials differ on the interface).
  auto same_material = [&](int a, int b) {
    return mu_r[a] == mu_r[b] && br_T.col(a) == br_T.col(b) &&
           (!split() || cell_total[static_cast<size_t>(a)] == cell_total[static_cast<size_t>(b)]);
  };
  // Barycentric coordinates of the local dof nodes (vertices, edge midpoints).
  std::array<Eigen::Vector4d, 10> node;
  for (int i = 0; i < 4; ++i) node[i] = Eigen::Vector4d::Unit(i);
  for (int e = 0; e < 6; ++e) node[4 + e] = 0.5 * (Eigen::Vector4d::Unit(kTetEdges[e][0]) + Eigen::Vector4d::Unit(kTetEdges[e][1]));
  Eigen::Matrix<double, 3, 10> G;
  for (int c = 0; c < num_cells(); ++c) {
    const TetGeometry g = tet_geometry(points_mm, cell_dofs.col(c).head<4>());
    for (int k = 0; k < nd; ++k) {
      basis_gradients(order, g, node[k], G);
      Eigen::Vector3d grad = Eigen::Vector3d::Zero();
      for (int i = 0; i < nd; ++i) grad += cell_dof_value(c, i) * G.col(i);
      const int d = cell_dofs(k, c);
      grad_recovered.col(d) += grad;
      count[d] += 1.0;
      int& m = material[static_cast<size_t>(d)];
      if (m == -1) m = c;
      else if (m >= 0 && !same_material(m, c)) m = -2;
    }
  }
  for (Eigen::Index d = 0; d < ndofs; ++d)
    if (count[d] > 0) grad_recovered.col(d) /= count[d];
  cell_uses_recovery.assign(static_cast<size_t>(num_cells()), 1);
  for (int c = 0; c < num_cells(); ++c)
    for (int k = 0; k < nd; ++k)
      if (material[static_cast<size_t>(cell_dofs(k, c))] == -2) cell_uses_recovery[static_cast<size_t>(c)] = 0;
}

double FeSolution::psi_in_cell(int c, const Eigen::Vector4d& L) const {
  double N[10];
  basis_values(order, L, N);
  double v = 0;
  for (int i = 0; i < dofs_per_cell(order); ++i) v += cell_dof_value(c, i) * N[i];
  return v;
}

PointLocator::PointLocator(const Eigen::Matrix3Xd& nodes, const Eigen::MatrixXi& cells) : nodes_(nodes) {
  const int nt = static_cast<int>(cells.cols());
  tets_ = cells.topRows(4);
  // 1. Face neighbours.
  neighbour_.setConstant(4, nt, -1);
  const std::vector<int> partner = face_partners(tets_, static_cast<int>(nodes.cols()));
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      const int q = partner[static_cast<size_t>(4 * t + k)];
      if (q >= 0) neighbour_(k, t) = q / 4;
    }
  // 2. Bucket grid of centroids (about 2 cells per bucket).
  Eigen::Matrix3Xd cen(3, nt);
  for (int t = 0; t < nt; ++t)
    cen.col(t) = 0.25 * (nodes.col(tets_(0, t)) + nodes.col(tets_(1, t)) + nodes.col(tets_(2, t)) + nodes.col(tets_(3, t)));
  lo_ = nodes.rowwise().minCoeff();
  const Eigen::Vector3d hi = nodes.rowwise().maxCoeff();
  const Eigen::Vector3d ext = (hi - lo_).cwiseMax(1e-9);
  const double per_axis = std::cbrt(std::max(1.0, nt / 2.0) / (ext.prod() / std::pow(ext.maxCoeff(), 3)));
  for (int d = 0; d < 3; ++d) dims_[d] = std::clamp(static_cast<int>(per_axis * ext[d] / ext.maxCoeff()), 1, 400);
  cell_size_ = ext.cwiseQuotient(dims_.cast<double>());
  const long nb = static_cast<long>(dims_.prod());
  std::vector<int> bucket_of(static_cast<size_t>(nt));
  bucket_start_.assign(static_cast<size_t>(nb) + 1, 0);
  for (int t = 0; t < nt; ++t) {
    Eigen::Vector3i ijk;
    for (int d = 0; d < 3; ++d)
      ijk[d] = std::clamp(static_cast<int>((cen(d, t) - lo_[d]) / cell_size_[d]), 0, dims_[d] - 1);
    bucket_of[static_cast<size_t>(t)] = (ijk[2] * dims_[1] + ijk[1]) * dims_[0] + ijk[0];
    bucket_start_[static_cast<size_t>(bucket_of[static_cast<size_t>(t)]) + 1]++;
  }
  for (long b = 0; b < nb; ++b) bucket_start_[static_cast<size_t>(b) + 1] += bucket_start_[static_cast<size_t>(b)];
  bucket_cells_.resize(static_cast<size_t>(nt));
  std::vector<int> fill(bucket_start_.begin(), bucket_start_.end() - 1);
  for (int t = 0; t < nt; ++t) bucket_cells_[static_cast<size_t>(fill[static_cast<size_t>(bucket_of[static_cast<size_t>(t)])]++)] = t;
}

int PointLocator::start_near(const Eigen::Vector3d& p) const {
  Eigen::Vector3i c;
  for (int d = 0; d < 3; ++d) c[d] = std::clamp(static_cast<int>(std::floor((p[d] - lo_[d]) / cell_size_[d])), 0, dims_[d] - 1);
  // Search growing shells of buckets until one holds a cell.
  for (int ring = 0; ring < std::max({dims_[0], dims_[1], dims_[2]}); ++ring) {
    for (int k = c[2] - ring; k <= c[2] + ring; ++k)
      for (int j = c[1] - ring; j <= c[1] + ring; ++j)
        for (int i = c[0] - ring; i <= c[0] + ring; ++i) {
          if (i < 0 || j < 0 || k < 0 || i >= dims_[0] || j >= dims_[1] || k >= dims_[2]) continue;
          if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != ring) continue;
          const int b = (k * dims_[1] + j) * dims_[0] + i;
          if (bucket_start_[static_cast<size_t>(b)] < bucket_start_[static_cast<size_t>(b) + 1])
            return bucket_cells_[static_cast<size_t>(bucket_start_[static_cast<size_t>(b)])];
        }
  }
  return 0;
}

std::optional<PointLocator::Hit> PointLocator::locate(const Eigen::Vector3d& p, int start_cell) const {
  const double tol = -1e-10;
  int t = start_cell >= 0 ? start_cell : start_near(p);
  const int nt = static_cast<int>(tets_.cols());
  for (int step = 0; step < 100000; ++step) {
    const TetGeometry g = tet_geometry(nodes_, tets_.col(t));
    const Eigen::Vector4d L = barycentric(g, p);
    int k;
    const double m = L.minCoeff(&k);
    if (m >= tol) return Hit{t, L};
    const int next = neighbour_(k, t);
    if (next < 0) {
      // Left through a boundary face: the mesh (a ball) is convex, so p is outside.
      return std::nullopt;
    }
    t = next;
  }
  // Walk did not terminate (degenerate cycle): brute force.
  for (int c = 0; c < nt; ++c) {
    const Eigen::Vector4d L = barycentric(tet_geometry(nodes_, tets_.col(c)), p);
    if (L.minCoeff() >= tol) return Hit{c, L};
  }
  return std::nullopt;
}

FieldEvaluator::FieldEvaluator(FeSolution solution)
    : sol_(std::move(solution)), locator_(sol_.points_mm, sol_.cell_dofs) {}

std::optional<Eigen::Vector3d> FieldEvaluator::B_T(const Eigen::Vector3d& p) const {
  auto hit = locator_.locate(p);
  if (!hit) return std::nullopt;
  return sol_.B_in_cell(hit->cell, hit->L);
}

std::optional<double> FieldEvaluator::psi_Tmm(const Eigen::Vector3d& p) const {
  auto hit = locator_.locate(p);
  if (!hit) return std::nullopt;
  return sol_.psi_in_cell(hit->cell, hit->L);
}

Eigen::Matrix3Xd FieldEvaluator::B_T(const Eigen::Matrix3Xd& p) const {
  Eigen::Matrix3Xd B(3, p.cols());
  long bad = -1;
#pragma omp parallel for schedule(dynamic, 256)
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    auto b = B_T(Eigen::Vector3d(p.col(i)));
    if (b) {
      B.col(i) = *b;
    } else {
      B.col(i).setConstant(std::nan(""));
#pragma omp critical
      if (bad < 0 || i < bad) bad = static_cast<long>(i);
    }
  }
  if (bad >= 0)
    throw InputError("point (" + num(p(0, bad)) + ", " + num(p(1, bad)) + ", " + num(p(2, bad)) +
                     ") mm lies outside the FE mesh");
  return B;
}

Eigen::Matrix3Xd FieldEvaluator::B_cell_centroids() const {
  Eigen::Matrix3Xd B(3, sol_.num_cells());
#pragma omp parallel for schedule(static)
  for (int c = 0; c < sol_.num_cells(); ++c) B.col(c) = sol_.B_in_cell(c, Eigen::Vector4d::Constant(0.25));
  return B;
}

}  // namespace magenc::fem
