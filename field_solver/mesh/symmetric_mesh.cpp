#include "field_solver/mesh/symmetric_mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <unordered_map>
#include <set>
#include <string>

#include "core/errors.hpp"
#include "core/units.hpp"

namespace magenc::fem {
namespace {

using Point = Eigen::Vector3d;

bool lex_less(const Point& a, const Point& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

// A symmetry plane through the z axis: signed distance s(p) = n . p, the
// kept side s >= 0. `axis` >= 0: the plane is the coordinate plane p[axis] = 0
// (cut points get that coordinate exactly 0); -1: an oblique plane, whose
// points are recognised within `tol`.
struct Plane {
  Point n;
  int axis = -1;
  double tol = 0;
  double s(const Point& p) const { return axis >= 0 ? p[axis] : n.dot(p); }
  bool on(const Point& p) const { return std::abs(s(p)) <= tol; }
  bool inside(const Point& p) const { return s(p) > tol; }
  bool outside(const Point& p) const { return s(p) < -tol; }
};

// Where edge ab crosses the plane (a strictly inside, b strictly outside or
// the reverse). Computed from the lexicographically smaller end so that the
// two facets sharing the edge get the same point bit for bit.
Point cut_point(const Point& a, const Point& b, const Plane& pl) {
  const Point& p = lex_less(a, b) ? a : b;
  const Point& q = lex_less(a, b) ? b : a;
  const double sp = pl.s(p), sq = pl.s(q);
  Point c = p + (sp / (sp - sq)) * (q - p);
  if (pl.axis >= 0) c[pl.axis] = 0.0;
  return c;
}

// Sutherland-Hodgman against the half-space s >= 0; vertices on the plane
// are inside and create no extra point.
std::vector<Point> clip_half_space(const std::vector<Point>& poly, const Plane& pl) {
  std::vector<Point> out;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Point& s = poly[(i + n - 1) % n];
    const Point& e = poly[i];
    if (!pl.outside(e)) {
      if (pl.outside(s) && pl.inside(e)) out.push_back(cut_point(s, e, pl));
      out.push_back(e);
    } else if (pl.inside(s)) {
      out.push_back(cut_point(s, e, pl));
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

// The symmetry facet in a plane through the z axis: its loop runs along the
// cut edges of the outer boundary from the lowest to the highest point of the
// z axis, then down the axis through every point on it.
Plc::Facet symmetry_facet(const Plc& plc, const std::string& plane, const std::vector<char>& on_axis,
                          const std::set<Edge>& outer_edges, const std::set<Edge>& inner_edges,
                          const std::set<int>& plane_points) {
  std::vector<int> axis;
  for (int i : plane_points)
    if (on_axis[static_cast<size_t>(i)]) axis.push_back(i);
  std::sort(axis.begin(), axis.end(), [&](int a, int b) { return plc.points[a].z() < plc.points[b].z(); });
  if (axis.size() < 2 || outer_edges.empty())
    throw ComputeError("symmetric mesh: the outer boundary does not cross the z axis in the plane " + plane);
  std::map<int, std::vector<int>> next;
  for (const auto& [a, b] : outer_edges) {
    next[a].push_back(b);
    next[b].push_back(a);
  }
  const std::string arc_error =
      "symmetric mesh: the outer boundary's cut in the plane " + plane + " is not one arc from the bottom to the top of the z axis";
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

// The two planes bounding the wedge 0 <= phi <= pi/N: x = 0 then y = 0 (N = 2;
// this order fixes the PLC's point order and so TetGen's mesh), or y = 0 then
// the oblique plane at phi = pi/N.
std::array<Plane, 2> wedge_planes(int sectors, double tol) {
  Plane y0{Point(0, 1, 0), 1, tol};
  if (sectors == 2) return {Plane{Point(1, 0, 0), 0, tol}, y0};
  const double a = kPi / sectors;
  return {y0, Plane{Point(std::sin(a), -std::cos(a), 0), -1, tol}};
}

void check_sectors(int sectors) {
  if (sectors < 2 || sectors > 64 || (sectors & (sectors - 1)) != 0)
    throw InputError("mesh.symmetry_order = " + std::to_string(sectors) + " is out of range: allowed 2, 4, 8, 16, 32 or 64");
}

}  // namespace

Plc clip_plc_to_wedge(const Plc& full, int sectors) {
  check_sectors(sectors);
  double scale = 0;
  for (const auto& p : full.points) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  const std::array<Plane, 2> planes = wedge_planes(sectors, 1e-12 * scale);
  std::vector<Point> pts = full.points;
  for (auto& p : pts)
    for (const Plane& pl : planes)
      if (pl.axis >= 0 && pl.on(p)) p[pl.axis] = 0.0;

  Plc q;
  PointIndex index{{}, &q};
  std::set<Edge> outer_cut[2], inner_cut[2];
  std::set<int> plane_points[2];
  std::vector<std::vector<int>> kept;
  std::vector<bool> kept_outer;
  for (const auto& facet : full.facets) {
    std::vector<Point> poly;
    for (int i : facet.polygon) poly.push_back(pts[static_cast<size_t>(i)]);
    if (!facet.constraints.empty())
      throw ComputeError("symmetric mesh: facets with constraint polygons cannot be clipped");
    poly = clip_half_space(clip_half_space(poly, planes[0]), planes[1]);
    std::vector<int> ids;
    for (const auto& p : poly) {
      const int id = index(p);
      if (ids.empty() || ids.back() != id) ids.push_back(id);
    }
    while (ids.size() > 1 && ids.front() == ids.back()) ids.pop_back();
    if (ids.size() < 3 || polygon_area(poly) <= 1e-14 * scale * scale) continue;  // outside, or touches a plane only
    kept.push_back(ids);
    kept_outer.push_back(facet.outer);
  }
  // On-plane flags of the points (cut points of an oblique plane are within rounding of it).
  const size_t np = q.points.size();
  std::vector<char> on[2] = {std::vector<char>(np), std::vector<char>(np)}, on_axis(np);
  for (size_t i = 0; i < np; ++i) {
    for (int k = 0; k < 2; ++k) on[k][i] = planes[static_cast<size_t>(k)].on(q.points[i]);
    on_axis[i] = on[0][i] && on[1][i];
  }
  for (size_t f = 0; f < kept.size(); ++f) {
    const auto& ids = kept[f];
    for (int k = 0; k < 2; ++k) {
      bool all = true;
      for (int id : ids) all = all && on[k][static_cast<size_t>(id)];
      if (all) throw ComputeError("symmetric mesh: an input facet lies in a symmetry plane");
    }
    for (size_t j = 0; j < ids.size(); ++j) {
      const int a = ids[j], b = ids[(j + 1) % ids.size()];
      for (int k = 0; k < 2; ++k) {
        if (on[k][static_cast<size_t>(a)]) plane_points[k].insert(a);
        if (on[k][static_cast<size_t>(a)] && on[k][static_cast<size_t>(b)])
          (kept_outer[f] ? outer_cut : inner_cut)[k].insert(edge_key(a, b));
      }
    }
    Plc::Facet facet;
    facet.polygon = ids;
    facet.outer = kept_outer[f];
    q.facets.push_back(std::move(facet));
  }
  const std::string names[2] = {sectors == 2 ? "x = 0" : "y = 0",
                                sectors == 2 ? "y = 0" : "phi = 180/" + std::to_string(sectors) + " deg"};
  for (int k = 0; k < 2; ++k) {
    for (const auto& e : outer_cut[k]) inner_cut[k].erase(e);
    q.facets.push_back(symmetry_facet(q, names[k], on_axis, outer_cut[k], inner_cut[k], plane_points[k]));
  }
  for (const auto& r : full.regions) {
    if (!(planes[0].inside(r.seed_mm) && planes[1].inside(r.seed_mm)))
      throw ComputeError("symmetric mesh: region seed outside the wedge 0 < phi < 180/" + std::to_string(sectors) + " deg");
    q.regions.push_back(r);
  }
  return q;
}

TetMesh replicate_wedge_to_quadrant(const TetMesh& wedge, int sectors) {
  check_sectors(sectors);
  if (sectors == 2) return wedge;
  const double tol = 1e-9 * wedge.nodes.cwiseAbs().maxCoeff();
  const std::array<Plane, 2> planes = wedge_planes(sectors, tol);
  const int n = wedge.num_nodes(), nt = wedge.num_tets(), copies = sectors / 2;
  std::vector<char> on[2] = {std::vector<char>(static_cast<size_t>(n)), std::vector<char>(static_cast<size_t>(n))};
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 2; ++k) {
      const Point p = wedge.nodes.col(i);
      if (planes[static_cast<size_t>(k)].outside(p)) throw ComputeError("symmetric mesh: a wedge mesh node lies outside the wedge");
      on[k][static_cast<size_t>(i)] = planes[static_cast<size_t>(k)].on(p);
    }
  // Copy c: rotation by c*pi/N (c even) or reflection y -> -y then rotation
  // by (c+1)*pi/N (c odd); it fills pi*c/N <= phi <= pi*(c+1)/N. Copies c-1
  // and c share the wedge's nodes on y = 0 (c even) or on the oblique plane
  // (c odd), which keep the id they got in copy c-1.
  std::vector<std::vector<int>> id(static_cast<size_t>(copies), std::vector<int>(static_cast<size_t>(n)));
  std::vector<Point> nodes;
  for (int c = 0; c < copies; ++c) {
    const double a = kPi * (c % 2 == 0 ? c : c + 1) / sectors, ca = std::cos(a), sa = std::sin(a);
    for (int i = 0; i < n; ++i) {
      if (c > 0 && on[c % 2 == 0 ? 0 : 1][static_cast<size_t>(i)]) {
        id[static_cast<size_t>(c)][static_cast<size_t>(i)] = id[static_cast<size_t>(c - 1)][static_cast<size_t>(i)];
        continue;
      }
      Point p = wedge.nodes.col(i);
      if (c % 2 == 1) p.y() = -p.y();
      id[static_cast<size_t>(c)][static_cast<size_t>(i)] = static_cast<int>(nodes.size());
      nodes.emplace_back(ca * p.x() - sa * p.y(), sa * p.x() + ca * p.y(), p.z());
    }
  }
  TetMesh m;
  m.nodes.resize(3, static_cast<Eigen::Index>(nodes.size()));
  for (size_t i = 0; i < nodes.size(); ++i) m.nodes.col(static_cast<Eigen::Index>(i)) = nodes[i];
  m.tets.resize(4, static_cast<Eigen::Index>(copies) * nt);
  m.region.resize(static_cast<Eigen::Index>(copies) * nt);
  for (int c = 0; c < copies; ++c)
    for (int t = 0; t < nt; ++t) {
      for (int k = 0; k < 4; ++k) m.tets(k, c * nt + t) = id[static_cast<size_t>(c)][static_cast<size_t>(wedge.tets(k, t))];
      m.region[c * nt + t] = wedge.region[t];
    }
  finalize_mesh(m);
  return m;
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
  // Exact coordinate match through a hash of the bit patterns (x + 0.0 maps
  // -0.0 to +0.0, so points on a plane find their image too); a std::map of
  // the 619k quadrant dofs of the default mesh took 1.7 s, this ~0.2 s.
  using Key = std::array<double, 3>;
  struct KeyHash {
    size_t operator()(const Key& k) const {
      uint64_t h = 0x9e3779b97f4a7c15ULL;
      for (double d : k) {
        uint64_t b;
        std::memcpy(&b, &d, sizeof b);
        h ^= b + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
      }
      return static_cast<size_t>(h);
    }
  };
  auto key = [](double x, double y, double z) { return Key{x + 0.0, y + 0.0, z + 0.0}; };
  std::unordered_map<Key, int, KeyHash> index;
  index.reserve(static_cast<size_t>(quad.cols()));
  for (Eigen::Index i = 0; i < quad.cols(); ++i) index.emplace(key(quad(0, i), quad(1, i), quad(2, i)), static_cast<int>(i));
  std::vector<int> map(static_cast<size_t>(full.cols()));
  bool missing = false;
#pragma omp parallel for schedule(static) reduction(|| : missing)
  for (Eigen::Index i = 0; i < full.cols(); ++i) {
    auto it = index.find(key(std::abs(full(0, i)), std::abs(full(1, i)), full(2, i)));
    if (it == index.end()) {
      missing = true;
      continue;
    }
    map[static_cast<size_t>(i)] = it->second;
  }
  if (missing) throw ComputeError("symmetric mesh: a dof has no mirror image in the quadrant");
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
  reorder_for_locality(m);
  return m;
}

}  // namespace magenc::fem
