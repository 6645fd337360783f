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

void PointLocator::BucketGrid::build(const Eigen::Matrix3Xd& cen, const std::vector<int>& ids, const Eigen::Vector3d& box_lo,
                                     const Eigen::Vector3d& box_hi, int max_dim) {
  const int n = static_cast<int>(ids.size());
  lo = box_lo;
  const Eigen::Vector3d ext = (box_hi - box_lo).cwiseMax(1e-9);
  const double per_axis = std::cbrt(std::max(1.0, n / 2.0) / (ext.prod() / std::pow(ext.maxCoeff(), 3)));
  for (int d = 0; d < 3; ++d) dims[d] = std::clamp(static_cast<int>(per_axis * ext[d] / ext.maxCoeff()), 1, max_dim);
  size = ext.cwiseQuotient(dims.cast<double>());
  const long nb = static_cast<long>(dims.prod());
  std::vector<long> bucket_of(static_cast<size_t>(n));
  start.assign(static_cast<size_t>(nb) + 1, 0);
  for (int i = 0; i < n; ++i) {
    bucket_of[static_cast<size_t>(i)] = bucket(index_of(cen.col(ids[static_cast<size_t>(i)])));
    start[static_cast<size_t>(bucket_of[static_cast<size_t>(i)]) + 1]++;
  }
  for (long b = 0; b < nb; ++b) start[static_cast<size_t>(b) + 1] += start[static_cast<size_t>(b)];
  cells.resize(static_cast<size_t>(n));
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int i = 0; i < n; ++i) cells[static_cast<size_t>(fill[static_cast<size_t>(bucket_of[static_cast<size_t>(i)])]++)] = ids[static_cast<size_t>(i)];
}

Eigen::Vector3i PointLocator::BucketGrid::index_of(const Eigen::Vector3d& p) const {
  Eigen::Vector3i c;
  for (int d = 0; d < 3; ++d) {
    const double x = std::floor((p[d] - lo[d]) / size[d]);  // clamped as a double: p may be far outside
    c[d] = static_cast<int>(std::clamp(x, 0.0, static_cast<double>(dims[d] - 1)));
  }
  return c;
}

int PointLocator::BucketGrid::first_near(const Eigen::Vector3d& p) const {
  const Eigen::Vector3i c = index_of(p);
  // Search growing shells of buckets until one holds a cell.
  for (int ring = 0; ring < dims.maxCoeff(); ++ring) {
    for (int k = std::max(0, c[2] - ring); k <= std::min(dims[2] - 1, c[2] + ring); ++k)
      for (int j = std::max(0, c[1] - ring); j <= std::min(dims[1] - 1, c[1] + ring); ++j)
        for (int i = std::max(0, c[0] - ring); i <= std::min(dims[0] - 1, c[0] + ring); ++i) {
          if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != ring) continue;
          const long b = bucket(Eigen::Vector3i(i, j, k));
          if (start[static_cast<size_t>(b)] < start[static_cast<size_t>(b) + 1]) return cells[static_cast<size_t>(start[static_cast<size_t>(b)])];
        }
  }
  return -1;
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
  // 2. Top grid of centroids over the mesh's bounding box (about 2 cells per bucket).
  Eigen::Matrix3Xd cen(3, nt);
  for (int t = 0; t < nt; ++t)
    cen.col(t) = 0.25 * (nodes.col(tets_(0, t)) + nodes.col(tets_(1, t)) + nodes.col(tets_(2, t)) + nodes.col(tets_(3, t)));
  std::vector<int> all(static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) all[static_cast<size_t>(t)] = t;
  top_.build(cen, all, nodes.rowwise().minCoeff(), nodes.rowwise().maxCoeff(), 400);
  // 3. Nested grids in the crowded buckets (graded meshes: many small cells in one top bucket).
  const long nb = static_cast<long>(top_.dims.prod());
  nested_of_.assign(static_cast<size_t>(nb), -1);
  for (long b = 0; b < nb; ++b) {
    const int b0 = top_.start[static_cast<size_t>(b)], b1 = top_.start[static_cast<size_t>(b) + 1];
    if (b1 - b0 <= kRefineAbove) continue;
    const Eigen::Vector3i ijk(static_cast<int>(b % top_.dims[0]), static_cast<int>((b / top_.dims[0]) % top_.dims[1]),
                              static_cast<int>(b / (static_cast<long>(top_.dims[0]) * top_.dims[1])));
    const Eigen::Vector3d blo = top_.lo + top_.size.cwiseProduct(ijk.cast<double>());
    const std::vector<int> ids(top_.cells.begin() + b0, top_.cells.begin() + b1);
    nested_of_[static_cast<size_t>(b)] = static_cast<int>(nested_.size());
    nested_.emplace_back().build(cen, ids, blo, blo + top_.size, 64);
  }
}

int PointLocator::start_near(const Eigen::Vector3d& p) const {
  const int g = nested_of_[static_cast<size_t>(top_.bucket(top_.index_of(p)))];
  const int t = g >= 0 ? nested_[static_cast<size_t>(g)].first_near(p) : top_.first_near(p);
  return std::max(t, 0);
}

PointLocator::Walk PointLocator::walk(const Eigen::Vector3d& p, int t, int max_steps, Hit& hit, int& visited) const {
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::Vector4d L = barycentric(nodes_, tets_.col(t), p);
    ++visited;
    int k;
    if (L.minCoeff(&k) >= kInsideTol) {
      hit = Hit{t, L};
      return Walk::found;
    }
    const int next = neighbour_(k, t);
    // Left through a boundary face: the mesh (a ball) is convex, so p is outside.
    if (next < 0) return Walk::outside;
    t = next;
  }
  return Walk::gave_up;
}

PointLocator::Hit PointLocator::lowest_containing(const Eigen::Vector3d& p, Hit hit, int& visited) const {
  // Faces p lies on (within kOnFace, generous next to kInsideTol so that every cell holding p within the
  // tolerance is reached whatever the cell heights): breadth-first over the cells containing p.
  constexpr double kOnFace = 1e-8;
  constexpr int kMaxCells = 256;  // the cells around a vertex, with room to spare
  if (hit.L.minCoeff() > kOnFace) return hit;
  std::array<int, kMaxCells> seen, queue;
  std::array<Eigen::Vector4d, kMaxCells> coords;
  int n_seen = 1, n_queue = 1;
  seen[0] = queue[0] = hit.cell;
  coords[0] = hit.L;
  for (int q = 0; q < n_queue; ++q) {
    const int c = queue[static_cast<size_t>(q)];
    const Eigen::Vector4d Lc = coords[static_cast<size_t>(q)];
    for (int k = 0; k < 4; ++k) {
      const int nb = neighbour_(k, c);
      if (Lc[k] > kOnFace || nb < 0 || n_seen == kMaxCells) continue;
      if (std::find(seen.begin(), seen.begin() + n_seen, nb) != seen.begin() + n_seen) continue;
      seen[static_cast<size_t>(n_seen++)] = nb;
      const Eigen::Vector4d L = barycentric(nodes_, tets_.col(nb), p);
      ++visited;
      if (L.minCoeff() < kInsideTol) continue;
      coords[static_cast<size_t>(n_queue)] = L;
      queue[static_cast<size_t>(n_queue++)] = nb;
      if (nb < hit.cell) hit = Hit{nb, L};
    }
  }
  return hit;
}

std::optional<PointLocator::Hit> PointLocator::locate(const Eigen::Vector3d& p, int start_cell, int* cells_visited) const {
  constexpr int kWarmSteps = 16;  // a warm start further away than this restarts cold
  int visited = 0;
  Hit hit{0, Eigen::Vector4d::Zero()};
  Walk w = Walk::gave_up;
  if (start_cell >= 0 && start_cell < num_cells()) w = walk(p, start_cell, kWarmSteps, hit, visited);
  if (w == Walk::gave_up) w = walk(p, start_near(p), 100000, hit, visited);
  if (w == Walk::gave_up) {
    // The walk did not terminate (degenerate cycle): brute force.
    w = Walk::outside;
    for (int c = 0; c < num_cells() && w != Walk::found; ++c) {
      const Eigen::Vector4d L = barycentric(nodes_, tets_.col(c), p);
      ++visited;
      if (L.minCoeff() >= kInsideTol) {
        hit = Hit{c, L};
        w = Walk::found;
      }
    }
  }
  if (w == Walk::found) hit = lowest_containing(p, hit, visited);
  if (cells_visited) *cells_visited = visited;
  if (w != Walk::found) return std::nullopt;
  return hit;
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
  const Eigen::Index n_chunks = (p.cols() + kBatchChunk - 1) / kBatchChunk;
#pragma omp parallel for schedule(dynamic, 1)
  for (Eigen::Index chunk = 0; chunk < n_chunks; ++chunk) {
    // The chunk's last kRecent hits: point, cell, squared length of the cell's first edge.
    std::array<Eigen::Vector3d, kRecent> recent_p;
    std::array<int, kRecent> recent_cell;
    std::array<double, kRecent> recent_h2;
    int n_recent = 0;
    for (Eigen::Index i = chunk * kBatchChunk; i < std::min(p.cols(), (chunk + 1) * kBatchChunk); ++i) {
      const Eigen::Vector3d x = p.col(i);
      int start = -1;
      double best = 0;
      for (int r = 0; r < std::min(n_recent, static_cast<int>(kRecent)); ++r) {
        const double d2 = (x - recent_p[static_cast<size_t>(r)]).squaredNorm();
        if (d2 <= 4.0 * recent_h2[static_cast<size_t>(r)] && (start < 0 || d2 < best)) {
          start = recent_cell[static_cast<size_t>(r)];
          best = d2;
        }
      }
      const auto hit = locator_.locate(x, start);
      if (hit) {
        B.col(i) = sol_.B_in_cell(hit->cell, hit->L);
        const size_t slot = static_cast<size_t>(n_recent++ % kRecent);
        recent_p[slot] = x;
        recent_cell[slot] = hit->cell;
        recent_h2[slot] = (sol_.points_mm.col(sol_.cell_dofs(1, hit->cell)) - sol_.points_mm.col(sol_.cell_dofs(0, hit->cell))).squaredNorm();
      } else {
        B.col(i).setConstant(std::nan(""));
#pragma omp critical
        if (bad < 0 || i < bad) bad = static_cast<long>(i);
      }
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
