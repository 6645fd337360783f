#include "fe_space.hpp"

#include <algorithm>

#include "element.hpp"
#include "core/errors.hpp"

namespace magenc::fem {

FeSpace::FeSpace(const TetMesh& mesh, int order) : order_(order) {
  if (order != 1 && order != 2) throw InputError("fem.order = " + std::to_string(order) + " is out of range: allowed 1 or 2");
  const int nt = mesh.num_tets(), nn = mesh.num_nodes();
  cell_dofs_.resize(fem::dofs_per_cell(order), nt);
  cell_dofs_.topRows(4) = mesh.tets;
  num_dofs_ = nn;
  std::vector<Eigen::Vector3d> mids;
  if (order == 2) {
    // Edge dofs numbered in the order of the edges' first occurrence (tet t, local edge e: o = 6 t + e).
    // Occurrences are filed under their smaller vertex a (a counting sort), sorted by (b, o) there.
    auto edge = [&](int o) {
      int a = mesh.tets(kTetEdges[o % 6][0], o / 6), b = mesh.tets(kTetEdges[o % 6][1], o / 6);
      if (a > b) std::swap(a, b);
      return std::pair<int, int>(a, b);
    };
    const int n_occ = 6 * nt;
    std::vector<long> start(static_cast<size_t>(nn) + 1, 0);
    for (int o = 0; o < n_occ; ++o) ++start[static_cast<size_t>(edge(o).first) + 1];
    for (int i = 0; i < nn; ++i) start[static_cast<size_t>(i) + 1] += start[static_cast<size_t>(i)];
    std::vector<std::pair<int, int>> occ(static_cast<size_t>(n_occ));  // (b, o) per a
    {
      std::vector<long> fill(start.begin(), start.end() - 1);
      for (int o = 0; o < n_occ; ++o) {
        const auto [a, b] = edge(o);
        occ[static_cast<size_t>(fill[static_cast<size_t>(a)]++)] = {b, o};
      }
    }
    // first[o]: the first occurrence of o's edge; edges per a counted for the CSR.
    std::vector<int> first(static_cast<size_t>(n_occ));
    std::vector<long> n_edges(static_cast<size_t>(nn) + 1, 0);
#pragma omp parallel for schedule(dynamic, 4096)
    for (int a = 0; a < nn; ++a) {
      const auto lo = occ.begin() + start[static_cast<size_t>(a)], hi = occ.begin() + start[static_cast<size_t>(a) + 1];
      std::sort(lo, hi);
      for (auto e = lo; e != hi;) {
        auto g = e;
        for (; g != hi && g->first == e->first; ++g) first[static_cast<size_t>(g->second)] = e->second;
        ++n_edges[static_cast<size_t>(a) + 1];
        e = g;
      }
    }
    std::vector<int> dof_at(static_cast<size_t>(n_occ));
    for (int o = 0; o < n_occ; ++o) {
      const int f = first[static_cast<size_t>(o)];
      if (f == o) {
        const auto [a, b] = edge(o);
        dof_at[static_cast<size_t>(o)] = num_dofs_++;
        mids.push_back(0.5 * (mesh.nodes.col(a) + mesh.nodes.col(b)));
      } else {
        dof_at[static_cast<size_t>(o)] = dof_at[static_cast<size_t>(f)];
      }
      cell_dofs_(4 + static_cast<int>(o % 6), static_cast<Eigen::Index>(o / 6)) = dof_at[static_cast<size_t>(o)];
    }
    // The edge table for edge_dof().
    for (int a = 0; a < nn; ++a) n_edges[static_cast<size_t>(a) + 1] += n_edges[static_cast<size_t>(a)];
    edge_start_ = n_edges;
    edge_b_.resize(static_cast<size_t>(edge_start_.back()));
    edge_dofs_.resize(edge_b_.size());
#pragma omp parallel for schedule(dynamic, 4096)
    for (int a = 0; a < nn; ++a) {
      long k = edge_start_[static_cast<size_t>(a)];
      const auto lo = occ.begin() + start[static_cast<size_t>(a)], hi = occ.begin() + start[static_cast<size_t>(a) + 1];
      for (auto e = lo; e != hi; ++e)
        if (e == lo || e->first != (e - 1)->first) {
          edge_b_[static_cast<size_t>(k)] = e->first;
          edge_dofs_[static_cast<size_t>(k++)] = dof_at[static_cast<size_t>(e->second)];
        }
    }
  }
  dof_points_.resize(3, num_dofs_);
  dof_points_.leftCols(nn) = mesh.nodes;
  for (size_t i = 0; i < mids.size(); ++i) dof_points_.col(nn + static_cast<Eigen::Index>(i)) = mids[i];
}

int FeSpace::edge_dof(int a, int b) const {
  if (a > b) std::swap(a, b);
  if (a < 0 || static_cast<size_t>(a) + 1 >= edge_start_.size()) return -1;
  const auto lo = edge_b_.begin() + edge_start_[static_cast<size_t>(a)], hi = edge_b_.begin() + edge_start_[static_cast<size_t>(a) + 1];
  const auto it = std::lower_bound(lo, hi, b);
  return it == hi || *it != b ? -1 : edge_dofs_[static_cast<size_t>(it - edge_b_.begin())];
}

}  // namespace magenc::fem
