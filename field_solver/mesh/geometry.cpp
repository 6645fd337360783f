#include "field_solver/mesh/geometry.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include "core/errors.hpp"
#include "field_solver/mesh/sector_magnetization.hpp"
#include "field_solver/mesh/symmetric_mesh.hpp"
#include "core/units.hpp"

namespace magenc::fem {
namespace {

// Unit icosphere: icosahedron refined `level` times by edge midpoints.
void unit_icosphere(int level, std::vector<Eigen::Vector3d>& v, std::vector<std::array<int, 3>>& f) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
       {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      int id = static_cast<int>(v.size()) - 1;
      mid[key] = id;
      return id;
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& tri : f) {
      int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], a, c});
      g.push_back({tri[1], b, a});
      g.push_back({tri[2], c, b});
      g.push_back({a, b, c});
    }
    f.swap(g);
  }
}

// Adds a faceted sphere (centre c, radius r) to the PLC. With equal_volume the
// vertices are pushed out so the polyhedron's volume is 4/3 pi r^3.
void add_sphere(Plc& plc, const Eigen::Vector3d& c, double r, int level, bool equal_volume, bool outer) {
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  unit_icosphere(level, v, f);
  double scale = 1.0;
  if (equal_volume) {
    double vol = 0;
    for (const auto& tri : f) vol += v[tri[0]].dot(v[tri[1]].cross(v[tri[2]])) / 6.0;
    scale = std::cbrt((4.0 / 3.0) * kPi / vol);
  }
  const int base = static_cast<int>(plc.points.size());
  for (const auto& p : v) plc.add_point(c + r * scale * p);
  for (const auto& tri : f) plc.facets.push_back({{base + tri[0], base + tri[1], base + tri[2]}, {}, outer});
}

// Adds a z-axis cylinder (polygon radius rp, N segments, z0 < z1).
void add_cylinder(Plc& plc, double rp, int N, double z0, double z1) {
  const int base = static_cast<int>(plc.points.size());
  for (int k = 0; k < N; ++k) {
    double a = 2.0 * kPi * k / N;
    plc.add_point({rp * std::cos(a), rp * std::sin(a), z0});
  }
  for (int k = 0; k < N; ++k) {
    double a = 2.0 * kPi * k / N;
    plc.add_point({rp * std::cos(a), rp * std::sin(a), z1});
  }
  Plc::Facet bottom, top;
  for (int k = 0; k < N; ++k) {
    bottom.polygon.push_back(base + k);
    top.polygon.push_back(base + N + k);
    int k1 = (k + 1) % N;
    plc.facets.push_back({{base + k, base + k1, base + N + k1, base + N + k}});
  }
  plc.facets.push_back(bottom);
  plc.facets.push_back(top);
}

void add_box(Plc& plc, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const int b = static_cast<int>(plc.points.size());
  for (int k = 0; k < 8; ++k)
    plc.add_point({(k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z()});
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& q : quads) plc.facets.push_back({{b + q[0], b + q[1], b + q[2], b + q[3]}});
}

// Region seed at radius r, height z and the angle pi/128: strictly inside the
// wedge 0 < phi < pi/N for every symmetry order N <= 64 (clip_plc_to_wedge
// keeps the seeds), and inside the intended region for all rotationally
// symmetric parts and the zone box (r < half width).
Eigen::Vector3d seed_at(double r_mm, double z_mm) {
  const double a = kPi / 128.0;
  return {r_mm * std::cos(a), r_mm * std::sin(a), z_mm};
}

// Zone box [-w, w]^2 x [top, z_max] around a core cylinder (radius rc, N-gon at
// the magnet's angles) from the magnet's top face (whose top ring of N points
// starts at magnet_top_first) to core_z_max. The planar faces at z = top are
// split into convex quads between rays at the polygon angles: magnet ring ->
// core ring (core bottom) and core ring -> square (zone bottom); N % 8 == 0 puts
// the square's corners on rays.
// With core_ring (N point ids of the core ring at z = top, the faces inside it
// already in the PLC) the magnet's ring is not used.
void add_zone_with_core(Plc& plc, const DomainSpec& spec, int magnet_top_first, double top,
                        const std::vector<int>* core_ring = nullptr) {
  const int N = spec.mesh.segments;
  const double w = spec.zone.half_width_mm, zt = spec.zone.z_max_mm, zc = spec.zone.core_z_max_mm;
  const double rc = polygon_radius(spec.zone.core_radius_mm, N, spec.mesh.equal_area);
  std::vector<int> cbr(static_cast<size_t>(N));  // core ring at z = top
  for (int k = 0; k < N; ++k) {
    const double a = 2.0 * kPi * k / N;
    cbr[static_cast<size_t>(k)] = core_ring ? (*core_ring)[static_cast<size_t>(k)]
                                            : plc.add_point({rc * std::cos(a), rc * std::sin(a), top});
  }
  auto cb_at = [&](int k) { return cbr[static_cast<size_t>(k % N)]; };
  const int ct = static_cast<int>(plc.points.size());  // core ring at z = zc
  for (int k = 0; k < N; ++k) {
    const double a = 2.0 * kPi * k / N;
    plc.add_point({rc * std::cos(a), rc * std::sin(a), zc});
  }
  const int sq = static_cast<int>(plc.points.size());  // square boundary on the rays, z = top
  for (int k = 0; k < N; ++k) {
    const double a = 2.0 * kPi * k / N, c = std::cos(a), s = std::sin(a);
    const double t = w / std::max(std::abs(c), std::abs(s));
    Eigen::Vector3d p(t * c, t * s, top);
    for (int d = 0; d < 2; ++d)
      if (std::abs(std::abs(p[d]) - w) < 1e-12 * w) p[d] = std::copysign(w, p[d]);  // exact on the side
    plc.add_point(p);
  }
  Plc::Facet core_top;
  for (int k = 0; k < N; ++k) {
    const int k1 = (k + 1) % N;
    if (!core_ring)
      plc.facets.push_back({{magnet_top_first + k, magnet_top_first + k1, cb_at(k1), cb_at(k)}});  // core bottom
    plc.facets.push_back({{cb_at(k), cb_at(k1), sq + k1, sq + k}});                                // zone bottom
    plc.facets.push_back({{cb_at(k), cb_at(k1), ct + k1, ct + k}});                                // core side
    core_top.polygon.push_back(ct + k);
  }
  plc.facets.push_back(core_top);
  // Box top corners (z = zt) at the rays 45, 135, 225, 315 deg: k = N/8 * (1, 3, 5, 7).
  const int tc = static_cast<int>(plc.points.size());
  const int corner_k[4] = {N / 8, 3 * N / 8, 5 * N / 8, 7 * N / 8};
  Plc::Facet box_top;
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d p = plc.points[sq + corner_k[i]];
    p.z() = zt;
    plc.add_point(p);
    box_top.polygon.push_back(tc + i);
  }
  plc.facets.push_back(box_top);
  // Sides: from corner i to corner i+1 along the square points at z = top, back along the top edge.
  for (int i = 0; i < 4; ++i) {
    Plc::Facet side;
    const int k0 = corner_k[i], k1 = corner_k[(i + 1) % 4] + (i == 3 ? N : 0);
    for (int k = k0; k <= k1; ++k) side.polygon.push_back(sq + k % N);
    side.polygon.push_back(tc + (i + 1) % 4);
    side.polygon.push_back(tc + i);
    plc.facets.push_back(side);
  }
  plc.regions.push_back({seed_at(0.5 * rc, 0.5 * (top + zc)), kRegionZone, tet_volume_for_edge(spec.mesh.h_core_mm)});
  plc.regions.push_back({seed_at(0.5 * (rc + w), 0.5 * (top + zt)), kRegionZone,
                         tet_volume_for_edge(spec.mesh.h_zone_mm)});
}


// Coaxial bodies of revolution given as rectangles of the meridian half-plane
// (r0..r1 x z0..z1, each with a region id), faceted as N-gon rings about the
// axis through `centre`. All rectangles share one grid of r and z breaks;
// every grid cell belongs to at most one rectangle (or to the air, id 0), and
// a facet is emitted wherever the owners of two neighbouring cells differ, as
// maximal runs of equal owner pairs. Bodies that touch (a holder around the
// magnet) so share their points and facets and the PLC stays conforming.
// force_z / force_r: facets are also emitted on the plane z = force_z for
// r <= force_r (the zone's bottom above the magnet); the ring at force_r there
// is returned in force_ring (N point ids).
// seed_each_cell: a seed in every grid cell the rectangle owns (an air rectangle that
// yields to the bodies inside it, as a ring's bore to a shaft through it; list it last),
// else one seed at the rectangle's middle.
struct AxiRect {
  double r0, r1, z0, z1;
  int region;
  double max_volume_mm3;
  bool seed_each_cell = false;
};

// Region seeds of add_bodies_of_revolution on its grid of r and z breaks: the middle of each rectangle
// (or of each grid cell it owns, seed_each_cell; a cell belongs to the first rectangle holding its middle),
// at the angle pi/128 (seed_at).
void add_axi_seeds(Plc& plc, const std::vector<AxiRect>& rects, const std::vector<double>& rb, const std::vector<double>& zb,
                   const Eigen::Vector2d& centre, int N, bool equal_area) {
  const double a = kPi / 128.0;
  const auto seed = [&](double r_mm, double z_mm, const AxiRect& q) {
    const double r = polygon_radius(r_mm, N, equal_area);
    plc.regions.push_back({{centre.x() + r * std::cos(a), centre.y() + r * std::sin(a), z_mm}, q.region, q.max_volume_mm3});
  };
  const auto owner = [&](double r, double z) {
    for (const auto& q : rects)
      if (r > q.r0 && r < q.r1 && z > q.z0 && z < q.z1) return q.region;
    return 0;
  };
  for (const auto& q : rects) {
    if (!q.seed_each_cell) {
      seed(0.5 * (q.r0 + q.r1), 0.5 * (q.z0 + q.z1), q);
      continue;
    }
    for (size_t i = 0; i + 1 < rb.size(); ++i)
      for (size_t j = 0; j + 1 < zb.size(); ++j) {
        const double r = 0.5 * (rb[i] + rb[i + 1]), z = 0.5 * (zb[j] + zb[j + 1]);
        if (owner(r, z) == q.region && rb[i] >= q.r0 && rb[i + 1] <= q.r1 && zb[j] >= q.z0 && zb[j + 1] <= q.z1)
          seed(r, z, q);
      }
  }
}

void add_bodies_of_revolution(Plc& plc, const std::vector<AxiRect>& rects, const Eigen::Vector2d& centre, int N,
                              bool equal_area, double force_z, double force_r, std::vector<int>* force_ring) {
  std::vector<double> rb{0.0}, zb;
  for (const auto& q : rects) {
    rb.insert(rb.end(), {q.r0, q.r1});
    zb.insert(zb.end(), {q.z0, q.z1});
  }
  const bool forced = force_ring != nullptr;
  if (forced) {
    rb.push_back(force_r);
    zb.push_back(force_z);
  }
  auto unique_sorted = [](std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  };
  unique_sorted(rb);
  unique_sorted(zb);
  const int nr = static_cast<int>(rb.size()), nz = static_cast<int>(zb.size());
  auto owner = [&](int i, int j) {  // cell [rb[i], rb[i+1]] x [zb[j], zb[j+1]]
    if (i < 0 || j < 0 || i >= nr - 1 || j >= nz - 1) return 0;
    const double r = 0.5 * (rb[i] + rb[i + 1]), z = 0.5 * (zb[j] + zb[j + 1]);
    for (const auto& q : rects)
      if (r > q.r0 && r < q.r1 && z > q.z0 && z < q.z1) return q.region;
    return 0;
  };
  std::map<std::array<int, 3>, int> ids;
  auto ring = [&](int i, int j, int k) {
    k %= N;
    const std::array<int, 3> key{i, j, k};
    auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const double rp = polygon_radius(rb[i], N, equal_area), a = 2.0 * kPi * k / N;
    const int id = plc.add_point({centre.x() + rp * std::cos(a), centre.y() + rp * std::sin(a), zb[j]});
    ids[key] = id;
    return id;
  };
  auto band = [&](int i0, int j0, int i1, int j1) {  // quads between the rings (i0, j0) and (i1, j1)
    for (int k = 0; k < N; ++k)
      plc.facets.push_back({{ring(i0, j0, k), ring(i0, j0, k + 1), ring(i1, j1, k + 1), ring(i1, j1, k)}});
  };
  const auto force_at = [&](int i, int j) { return forced && zb[j] == force_z && rb[i + 1] <= force_r; };
  // Cylindrical faces at r = rb[i], runs in z.
  for (int i = 1; i < nr; ++i) {
    int j = 0;
    while (j < nz - 1) {
      const int a = owner(i - 1, j), b = owner(i, j);
      if (a == b) {
        ++j;
        continue;
      }
      int e = j + 1;
      while (e < nz - 1 && owner(i - 1, e) == a && owner(i, e) == b && !(forced && zb[e] == force_z)) ++e;
      band(i, j, i, e);
      j = e;
    }
  }
  // Plane faces at z = zb[j], runs in r.
  for (int j = 0; j < nz; ++j) {
    int i = 0;
    while (i < nr - 1) {
      const int a = owner(i, j - 1), b = owner(i, j);
      const bool f = force_at(i, j);
      if (a == b && !f) {
        ++i;
        continue;
      }
      int e = i + 1;
      while (e < nr - 1 && owner(e, j - 1) == a && owner(e, j) == b && force_at(e, j) == f &&
             !(forced && rb[e] == force_r))
        ++e;
      if (rb[i] == 0.0) {
        Plc::Facet disk;
        for (int k = 0; k < N; ++k) disk.polygon.push_back(ring(e, j, k));
        plc.facets.push_back(disk);
      } else {
        band(i, j, e, j);
      }
      i = e;
    }
  }
  if (forced) {
    const int i = static_cast<int>(std::find(rb.begin(), rb.end(), force_r) - rb.begin());
    const int j = static_cast<int>(std::find(zb.begin(), zb.end(), force_z) - zb.begin());
    force_ring->clear();
    for (int k = 0; k < N; ++k) force_ring->push_back(ring(i, j, k));
  }
  add_axi_seeds(plc, rects, rb, zb, centre, N, equal_area);
}

void require_positive(const char* key, double v, const char* unit) {
  if (!(std::isfinite(v) && v > 0))
    throw InputError(std::string(key) + " = " + num(v) + " is out of range: allowed > 0 " + unit);
}

}  // namespace

double tet_volume_for_edge(double h_mm) { return h_mm * h_mm * h_mm / (6.0 * std::sqrt(2.0)); }

double polygon_radius(double R_mm, int segments, bool equal_area) {
  if (!equal_area) return R_mm;
  const double t = 2.0 * kPi / segments;
  return R_mm * std::sqrt(t / std::sin(t));
}

double DomainSpec::mu_r(int region) const {
  switch (region) {
    case kRegionMagnet: return magnet.mu_r;
    case kRegionShaft: return shaft.mu_r;
    default: break;
  }
  const int i = region - kRegionPartFirst;
  if (i >= 0 && i < static_cast<int>(parts.size())) return parts[static_cast<size_t>(i)].mu_r;
  return 1.0;
}

std::string to_string(PartShape s) {
  switch (s) {
    case PartShape::Cylinder: return "cylinder";
    case PartShape::Tube: return "tube";
    case PartShape::Cup: return "cup";
    case PartShape::Disk: return "disk";
  }
  return "?";
}

std::vector<PartSpec::Rect> PartSpec::rects() const {
  if (shape == PartShape::Cup)
    return {{r_inner_mm, r_outer_mm, z_min_mm + base_mm, z_max_mm}, {0.0, r_outer_mm, z_min_mm, z_min_mm + base_mm}};
  return {{r_inner_mm, r_outer_mm, z_min_mm, z_max_mm}};
}

bool DomainSpec::has_off_axis_part() const {
  return std::any_of(parts.begin(), parts.end(), [](const PartSpec& p) { return !p.coaxial(); });
}

// A B-H part is permeable whatever its start value mu_r (a curve whose first rows are convex starts at 1).
bool DomainSpec::has_permeable_part() const {
  return std::any_of(parts.begin(), parts.end(), [](const PartSpec& p) { return p.mu_r != 1.0 || p.bh != nullptr; });
}

bool DomainSpec::permeable_part_region(int region) const {
  const int i = region - kRegionPartFirst;
  if (i < 0 || i >= static_cast<int>(parts.size())) return false;
  const PartSpec& p = parts[static_cast<size_t>(i)];
  return p.mu_r != 1.0 || p.bh != nullptr;
}

bool DomainSpec::has_nonlinear_part() const {
  return std::any_of(parts.begin(), parts.end(), [](const PartSpec& p) { return p.bh != nullptr; });
}

bool DomainSpec::has_permeable_part_touching_magnet() const {
  const double top = 0.5 * magnet.height_mm, R = magnet.radius_mm;
  const double Ri = magnet.inner_radius_mm;
  for (const auto& p : parts) {
    if ((p.mu_r == 1.0 && !p.bh) || !p.coaxial()) continue;  // parts off the axis keep a gap to the magnet (validate)
    for (const auto& q : p.rects())
      if (q.r0 <= R && q.r1 >= Ri && q.z0 <= top && q.z1 >= -top) return true;  // closed meridian rectangles meet
  }
  return false;
}

namespace {

// One body for the overlap checks: its rectangles about the axis through (cx, cy).
struct Body {
  std::string what;
  double cx, cy;
  std::vector<PartSpec::Rect> rects;
  bool coaxial() const { return cx == 0.0 && cy == 0.0; }
};

// Two rectangles' interiors overlap (touching allowed).
bool open_overlap(const PartSpec::Rect& a, const PartSpec::Rect& b) {
  return a.r0 < b.r1 && b.r0 < a.r1 && a.z0 < b.z1 && b.z0 < a.z1;
}

// Bodies on different axes: their closed extents (solid discs of the outer radius) meet.
bool closed_meet(const Body& a, const Body& b) {
  const double d = std::hypot(a.cx - b.cx, a.cy - b.cy);
  for (const auto& p : a.rects)
    for (const auto& q : b.rects) {
      if (p.z0 > q.z1 || q.z0 > p.z1) continue;
      // Annulus q about b's axis against the disc of radius p.r1 about a's axis (and vice versa, conservative).
      if (d - p.r1 <= q.r1 && d + p.r1 >= q.r0 && d - q.r1 <= p.r1 && d + q.r1 >= p.r0) return true;
    }
  return false;
}

// The narrowest wall and gap the mesher is given: TetGen refines a gap of g between faces of area A into
// about A/g^2 elements (0.05 mm walls and 0.1 mm gaps about the default magnet mesh in seconds; 0.01 mm
// never ends, 1e-9 mm crashes TetGen). Bodies closer than this must touch (equal coordinates) instead.
constexpr double kMinFeature_mm = 0.05;

// Distance between two rectangles of the meridian half-plane (0 when they touch or overlap).
double rect_gap(const PartSpec::Rect& a, const PartSpec::Rect& b) {
  const double dr = std::max(a.r0 - b.r1, b.r0 - a.r1), dz = std::max(a.z0 - b.z1, b.z0 - a.z1);
  if (dr > 0 && dz > 0) return std::hypot(dr, dz);
  return std::max({dr, dz, 0.0});
}

// Walls and gaps the mesh can resolve (coaxial bodies; bodies off the axis keep a gap checked above).
void check_smallest_features(const Body& b, const std::vector<Body>& others) {
  for (const auto& q : b.rects) {
    const double wall = std::min(q.r1 - q.r0, q.z1 - q.z0);
    if (wall < kMinFeature_mm)
      throw InputError(b.what + " has a wall of " + num(wall) + " mm: allowed at least " + num(kMinFeature_mm) +
                       " mm (the mesher cannot resolve a thinner one)");
  }
  if (!b.coaxial()) return;
  for (const Body& o : others) {
    if (!o.coaxial()) continue;
    for (const auto& q : b.rects)
      for (const auto& r : o.rects) {
        const double g = rect_gap(q, r);
        if (g > 0 && g < kMinFeature_mm)
          throw InputError(b.what + " is " + num(g) + " mm from " + o.what + ": allowed touching it (equal coordinates) "
                           "or a gap of at least " + num(kMinFeature_mm) + " mm (the mesher cannot resolve a narrower one)");
      }
  }
}

void validate_part(const PartSpec& p, const std::string& what) {
  auto bad = [&](const std::string& why) { throw InputError(what + ": " + why); };
  auto finite = [&](const char* key, double v) {
    if (!std::isfinite(v)) bad(std::string(key) + " = " + num(v) + " is not a finite number");
  };
  finite("r_inner_mm", p.r_inner_mm);
  finite("r_outer_mm", p.r_outer_mm);
  finite("z_min_mm", p.z_min_mm);
  finite("z_max_mm", p.z_max_mm);
  finite("base_mm", p.base_mm);
  if (!std::isfinite(p.offset_x_mm) || !std::isfinite(p.offset_y_mm))
    bad("offset_mm = [" + num(p.offset_x_mm) + ", " + num(p.offset_y_mm) + "] is not a pair of finite numbers");
  if (!(p.r_outer_mm > 0)) bad("r_outer_mm = " + num(p.r_outer_mm) + " is out of range: allowed > 0 mm");
  if (!(p.r_inner_mm >= 0 && p.r_inner_mm < p.r_outer_mm))
    bad("r_inner_mm = " + num(p.r_inner_mm) + " is out of range: allowed [0, r_outer_mm = " + num(p.r_outer_mm) + ") mm");
  if (!(p.z_max_mm > p.z_min_mm))
    bad("z_max_mm = " + num(p.z_max_mm) + " is out of range: allowed > z_min_mm = " + num(p.z_min_mm) + " mm");
  if (p.shape == PartShape::Cylinder && p.r_inner_mm != 0)
    bad("r_inner_mm = " + num(p.r_inner_mm) + " is out of range for shape = cylinder: allowed 0 (use tube)");
  if ((p.shape == PartShape::Tube || p.shape == PartShape::Cup) && !(p.r_inner_mm > 0))
    bad("r_inner_mm = " + num(p.r_inner_mm) + " is out of range for shape = " + to_string(p.shape) + ": allowed > 0 mm");
  if (p.shape == PartShape::Cup && !(p.base_mm > 0 && p.base_mm < p.z_max_mm - p.z_min_mm))
    bad("base_mm = " + num(p.base_mm) + " is out of range for shape = cup: allowed (0, z_max_mm - z_min_mm = " +
        num(p.z_max_mm - p.z_min_mm) + ") mm");
  if (p.shape != PartShape::Cup && p.base_mm != 0)
    bad("base_mm = " + num(p.base_mm) + " is out of range for shape = " + to_string(p.shape) + ": allowed 0 (cup only)");
  if (!(std::isfinite(p.mu_r) && p.mu_r >= 1 && p.mu_r <= 1e6))
    bad("material mu_r = " + num(p.mu_r) + " is out of range: allowed [1, 1e6]");
}

}  // namespace

void DomainSpec::validate() const {
  magnet.validate();
  const MeshSpec& m = mesh;
  if (m.segments < 8 || m.segments > 4096)
    throw InputError("mesh.segments = " + std::to_string(m.segments) + " is out of range: allowed [8, 4096]");
  if (m.symmetric && magnet.is_uniform()) {  // a sector pattern is meshed whole (refuse_off_axis)
    const int N = m.symmetry_order;
    if (N < 2 || N > 64 || (N & (N - 1)) != 0)
      throw InputError("mesh.symmetry_order = " + std::to_string(N) + " is out of range: allowed 2, 4, 8, 16, 32 or 64");
    if (m.segments % N != 0)
      throw InputError("mesh.segments = " + std::to_string(m.segments) + " is out of range with mesh.symmetric = true: " +
                       "must be a multiple of mesh.symmetry_order = " + std::to_string(N) +
                       " (polygons with the mesh's mirror symmetry)");
  }
  if (!magnet.is_uniform()) validate_pattern_mesh();
  if (m.sphere_subdivisions < 1 || m.sphere_subdivisions > 6)
    throw InputError("mesh.sphere_subdivisions = " + std::to_string(m.sphere_subdivisions) +
                     " is out of range: allowed [1, 6]");
  require_positive("mesh.h_magnet_mm", m.h_magnet_mm, "mm");
  require_positive("mesh.h_zone_mm", m.h_zone_mm, "mm");
  require_positive("mesh.h_air_mm", m.h_air_mm, "mm");
  require_positive("mesh.outer_radius_mm", m.outer_radius_mm, "mm");
  const double R = magnet.radius_mm, L = magnet.height_mm;
  const double rp = polygon_radius(R, m.segments, m.equal_area);
  // Farthest magnet point from the origin must be well inside the truncation sphere.
  const double magnet_extent = shape == MagnetShape::Sphere ? R : std::hypot(rp, 0.5 * L);
  if (m.outer_radius_mm < 2.0 * magnet_extent)
    throw InputError("mesh.outer_radius_mm = " + num(m.outer_radius_mm) +
                     " is out of range: must be >= 2x the magnet's extent (" + num(2.0 * magnet_extent) +
                     " mm; >= 10x recommended)");
  const double top = shape == MagnetShape::Sphere ? R : 0.5 * L;
  if (zone.enabled) {
    require_positive("mesh.zone_half_width_mm", zone.half_width_mm, "mm");
    if (!(zone.z_max_mm > zone.z_min_mm))
      throw InputError("refinement zone is empty: z_max = " + num(zone.z_max_mm) + " <= z_min = " + num(zone.z_min_mm));
    if (zone.annulus()) validate_zone_annulus();
    else if (!(zone.z_min_mm > top))
      throw InputError("refinement zone bottom z = " + num(zone.z_min_mm) + " mm touches the magnet (top face at " +
                       num(top) + " mm): sensor.plane_height_mm must be > 0");
    const double corner = zone.annulus()
                              ? std::hypot(polygon_radius(zone.annulus_r1_mm, m.segments, m.equal_area),
                                           std::max(std::abs(zone.z_min_mm), std::abs(zone.z_max_mm)))
                              : Eigen::Vector3d(zone.half_width_mm, zone.half_width_mm,
                                                std::max(std::abs(zone.z_min_mm), std::abs(zone.z_max_mm))).norm();
    if (zone.core()) {
      require_positive("mesh.h_core_mm", m.h_core_mm, "mm");
      if (shape != MagnetShape::Cylinder)
        throw InputError("mesh.core_radius_mm = " + num(zone.core_radius_mm) + ": a zone core needs a cylinder magnet (use 0)");
      if (m.segments % 8 != 0)
        throw InputError("mesh.segments = " + std::to_string(m.segments) +
                         " is out of range with a zone core (mesh.core_radius_mm > 0): must be a multiple of 8");
      if (!(zone.core_radius_mm > 1.05 * rp && zone.core_radius_mm < 0.8 * zone.half_width_mm))
        throw InputError("mesh.core_radius_mm = " + num(zone.core_radius_mm) + " is out of range: allowed (" +
                         num(1.05 * rp) + ", " + num(0.8 * zone.half_width_mm) +
                         ") mm (beyond the magnet's radius, inside 0.8x mesh.zone_half_width_mm)");
      if (!zone.core_to_magnet() && !(zone.core_z_max_mm > zone.core_z_min_mm))
        throw InputError("zone core is empty: top z = " + num(zone.core_z_max_mm) + " <= bottom z = " + num(zone.core_z_min_mm));
      if (!(zone.core_z_max_mm > top && zone.core_z_max_mm < zone.z_max_mm))
        throw InputError("zone core top z = " + num(zone.core_z_max_mm) + " mm is out of range: allowed (" + num(top) +
                         ", " + num(zone.z_max_mm) + ") mm (mesh.core_top_above_plane_mm must be < mesh.zone_half_height_mm)");
    }
    if (corner >= 0.9 * m.outer_radius_mm)
      throw InputError("refinement zone (corner at " + num(corner) + " mm from the origin) reaches the truncation sphere: "
                       "mesh.outer_radius_mm = " + num(m.outer_radius_mm) + " must be > " + num(corner / 0.9) + " mm");
  }
  if (!parts.empty()) validate_parts();
  if (shaft.enabled) {
    require_positive("shaft.radius_mm", shaft.radius_mm, "mm");
    require_positive("shaft.length_mm", shaft.length_mm, "mm");
    require_positive("shaft.gap_mm", shaft.gap_mm, "mm");
    if (!(std::isfinite(shaft.mu_r) && shaft.mu_r >= 1))
      throw InputError("shaft.mu_r = " + num(shaft.mu_r) + " is out of range: allowed [1, 1e6]");
    const double z_far = -top - shaft.gap_mm - shaft.length_mm;
    const double ext = std::hypot(polygon_radius(shaft.radius_mm, m.segments, m.equal_area), z_far);
    if (ext >= 0.9 * m.outer_radius_mm)
      throw InputError("shaft reaches the truncation sphere (" + num(ext) + " mm from the origin): mesh.outer_radius_mm = " +
                       num(m.outer_radius_mm) + " must be > " + num(ext / 0.9) + " mm");
  }
}

void DomainSpec::validate_pattern_mesh() const {
  const std::string what = "magnet.pattern = " + pattern_name(magnet.pattern);
  if (shape != MagnetShape::Cylinder) throw InputError(what + " needs a cylinder magnet (the sphere is a validation case)");
  if (!magnet.is_multipole()) return;
  if (magnet.pole_edge_sigma_deg != 0.0)
    throw InputError(what + " with magnet.pole_edge_sigma_deg = " + num(magnet.pole_edge_sigma_deg) +
                     " is out of range for the FEM: allowed 0 (the mesh's sector facets lie on the ideal boundaries)");
  const long need = 4L * magnet.pole_pairs;
  if (mesh.segments % need != 0)
    throw InputError("mesh.segments = " + std::to_string(mesh.segments) + " is out of range with " + what +
                     ", magnet.pole_pairs = " + std::to_string(magnet.pole_pairs) + ": allowed a multiple of 4 pole_pairs = " +
                     std::to_string(need) + " (every sector boundary on a polygon vertex)");
}

void DomainSpec::validate_zone_annulus() const {
  const double top = 0.5 * magnet.height_mm, r0 = zone.annulus_r0_mm, r1 = zone.annulus_r1_mm;
  if (shape != MagnetShape::Cylinder) throw InputError("a refinement zone around the axis needs a cylinder magnet");
  if (!(r0 >= 0 && r1 > r0))
    throw InputError("refinement zone annulus r " + num(r0) + " to " + num(r1) + " mm is empty or negative");
  const bool beside = zone.z_min_mm < top && zone.z_max_mm > -top;
  if (beside && r1 > magnet.inner_radius_mm && r0 < magnet.radius_mm)
    throw InputError("refinement zone annulus r " + num(r0) + " to " + num(r1) + " mm, z " + num(zone.z_min_mm) + " to " +
                     num(zone.z_max_mm) + " mm overlaps the magnet (r " + num(magnet.inner_radius_mm) + " to " +
                     num(magnet.radius_mm) + " mm, z +-" + num(top) + " mm): a sensing point lies in or too near the "
                     "magnet's material (sensor.center_mm, sensor.r0_mm, sensor.plane_height_mm)");
}

namespace {

// build_plc with [[parts]]: the magnet, the shaft and the coaxial parts as one
// set of bodies of revolution (shared faces where they touch), the zone as in
// build_plc (with a core reaching the magnet, its bottom face split at every
// body's ring), then each off-axis part on its own axis.
// The refinement zone as a box around the sensing plane (no core reaching the magnet); a core
// cylinder, when set, nested inside the box, and the box's seed between core and box side.
void add_zone_box(Plc& plc, const DomainSpec& spec) {
  const MeshSpec& m = spec.mesh;
  const double w = spec.zone.half_width_mm;
  add_box(plc, {-w, -w, spec.zone.z_min_mm}, {w, w, spec.zone.z_max_mm});
  Eigen::Vector3d seed = seed_at(0.5 * w, 0.5 * (spec.zone.z_min_mm + spec.zone.z_max_mm));
  if (spec.zone.core()) {
    add_cylinder(plc, polygon_radius(spec.zone.core_radius_mm, m.segments, m.equal_area), m.segments,
                 spec.zone.core_z_min_mm, spec.zone.core_z_max_mm);
    const double rc = spec.zone.core_radius_mm;
    plc.regions.push_back({seed_at(0.5 * rc, 0.5 * (spec.zone.core_z_min_mm + spec.zone.core_z_max_mm)), kRegionZone,
                           tet_volume_for_edge(m.h_core_mm)});
    seed = seed_at(0.5 * (polygon_radius(rc, m.segments, m.equal_area) + w), seed.z());
  }
  plc.regions.push_back({seed, kRegionZone, tet_volume_for_edge(m.h_zone_mm)});
}

Plc build_plc_with_parts(const DomainSpec& spec) {
  const MeshSpec& m = spec.mesh;
  const double R = spec.magnet.radius_mm, top = 0.5 * spec.magnet.height_mm;
  const double v_body = tet_volume_for_edge(m.h_magnet_mm);
  Plc plc;
  add_sphere(plc, Eigen::Vector3d::Zero(), m.outer_radius_mm, m.sphere_subdivisions, false, true);
  std::vector<AxiRect> axial{{spec.magnet.inner_radius_mm, R, -top, top, kRegionMagnet, v_body}};
  if (spec.shaft.enabled) {
    const double z1 = -top - spec.shaft.gap_mm;
    axial.push_back({0.0, spec.shaft.radius_mm, z1 - spec.shaft.length_mm, z1, kRegionShaft, v_body});
  }
  for (size_t i = 0; i < spec.parts.size(); ++i) {
    const PartSpec& p = spec.parts[i];
    if (!p.coaxial()) continue;
    for (const auto& q : p.rects()) axial.push_back({q.r0, q.r1, q.z0, q.z1, kRegionPartFirst + static_cast<int>(i), v_body});
  }
  // A ring's bore: air closed by the planes of the magnet's faces and meshed like the magnet, except
  // where a body (a shaft) passes through it.
  if (spec.zone.annulus())
    axial.push_back({spec.zone.annulus_r0_mm, spec.zone.annulus_r1_mm, spec.zone.z_min_mm, spec.zone.z_max_mm, kRegionZone,
                     tet_volume_for_edge(m.h_zone_mm)});
  if (spec.magnet.is_ring())
    axial.push_back({0.0, spec.magnet.inner_radius_mm, -top, top, kRegionAir, v_body, true});
  std::vector<int> core_ring;
  const bool core = spec.zone.core_to_magnet();
  add_bodies_of_revolution(plc, axial, Eigen::Vector2d::Zero(), m.segments, m.equal_area, top,
                           spec.zone.core_radius_mm, core ? &core_ring : nullptr);
  if (spec.magnet.is_multipole())
    add_sector_facets(plc, spec.magnet, m.segments,
                      spec.magnet.is_ring() ? polygon_radius(spec.magnet.inner_radius_mm, m.segments, m.equal_area) : 0.0,
                      polygon_radius(R, m.segments, m.equal_area), v_body);
  if (core) {
    add_zone_with_core(plc, spec, -1, top, &core_ring);
  } else if (spec.zone.enabled && !spec.zone.annulus()) {
    add_zone_box(plc, spec);
  }
  for (size_t i = 0; i < spec.parts.size(); ++i) {
    const PartSpec& p = spec.parts[i];
    if (p.coaxial()) continue;
    std::vector<AxiRect> own;
    for (const auto& q : p.rects()) own.push_back({q.r0, q.r1, q.z0, q.z1, kRegionPartFirst + static_cast<int>(i), v_body});
    add_bodies_of_revolution(plc, own, {p.offset_x_mm, p.offset_y_mm}, m.segments, m.equal_area, 0, 0, nullptr);
  }
  plc.regions.push_back({seed_at(0.9 * m.outer_radius_mm, 0), kRegionAir, tet_volume_for_edge(m.h_air_mm)});
  return plc;
}

}  // namespace

void DomainSpec::validate_parts() const {
  const MeshSpec& m = mesh;
  if (shape != MagnetShape::Cylinder) throw InputError("parts need a cylinder magnet (the sphere is a validation case)");
  const double top = 0.5 * magnet.height_mm;
  std::vector<Body> bodies;
  bodies.push_back({"the magnet", 0, 0, {{magnet.inner_radius_mm, magnet.radius_mm, -top, top}}});
  if (shaft.enabled) {
    const double z1 = -top - shaft.gap_mm;
    bodies.push_back({"the shaft", 0, 0, {{0.0, shaft.radius_mm, z1 - shaft.length_mm, z1}}});
  }
  const double c = polygon_radius(1.0, m.segments, m.equal_area);
  for (size_t i = 0; i < parts.size(); ++i) {
    const PartSpec& p = parts[i];
    const std::string what = "parts element " + std::to_string(i + 1) + " of " + std::to_string(parts.size()) +
                             " ('" + p.name + "')";
    validate_part(p, what);
    const double d = std::hypot(p.offset_x_mm, p.offset_y_mm);
    const double ext = std::hypot(d + c * p.r_outer_mm, std::max(std::abs(p.z_min_mm), std::abs(p.z_max_mm)));
    if (ext >= 0.9 * m.outer_radius_mm)
      throw InputError(what + " reaches " + num(ext) + " mm from the origin, outside the domain: mesh.outer_radius_mm = " +
                       num(m.outer_radius_mm) + " must be > " + num(ext / 0.9) + " mm");
    Body b{what, p.offset_x_mm, p.offset_y_mm, p.rects()};
    check_smallest_features(b, bodies);
    for (const Body& o : bodies) {
      bool meet = false;
      if (b.coaxial() && o.coaxial()) {
        for (const auto& q : b.rects)
          for (const auto& r : o.rects) meet = meet || open_overlap(q, r);
        if (meet) throw InputError(what + " overlaps " + o.what + ": parts may touch, not overlap");
      } else if (closed_meet(b, o)) {
        throw InputError(what + " touches or overlaps " + o.what +
                         ": a part off the axis (offset_mm != [0, 0]) must keep a gap to every other body");
      }
    }
    // The refinement zone around the sensing plane stays air.
    if (zone.annulus()) {
      const Body z{"the refinement zone around the probes' circles", 0, 0,
                   {{zone.annulus_r0_mm, zone.annulus_r1_mm, zone.z_min_mm, zone.z_max_mm}}};
      bool meet = false;
      for (const auto& q : b.rects) meet = meet || (b.coaxial() ? open_overlap(q, z.rects[0]) : closed_meet(b, z));
      if (meet) throw InputError(what + " reaches " + z.what + " (r " + num(zone.annulus_r0_mm) + " to " +
                                 num(zone.annulus_r1_mm) + " mm, z " + num(zone.z_min_mm) + " to " + num(zone.z_max_mm) +
                                 " mm): allowed outside it");
    } else if (zone.enabled) {
      const double zb = zone.core_to_magnet() ? top : zone.z_min_mm, zt = zone.z_max_mm, w = zone.half_width_mm;
      for (const auto& q : b.rects) {
        // Distance in xy from the part's axis to the zone square, and the square's farthest corner.
        const double dx = std::max(0.0, std::abs(p.offset_x_mm) - w), dy = std::max(0.0, std::abs(p.offset_y_mm) - w);
        const double near = std::hypot(dx, dy), far = std::hypot(std::abs(p.offset_x_mm) + w, std::abs(p.offset_y_mm) + w);
        const bool xy = c * q.r1 > near && q.r0 < far;
        if (!xy) continue;
        const bool flush_ok = b.coaxial() && zone.core_to_magnet() && q.z1 == zb && q.r1 <= zone.core_radius_mm;
        if ((q.z0 < zt && zb < q.z1) || (q.z1 == zb && !flush_ok) || q.z0 == zt)
          throw InputError(what + " reaches the refinement zone (z " + num(zb) + " to " + num(zt) + " mm, half width " +
                           num(w) + " mm) around the sensing plane: allowed below or above it, or flush with the "
                           "magnet's top face within mesh.core_radius_mm = " + num(zone.core_radius_mm) + " mm");
      }
    }
    bodies.push_back(std::move(b));
  }
}

Plc build_plc(const DomainSpec& spec) {
  spec.validate();
  // A ring (its bore is air) is a body of revolution like the parts; the solid cylinder keeps its own PLC.
  if (!spec.parts.empty() || (spec.shape == MagnetShape::Cylinder && (spec.magnet.is_ring() || spec.zone.annulus())))
    return build_plc_with_parts(spec);
  const MeshSpec& m = spec.mesh;
  const double R = spec.magnet.radius_mm, L = spec.magnet.height_mm;
  Plc plc;
  // 1. Truncation sphere (air region seed just inside it).
  add_sphere(plc, Eigen::Vector3d::Zero(), m.outer_radius_mm, m.sphere_subdivisions, false, true);
  // 2. Magnet.
  double top = 0.5 * L;
  const int magnet_base = static_cast<int>(plc.points.size());
  if (spec.shape == MagnetShape::Cylinder) {
    add_cylinder(plc, polygon_radius(R, m.segments, m.equal_area), m.segments, -0.5 * L, 0.5 * L);
  } else {
    add_sphere(plc, Eigen::Vector3d::Zero(), R, m.sphere_subdivisions, m.equal_area, false);
    top = R;
  }
  plc.regions.push_back({seed_at(0.5 * R, 0), kRegionMagnet, tet_volume_for_edge(m.h_magnet_mm)});
  if (spec.magnet.is_multipole())
    add_sector_facets(plc, spec.magnet, m.segments, 0.0, polygon_radius(R, m.segments, m.equal_area),
                      tet_volume_for_edge(m.h_magnet_mm));
  // 3. Refinement zone around the sensing plane.
  if (spec.zone.core_to_magnet()) {
    add_zone_with_core(plc, spec, magnet_base + m.segments, top);
  } else if (spec.zone.enabled) {
    add_zone_box(plc, spec);
  }
  // 4. Shaft below the magnet.
  if (spec.shaft.enabled) {
    const double z1 = -top - spec.shaft.gap_mm, z0 = z1 - spec.shaft.length_mm;
    add_cylinder(plc, polygon_radius(spec.shaft.radius_mm, m.segments, m.equal_area), m.segments, z0, z1);
    const double rs = spec.shaft.radius_mm;
    plc.regions.push_back({seed_at(0.5 * rs, 0.5 * (z0 + z1)), kRegionShaft, tet_volume_for_edge(m.h_magnet_mm)});
  }
  // Air seed: 0.9 R_out from the origin in the plane z = 0, outside everything else
  // (zone, shaft end within 0.9 R_out and off this plane; inside the faceted sphere).
  plc.regions.push_back({seed_at(0.9 * m.outer_radius_mm, 0), kRegionAir, tet_volume_for_edge(m.h_air_mm)});
  return plc;
}

namespace {
void refuse_off_axis(const DomainSpec& spec) {
  if (!spec.magnet.is_uniform())
    throw InputError("magnet.pattern = " + pattern_name(spec.magnet.pattern) +
                     ": a symmetric mesh (mesh.symmetric = true) is refused for a sector pattern (its facets inside the "
                     "magnet and its parities are not the mirrored wedge's); use mesh.symmetric = false");
  for (const auto& p : spec.parts)
    if (!p.coaxial())
      throw InputError("part '" + p.name + "' is off the axis (offset_mm = [" + num(p.offset_x_mm) + ", " + num(p.offset_y_mm) +
                       "] mm): the domain has no mirror symmetry, a symmetric mesh (mesh.symmetric = true) is refused; "
                       "use mesh.symmetric = false");
}
}  // namespace

TetMesh mesh_quadrant(const DomainSpec& spec) {
  refuse_off_axis(spec);
  const int N = spec.mesh.symmetry_order;
  TetMesh q = replicate_wedge_to_quadrant(tetrahedralize_plc(clip_plc_to_wedge(build_plc(spec), N), spec.mesh.mesher), N);
  snap_quadrant_mesh(q);
  // Every remaining boundary face must lie on the truncation sphere (a face
  // left on an inner mirror plane would mean the wedge copies do not conform).
  for (Eigen::Index f = 0; f < q.boundary_faces.cols(); ++f)
    for (int k = 0; k < 3; ++k)
      if (q.nodes.col(q.boundary_faces(k, f)).norm() < 0.5 * spec.mesh.outer_radius_mm)
        throw ComputeError("symmetric mesh: the wedge copies do not conform (a boundary face inside the domain)");
  reorder_for_locality(q);
  return q;
}

TetMesh mesh_domain(const DomainSpec& spec) {
  if (!spec.mesh.symmetric) {
    TetMesh m = tetrahedralize_plc(build_plc(spec), spec.mesh.mesher);
    reorder_for_locality(m);
    return m;
  }
  refuse_off_axis(spec);
  return mirror_quadrant_mesh(mesh_quadrant(spec));
}

}  // namespace magenc::fem
