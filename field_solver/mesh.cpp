#include "mesh.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <unordered_map>

namespace magenc::fem {

void finalize_mesh(TetMesh& mesh) {
  // 1. Orientation: swap two vertices of any negatively oriented tet.
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) J.col(k) = mesh.nodes.col(mesh.tets(k + 1, t)) - mesh.nodes.col(mesh.tets(0, t));
    if (J.determinant() < 0) std::swap(mesh.tets(2, t), mesh.tets(3, t));
  }
  // 2. Boundary faces: faces that occur in exactly one tet, outward oriented.
  struct Key {
    std::array<int, 3> v;
    bool operator==(const Key& o) const { return v == o.v; }
  };
  struct Hash {
    size_t operator()(const Key& k) const {
      return (static_cast<size_t>(k.v[0]) * 73856093u) ^ (static_cast<size_t>(k.v[1]) * 19349663u) ^
             (static_cast<size_t>(k.v[2]) * 83492791u);
    }
  };
  // Local faces opposite vertex k, ordered so that the normal points outward.
  static const int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::unordered_map<Key, std::pair<int, std::array<int, 3>>, Hash> count;
  count.reserve(static_cast<size_t>(mesh.num_tets()) * 3);
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> f{mesh.tets(kFace[k][0], t), mesh.tets(kFace[k][1], t), mesh.tets(kFace[k][2], t)};
      Key key{f};
      std::sort(key.v.begin(), key.v.end());
      auto [it, inserted] = count.try_emplace(key, 0, f);
      it->second.first++;
    }
  std::vector<std::array<int, 3>> faces;
  for (const auto& [key, val] : count)
    if (val.first == 1) faces.push_back(val.second);
  std::sort(faces.begin(), faces.end());  // deterministic order
  mesh.boundary_faces.resize(3, static_cast<Eigen::Index>(faces.size()));
  for (size_t i = 0; i < faces.size(); ++i)
    for (int d = 0; d < 3; ++d) mesh.boundary_faces(d, static_cast<Eigen::Index>(i)) = faces[i][d];
}

}  // namespace magenc::fem
