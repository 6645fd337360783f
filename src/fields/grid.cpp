#include "fields/grid.hpp"

#include <cmath>

#include "core/errors.hpp"

namespace magenc {

Eigen::Matrix3Xd GridData::points_mm() const {
  Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(nodes()));
  Eigen::Index n = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        p.col(n++) = origin_mm + Eigen::Vector3d(i * spacing_mm[0], j * spacing_mm[1], k * spacing_mm[2]);
  return p;
}

void GridData::set_B(const Eigen::Matrix3Xd& B_T) {
  const std::size_t n = static_cast<std::size_t>(B_T.cols());
  Bx_T.resize(n);
  By_T.resize(n);
  Bz_T.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Bx_T[i] = B_T(0, Eigen::Index(i));
    By_T[i] = B_T(1, Eigen::Index(i));
    Bz_T[i] = B_T(2, Eigen::Index(i));
  }
}

GridData GridData::from_range(const Eigen::Vector3d& min_mm, const Eigen::Vector3d& max_mm,
                              const Eigen::Vector3d& step_mm) {
  GridData g;
  g.origin_mm = min_mm;
  g.spacing_mm = step_mm;
  for (int d = 0; d < 3; ++d)
    g.dims[d] = 1 + static_cast<int>(std::floor((max_mm[d] - min_mm[d]) / step_mm[d] + 1e-9));
  return g;
}

void GridData::validate() const {
  const std::string what = "grid " + (source.empty() ? std::string("<memory>") : source);
  for (int d = 0; d < 3; ++d)
    if (dims[d] < 1) throw InputError(what + ": dimension " + std::to_string(d) + " has " + std::to_string(dims[d]) + " nodes: allowed >= 1");
  for (int d = 0; d < (is_plane() ? 2 : 3); ++d)
    if (!(std::isfinite(spacing_mm[d]) && spacing_mm[d] > 0))
      throw InputError(what + ": spacing " + num(spacing_mm[d]) + " mm along axis " + std::to_string(d) + ": allowed > 0");
  if (!origin_mm.allFinite()) throw InputError(what + ": origin is not finite");
  if (Bz_T.size() != nodes()) throw InputError(what + ": Bz has " + std::to_string(Bz_T.size()) + " values, grid has " + std::to_string(nodes()) + " nodes");
  if (has_B() && (Bx_T.size() != nodes() || By_T.size() != nodes()))
    throw InputError(what + ": B components do not match the grid's node count");
  auto finite = [&](const std::vector<double>& v, const char* name) {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i])) throw InputError(what + ": " + name + " is not finite at node " + std::to_string(i));
  };
  finite(Bz_T, "Bz");
  finite(Bx_T, "Bx");
  finite(By_T, "By");
}

}  // namespace magenc
