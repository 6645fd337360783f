#include "mesh.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <vector>

namespace magenc::fem {

void finalize_mesh(TetMesh& mesh) {
  const int nt = mesh.num_tets();
  // 1. Orientation: swap two vertices of any negatively oriented tet.
#pragma omp parallel for schedule(static)
  for (int t = 0; t < nt; ++t) {
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) J.col(k) = mesh.nodes.col(mesh.tets(k + 1, t)) - mesh.nodes.col(mesh.tets(0, t));
    if (J.determinant() < 0) std::swap(mesh.tets(2, t), mesh.tets(3, t));
  }
  // 2. Boundary faces: faces that occur in exactly one tet, outward oriented. Every face (t, k)
  // is filed under its smallest vertex (a counting sort), then each vertex's few faces are sorted
  // by their other two vertices: a face whose sorted vertex triple occurs once is a boundary face.
  // Local faces opposite vertex k, ordered so that the normal points outward.
  static const int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  auto sorted_face = [&](int t, int k) {
    std::array<int, 3> v{mesh.tets(kFace[k][0], t), mesh.tets(kFace[k][1], t), mesh.tets(kFace[k][2], t)};
    std::sort(v.begin(), v.end());
    return v;
  };
  struct Entry {
    int b, c, face;  // the face's two larger vertices; face = 4 t + k
    bool operator<(const Entry& o) const { return b != o.b ? b < o.b : c != o.c ? c < o.c : face < o.face; }
  };
  const int nn = mesh.num_nodes();
  std::vector<long> start(static_cast<size_t>(nn) + 1, 0);
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) ++start[static_cast<size_t>(sorted_face(t, k)[0]) + 1];
  for (int i = 0; i < nn; ++i) start[static_cast<size_t>(i) + 1] += start[static_cast<size_t>(i)];
  std::vector<Entry> entries(static_cast<size_t>(4) * static_cast<size_t>(nt));
  {
    std::vector<long> fill(start.begin(), start.end() - 1);
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 4; ++k) {
        const auto v = sorted_face(t, k);
        entries[static_cast<size_t>(fill[static_cast<size_t>(v[0])]++)] = Entry{v[1], v[2], 4 * t + k};
      }
  }
  std::vector<char> single(entries.size(), 0);  // per entry: its face occurs once
#pragma omp parallel for schedule(dynamic, 4096)
  for (int a = 0; a < nn; ++a) {
    const auto lo = entries.begin() + start[static_cast<size_t>(a)], hi = entries.begin() + start[static_cast<size_t>(a) + 1];
    std::sort(lo, hi);
    for (auto e = lo; e != hi;) {
      auto g = e + 1;
      while (g != hi && g->b == e->b && g->c == e->c) ++g;
      if (g - e == 1) single[static_cast<size_t>(e - entries.begin())] = 1;
      e = g;
    }
  }
  std::vector<std::array<int, 3>> faces;
  for (size_t i = 0; i < entries.size(); ++i)
    if (single[i]) {
      const int t = entries[i].face / 4, k = entries[i].face % 4;
      faces.push_back({mesh.tets(kFace[k][0], t), mesh.tets(kFace[k][1], t), mesh.tets(kFace[k][2], t)});
    }
  std::sort(faces.begin(), faces.end());  // deterministic order
  mesh.boundary_faces.resize(3, static_cast<Eigen::Index>(faces.size()));
  for (size_t i = 0; i < faces.size(); ++i)
    for (int d = 0; d < 3; ++d) mesh.boundary_faces(d, static_cast<Eigen::Index>(i)) = faces[i][d];
}

}  // namespace magenc::fem
