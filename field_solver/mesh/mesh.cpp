#include "field_solver/mesh/mesh.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include "core/errors.hpp"

namespace magenc::fem {

std::vector<int> face_partners(const Eigen::Matrix4Xi& tets, int num_nodes) {
  const int nt = static_cast<int>(tets.cols());
  // Every face is filed under its smallest vertex (a counting sort), then each vertex's few
  // faces are sorted by their other two vertices and their index.
  auto sorted_face = [&](int t, int k) {
    std::array<int, 3> v{};
    for (int i = 0, n = 0; i < 4; ++i)
      if (i != k) v[static_cast<size_t>(n++)] = tets(i, t);
    std::sort(v.begin(), v.end());
    return v;
  };
  struct Entry {
    int b, c, face;  // the face's two larger vertices; face = 4 t + k
    bool operator<(const Entry& o) const { return b != o.b ? b < o.b : c != o.c ? c < o.c : face < o.face; }
  };
  std::vector<long> start(static_cast<size_t>(num_nodes) + 1, 0);
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      const auto v = sorted_face(t, k);
      if (v[0] < 0 || v[2] >= num_nodes) throw ComputeError("mesh: a tet refers to a vertex that does not exist");
      ++start[static_cast<size_t>(v[0]) + 1];
    }
  for (int i = 0; i < num_nodes; ++i) start[static_cast<size_t>(i) + 1] += start[static_cast<size_t>(i)];
  std::vector<Entry> entries(static_cast<size_t>(4) * static_cast<size_t>(nt));
  {
    std::vector<long> fill(start.begin(), start.end() - 1);
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 4; ++k) {
        const auto v = sorted_face(t, k);
        entries[static_cast<size_t>(fill[static_cast<size_t>(v[0])]++)] = Entry{v[1], v[2], 4 * t + k};
      }
  }
  std::vector<int> partner(entries.size(), -1);
#pragma omp parallel for schedule(dynamic, 4096)
  for (int a = 0; a < num_nodes; ++a) {
    const auto lo = entries.begin() + start[static_cast<size_t>(a)], hi = entries.begin() + start[static_cast<size_t>(a) + 1];
    std::sort(lo, hi);
    for (auto e = lo; e != hi;) {
      auto g = e + 1;
      while (g != hi && g->b == e->b && g->c == e->c) ++g;
      auto q = e;
      for (; g - q >= 2; q += 2) {
        partner[static_cast<size_t>(q->face)] = (q + 1)->face;
        partner[static_cast<size_t>((q + 1)->face)] = q->face;
      }
      if (q != g && g - e > 1) partner[static_cast<size_t>(q->face)] = -2;
      e = g;
    }
  }
  return partner;
}

namespace {

// mesh.boundary_faces = faces in sorted order (a deterministic order whatever the tet order).
void set_boundary_faces(TetMesh& mesh, std::vector<std::array<int, 3>> faces) {
  std::sort(faces.begin(), faces.end());
  mesh.boundary_faces.resize(3, static_cast<Eigen::Index>(faces.size()));
  for (size_t i = 0; i < faces.size(); ++i)
    for (int d = 0; d < 3; ++d) mesh.boundary_faces(d, static_cast<Eigen::Index>(i)) = faces[i][static_cast<size_t>(d)];
}

}  // namespace

void finalize_mesh(TetMesh& mesh) {
  const int nt = mesh.num_tets();
  // 1. Orientation: swap two vertices of any negatively oriented tet.
#pragma omp parallel for schedule(static)
  for (int t = 0; t < nt; ++t) {
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) J.col(k) = mesh.nodes.col(mesh.tets(k + 1, t)) - mesh.nodes.col(mesh.tets(0, t));
    if (J.determinant() < 0) std::swap(mesh.tets(2, t), mesh.tets(3, t));
  }
  // 2. Boundary faces: faces that occur in exactly one tet, outward oriented.
  // Local faces opposite vertex k, ordered so that the normal points outward.
  static const int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  const std::vector<int> partner = face_partners(mesh.tets, mesh.num_nodes());
  std::vector<std::array<int, 3>> faces;
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k)
      if (partner[static_cast<size_t>(4 * t + k)] == -1)
        faces.push_back({mesh.tets(kFace[k][0], t), mesh.tets(kFace[k][1], t), mesh.tets(kFace[k][2], t)});
  set_boundary_faces(mesh, std::move(faces));
}

namespace {

// 21 bits of v spread to every third bit (bits 0, 3, 6, ...).
std::uint64_t spread3(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

void reorder_for_locality(TetMesh& mesh) {
  const int nn = mesh.num_nodes(), nt = mesh.num_tets();
  if (nn == 0) return;
  // 1. Nodes by Morton code (ties by old id: a stable order).
  const Eigen::Vector3d lo = mesh.nodes.rowwise().minCoeff(), hi = mesh.nodes.rowwise().maxCoeff();
  const Eigen::Vector3d ext = (hi - lo).cwiseMax(1e-300);
  std::vector<std::uint64_t> key(static_cast<size_t>(nn));
  for (int i = 0; i < nn; ++i) {
    std::uint64_t k = 0;
    for (int d = 0; d < 3; ++d) {
      const double u = (mesh.nodes(d, i) - lo[d]) / ext[d];  // in [0, 1]; NaN coordinates count as 0
      const auto q = static_cast<std::uint64_t>((u > 0.0 ? std::min(u, 1.0) : 0.0) * 2097151.0);
      k |= spread3(q) << d;
    }
    key[static_cast<size_t>(i)] = k;
  }
  std::vector<int> order(static_cast<size_t>(nn));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return key[static_cast<size_t>(a)] < key[static_cast<size_t>(b)]; });
  std::vector<int> new_id(static_cast<size_t>(nn));
  Eigen::Matrix3Xd nodes(3, nn);
  for (int i = 0; i < nn; ++i) {
    new_id[static_cast<size_t>(order[static_cast<size_t>(i)])] = i;
    nodes.col(i) = mesh.nodes.col(order[static_cast<size_t>(i)]);
  }
  mesh.nodes.swap(nodes);
  // 2. Tets by smallest new vertex id: a stable counting sort.
  std::vector<int> first(static_cast<size_t>(nt));
  std::vector<int> start(static_cast<size_t>(nn) + 1, 0);
  for (int t = 0; t < nt; ++t) {
    int m = nn;
    for (int k = 0; k < 4; ++k) {
      const int v = mesh.tets(k, t);
      if (v < 0 || v >= nn) throw ComputeError("mesh: a tet refers to a vertex that does not exist");
      m = std::min(m, new_id[static_cast<size_t>(v)]);
    }
    first[static_cast<size_t>(t)] = m;
    ++start[static_cast<size_t>(m) + 1];
  }
  for (int i = 0; i < nn; ++i) start[static_cast<size_t>(i) + 1] += start[static_cast<size_t>(i)];
  const bool has_region = mesh.region.size() == nt;
  Eigen::Matrix4Xi tets(4, nt);
  Eigen::VectorXi region(has_region ? nt : 0);
  for (int t = 0; t < nt; ++t) {
    const int s = start[static_cast<size_t>(first[static_cast<size_t>(t)])]++;
    for (int k = 0; k < 4; ++k) tets(k, s) = new_id[static_cast<size_t>(mesh.tets(k, t))];
    if (has_region) region[s] = mesh.region[t];
  }
  mesh.tets.swap(tets);
  if (has_region) mesh.region.swap(region);
  // 3. Boundary faces: renumbered, then sorted as finalize_mesh sorts them.
  std::vector<std::array<int, 3>> faces(static_cast<size_t>(mesh.boundary_faces.cols()));
  for (size_t f = 0; f < faces.size(); ++f)
    for (int d = 0; d < 3; ++d) {
      const int v = mesh.boundary_faces(d, static_cast<Eigen::Index>(f));
      if (v < 0 || v >= nn) throw ComputeError("mesh: a boundary face refers to a vertex that does not exist");
      faces[f][static_cast<size_t>(d)] = new_id[static_cast<size_t>(v)];
    }
  set_boundary_faces(mesh, std::move(faces));
}

}  // namespace magenc::fem
