#include "symmetric_mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "errors.hpp"

namespace magenc::fem {
namespace {

using Point = Eigen::Vector3d;

bool lex_less(const Point& a, const Point& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

// Where edge ab crosses the plane p[d] = 0 (a[d], b[d] of strictly opposite
// signs). Computed from the lexicographically smaller end so that the two
// facets sharing the edge get the same point bit for bit.
Point cut_point(const Point& a, const Point& b, int d) {
  const Point& p = lex_less(a, b) ? a : b;
  const Point& q = lex_less(a, b) ? b : a;
  Point c = p + (p[d] / (p[d] - q[d])) * (q - p);
  c[d] = 0.0;
  return c;
}

// Sutherland-Hodgman against the half-space p[d] >= 0; vertices on the plane
// are inside and create no extra point.
std::vector<Point> clip_half_space(const std::vector<Point>& poly, int d) {
  std::vector<Point> out;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Point& s = poly[(i + n - 1) % n];
    const Point& e = poly[i];
    if (e[d] >= 0) {
      if (s[d] < 0 && e[d] > 0) out.push_back(cut_point(s, e, d));
      out.push_back(e);
    } else if (s[d] > 0) {
      out.push_back(cut_point(s, e, d));
    }
  }
  return out;
}

double polygon_area(const std::vector<Point>& poly) {
  Point n = Point::Zero();
  for (size_t i = 0; i < poly.size(); ++i) n += poly[i].cross(poly[(i + 1) % poly.size()]);
  return 0.5 * n.norm();
}

struct PointIndex {
  std::map<std::array<double, 3>, int> ids;
  Plc* plc;
  int operator()(const Point& p) {
    const std::array<double, 3> key{p.x(), p.y(), p.z()};
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const int id = plc->add_point(p);
    ids.emplace(key, id);
    return id;
  }
};

using Edge = std::pair<int, int>;
Edge edge_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// The symmetry facet in the plane p[d] = 0 (d = 0: x = 0, d = 1: y = 0): its
// loop runs along the cut edges of the outer boundary from the lowest to the
// highest point of the z axis, then down the axis through every point on it.
Plc::Facet symmetry_facet(const Plc& plc, int d, const std::set<Edge>& outer_edges, const std::set<Edge>& inner_edges,
                          const std::set<int>& plane_points) {
  const char* plane = d == 0 ? "x = 0" : "y = 0";
  auto on_axis = [&](int i) { return plc.points[i].x() == 0.0 && plc.points[i].y() == 0.0; };
  std::vector<int> axis;
  for (int i : plane_points)
    if (on_axis(i)) axis.push_back(i);
  std::sort(axis.begin(), axis.end(), [&](int a, int b) { return plc.points[a].z() < plc.points[b].z(); });
  if (axis.size() < 2 || outer_edges.empty())
    throw ComputeError(std::string("symmetric mesh: the outer boundary does not cross the z axis in the plane ") + plane);
  std::map<int, std::vector<int>> next;
  for (const auto& [a, b] : outer_edges) {
    next[a].push_back(b);
    next[b].push_back(a);
  }
  const std::string arc_error = std::string("symmetric mesh: the outer boundary's cut in the plane ") + plane +
                                " is not one arc from the bottom to the top of the z axis";
  Plc::Facet f;
  int prev = -1, cur = axis.front();
  if (next[cur].size() != 1) throw ComputeError(arc_error);
  f.polygon.push_back(cur);
  while (cur != axis.back()) {
    const auto& nb = next[cur];
    if (prev >= 0 && nb.size() != 2) throw ComputeError(arc_error);
    const int nxt = nb[0] != prev ? nb[0] : nb[1];
    prev = cur;
    cur = nxt;
    f.polygon.push_back(cur);
    if (f.polygon.size() > outer_edges.size() + 1) throw ComputeError(arc_error);
  }
  if (f.polygon.size() != outer_edges.size() + 1) throw ComputeError(arc_error);
  for (size_t k = axis.size() - 2; k >= 1; --k) f.polygon.push_back(axis[k]);  // down the axis
  // Constraints: the cut edges of internal surfaces, then lone points.
  std::set<int> covered(f.polygon.begin(), f.polygon.end());
  for (const auto& [a, b] : inner_edges) {
    f.constraints.push_back({a, b});
    covered.insert(a);
    covered.insert(b);
  }
  for (int i : plane_points)
    if (!covered.count(i)) f.constraints.push_back({i});
  return f;
}

}  // namespace

Plc clip_plc_to_quadrant(const Plc& full) {
  double scale = 0;
  for (const auto& p : full.points) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  const double snap = 1e-12 * scale;
  std::vector<Point> pts = full.points;
  for (auto& p : pts)
    for (int d = 0; d < 2; ++d)
      if (std::abs(p[d]) <= snap) p[d] = 0.0;

  Plc q;
  PointIndex index{{}, &q};
  std::set<Edge> outer_cut[2], inner_cut[2];
  std::set<int> plane_points[2];
  for (const auto& facet : full.facets) {
    std::vector<Point> poly;
    for (int i : facet.polygon) poly.push_back(pts[static_cast<size_t>(i)]);
    if (!facet.constraints.empty())
      throw ComputeError("symmetric mesh: facets with constraint polygons cannot be clipped");
    poly = clip_half_space(clip_half_space(poly, 0), 1);
    std::vector<int> ids;
    for (const auto& p : poly) {
      const int id = index(p);
      if (ids.empty() || ids.back() != id) ids.push_back(id);
    }
    while (ids.size() > 1 && ids.front() == ids.back()) ids.pop_back();
    if (ids.size() < 3 || polygon_area(poly) <= 1e-14 * scale * scale) continue;  // outside, or touches a plane only
    bool in_plane[2] = {true, true};
    for (int id : ids)
      for (int d = 0; d < 2; ++d) in_plane[d] = in_plane[d] && q.points[id][d] == 0.0;
    if (in_plane[0] || in_plane[1])
      throw ComputeError("symmetric mesh: an input facet lies in a symmetry plane");
    for (size_t k = 0; k < ids.size(); ++k) {
      const int a = ids[k], b = ids[(k + 1) % ids.size()];
      for (int d = 0; d < 2; ++d) {
        if (q.points[a][d] == 0.0) plane_points[d].insert(a);
        if (q.points[a][d] == 0.0 && q.points[b][d] == 0.0) (facet.outer ? outer_cut : inner_cut)[d].insert(edge_key(a, b));
      }
    }
    Plc::Facet f;
    f.polygon = ids;
    f.outer = facet.outer;
    q.facets.push_back(std::move(f));
  }
  for (int d = 0; d < 2; ++d) {
    for (const auto& e : outer_cut[d]) inner_cut[d].erase(e);
    q.facets.push_back(symmetry_facet(q, d, outer_cut[d], inner_cut[d], plane_points[d]));
  }
  for (const auto& r : full.regions) {
    if (!(r.seed_mm.x() > 0 && r.seed_mm.y() > 0))
      throw ComputeError("symmetric mesh: region seed outside the quadrant x > 0, y > 0");
    q.regions.push_back(r);
  }
  return q;
}

void snap_quadrant_mesh(TetMesh& quad) {
  const double tol = 1e-9 * quad.nodes.cwiseAbs().maxCoeff();
  for (int i = 0; i < quad.num_nodes(); ++i)
    for (int d = 0; d < 2; ++d) {
      if (quad.nodes(d, i) < -tol) throw ComputeError("symmetric mesh: a quadrant mesh node lies outside the quadrant");
      if (std::abs(quad.nodes(d, i)) <= tol) quad.nodes(d, i) = 0.0;
    }
  std::vector<int> keep;
  for (Eigen::Index f = 0; f < quad.boundary_faces.cols(); ++f) {
    bool on_plane = false;
    for (int d = 0; d < 2; ++d) {
      bool all = true;
      for (int k = 0; k < 3; ++k) all = all && quad.nodes(d, quad.boundary_faces(k, f)) == 0.0;
      on_plane = on_plane || all;
    }
    if (!on_plane) keep.push_back(static_cast<int>(f));
  }
  Eigen::Matrix3Xi outer(3, static_cast<Eigen::Index>(keep.size()));
  for (size_t i = 0; i < keep.size(); ++i) outer.col(static_cast<Eigen::Index>(i)) = quad.boundary_faces.col(keep[i]);
  quad.boundary_faces = outer;
}

std::vector<int> mirror_dof_map(const Eigen::Matrix3Xd& full, const Eigen::Matrix3Xd& quad) {
  std::map<std::array<double, 3>, int> index;
  for (Eigen::Index i = 0; i < quad.cols(); ++i) index.emplace(std::array<double, 3>{quad(0, i), quad(1, i), quad(2, i)}, i);
  std::vector<int> map(static_cast<size_t>(full.cols()));
  for (Eigen::Index i = 0; i < full.cols(); ++i) {
    // std::abs maps -0.0 to +0.0, so points on a plane find their image too.
    auto it = index.find({std::abs(full(0, i)), std::abs(full(1, i)), full(2, i)});
    if (it == index.end()) throw ComputeError("symmetric mesh: a dof has no mirror image in the quadrant");
    map[static_cast<size_t>(i)] = it->second;
  }
  return map;
}

TetMesh mirror_quadrant_mesh(const TetMesh& quad_in) {
  TetMesh quad = quad_in;
  snap_quadrant_mesh(quad);
  const int n = quad.num_nodes(), nt = quad.num_tets();
  const Eigen::Matrix3Xd& p = quad.nodes;
  // Copy c reflects x if (c & 1), y if (c & 2). A node on a symmetry plane is
  // its own mirror image there: it keeps the id it has in the copy without that reflection.
  std::array<std::vector<int>, 4> id;
  std::vector<Eigen::Vector3d> nodes;
  nodes.reserve(4 * static_cast<size_t>(n));
  for (int c = 0; c < 4; ++c) {
    id[c].resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      int src = c;
      if (p(0, i) == 0.0) src &= ~1;
      if (p(1, i) == 0.0) src &= ~2;
      if (src != c) {
        id[c][i] = id[src][i];
        continue;
      }
      Eigen::Vector3d x = p.col(i);
      if (c & 1) x.x() = -x.x();
      if (c & 2) x.y() = -x.y();
      id[c][i] = static_cast<int>(nodes.size());
      nodes.push_back(x);
    }
  }
  TetMesh m;
  m.nodes.resize(3, static_cast<Eigen::Index>(nodes.size()));
  for (size_t i = 0; i < nodes.size(); ++i) m.nodes.col(static_cast<Eigen::Index>(i)) = nodes[i];
  m.tets.resize(4, 4 * nt);
  m.region.resize(4 * nt);
  for (int c = 0; c < 4; ++c)
    for (int t = 0; t < nt; ++t) {
      for (int k = 0; k < 4; ++k) m.tets(k, c * nt + t) = id[c][quad.tets(k, t)];
      m.region[c * nt + t] = quad.region[t];
    }
  finalize_mesh(m);
  for (Eigen::Index f = 0; f < m.boundary_faces.cols(); ++f)
    for (int d = 0; d < 2; ++d) {
      bool all = true;
      for (int k = 0; k < 3; ++k) all = all && m.nodes(d, m.boundary_faces(k, f)) == 0.0;
      if (all) throw ComputeError("symmetric mesh: a face on a symmetry plane has no mirror partner (non-conforming cut)");
    }
  return m;
}

}  // namespace magenc::fem
