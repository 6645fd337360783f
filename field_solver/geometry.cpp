#include "geometry.hpp"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include "core/errors.hpp"
#include "symmetric_mesh.hpp"
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
void add_zone_with_core(Plc& plc, const DomainSpec& spec, int magnet_top_first, double top) {
  const int N = spec.mesh.segments;
  const double w = spec.zone.half_width_mm, zt = spec.zone.z_max_mm, zc = spec.zone.core_z_max_mm;
  const double rc = polygon_radius(spec.zone.core_radius_mm, N, spec.mesh.equal_area);
  const int cb = static_cast<int>(plc.points.size());  // core ring at z = top
  for (int k = 0; k < N; ++k) {
    const double a = 2.0 * kPi * k / N;
    plc.add_point({rc * std::cos(a), rc * std::sin(a), top});
  }
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
    plc.facets.push_back({{magnet_top_first + k, magnet_top_first + k1, cb + k1, cb + k}});  // core bottom
    plc.facets.push_back({{cb + k, cb + k1, sq + k1, sq + k}});                              // zone bottom
    plc.facets.push_back({{cb + k, cb + k1, ct + k1, ct + k}});                              // core side
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
    default: return 1.0;
  }
}

void DomainSpec::validate() const {
  magnet.validate();
  const MeshSpec& m = mesh;
  if (m.segments < 8 || m.segments > 4096)
    throw InputError("mesh.segments = " + std::to_string(m.segments) + " is out of range: allowed [8, 4096]");
  if (m.symmetric) {
    const int N = m.symmetry_order;
    if (N < 2 || N > 64 || (N & (N - 1)) != 0)
      throw InputError("mesh.symmetry_order = " + std::to_string(N) + " is out of range: allowed 2, 4, 8, 16, 32 or 64");
    if (m.segments % N != 0)
      throw InputError("mesh.segments = " + std::to_string(m.segments) + " is out of range with mesh.symmetric = true: " +
                       "must be a multiple of mesh.symmetry_order = " + std::to_string(N) +
                       " (polygons with the mesh's mirror symmetry)");
  }
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
    if (!(zone.z_min_mm > top))
      throw InputError("refinement zone bottom z = " + num(zone.z_min_mm) + " mm touches the magnet (top face at " +
                       num(top) + " mm): sensor.plane_height_mm must be > 0");
    const double corner = Eigen::Vector3d(zone.half_width_mm, zone.half_width_mm,
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

Plc build_plc(const DomainSpec& spec) {
  spec.validate();
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
  // 3. Refinement zone around the sensing plane.
  if (spec.zone.core_to_magnet()) {
    add_zone_with_core(plc, spec, magnet_base + m.segments, top);
  } else if (spec.zone.enabled) {
    const double w = spec.zone.half_width_mm;
    add_box(plc, {-w, -w, spec.zone.z_min_mm}, {w, w, spec.zone.z_max_mm});
    Eigen::Vector3d seed = seed_at(0.5 * w, 0.5 * (spec.zone.z_min_mm + spec.zone.z_max_mm));
    if (spec.zone.core()) {  // core cylinder nested inside the box; box seed between core and box side
      add_cylinder(plc, polygon_radius(spec.zone.core_radius_mm, m.segments, m.equal_area), m.segments,
                   spec.zone.core_z_min_mm, spec.zone.core_z_max_mm);
      const double rc = spec.zone.core_radius_mm;
      plc.regions.push_back({seed_at(0.5 * rc, 0.5 * (spec.zone.core_z_min_mm + spec.zone.core_z_max_mm)), kRegionZone,
                             tet_volume_for_edge(m.h_core_mm)});
      seed = seed_at(0.5 * (polygon_radius(rc, m.segments, m.equal_area) + w), seed.z());
    }
    plc.regions.push_back({seed, kRegionZone, tet_volume_for_edge(m.h_zone_mm)});
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

TetMesh mesh_quadrant(const DomainSpec& spec) {
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
  return mirror_quadrant_mesh(mesh_quadrant(spec));
}

}  // namespace magenc::fem
