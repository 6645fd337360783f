#include "mesh.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
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
  std::sort(faces.begin(), faces.end());  // deterministic order
  mesh.boundary_faces.resize(3, static_cast<Eigen::Index>(faces.size()));
  for (size_t i = 0; i < faces.size(); ++i)
    for (int d = 0; d < 3; ++d) mesh.boundary_faces(d, static_cast<Eigen::Index>(i)) = faces[i][d];
}

}  // namespace magenc::fem
