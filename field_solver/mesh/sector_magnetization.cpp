#include "field_solver/mesh/sector_magnetization.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/units.hpp"
#include "fields/multipole_field.hpp"

namespace magenc::fem {
namespace {

// The polygon vertex index k (0..segments-1) of the azimuth phi_rad; ComputeError when phi is not one.
int vertex_index(double phi_rad, int segments) {
  const double x = phi_rad * segments / (2.0 * kPi);
  const double k = std::round(x);
  if (std::abs(x - k) > 1e-9)
    throw ComputeError("sector boundary at " + num(rad_to_deg(phi_rad)) + " deg is not a polygon vertex of mesh.segments = " +
                       std::to_string(segments));
  return static_cast<int>(((static_cast<long>(k) % segments) + segments) % segments);
}

// Finds the point (or adds it) at exactly p.
int find_or_add(Plc& plc, const Eigen::Vector3d& p) {
  for (size_t i = 0; i < plc.points.size(); ++i)
    if (plc.points[i] == p) return static_cast<int>(i);
  return plc.add_point(p);
}

}  // namespace

void add_sector_facets(Plc& plc, const Magnet& magnet, int segments, double rp_inner_mm, double rp_outer_mm,
                       double max_volume_mm3) {
  const std::vector<MagnetSector> sectors = pattern_sectors(magnet);
  if (sectors.size() < 2) return;  // radial: one sector, no boundary
  const double top = magnet.top_z_mm(), scale = std::max(rp_outer_mm, top);
  const double tol = 1e-9 * scale;
  const bool disk = rp_inner_mm == 0.0;
  const int centre_top = disk ? find_or_add(plc, {0.0, 0.0, top}) : -1;
  const int centre_bottom = disk ? find_or_add(plc, {0.0, 0.0, -top}) : -1;
  const size_t n_points = plc.points.size();
  for (const MagnetSector& sec : sectors) {
    const int k = vertex_index(sec.phi_a_rad, segments);
    const double a = 2.0 * kPi * k / segments, c = std::cos(a), s = std::sin(a);
    // The PLC points on the outline of the cross-section at azimuth a, by their position along it:
    // bottom edge (r up), outer face (z up), top edge (r down), inner face or axis (z down).
    std::vector<std::pair<double, int>> outline;
    for (size_t i = 0; i < n_points; ++i) {
      const Eigen::Vector3d& p = plc.points[i];
      const double r = p.x() * c + p.y() * s;
      if (std::abs(p.y() * c - p.x() * s) > tol || std::abs(p.z()) > top + tol) continue;
      if (static_cast<int>(i) == centre_top || static_cast<int>(i) == centre_bottom) {
        outline.emplace_back(p.z() > 0 ? 3.0 : 0.0, static_cast<int>(i));
        continue;
      }
      if (r < rp_inner_mm - tol || r > rp_outer_mm + tol || r <= tol) continue;
      const double w = rp_outer_mm - rp_inner_mm, h = 2.0 * top;
      double t;
      if (std::abs(p.z() + top) <= tol && r < rp_outer_mm - tol) t = (r - rp_inner_mm) / w;
      else if (std::abs(r - rp_outer_mm) <= tol && p.z() < top - tol) t = 1.0 + (p.z() + top) / h;
      else if (std::abs(p.z() - top) <= tol && r > rp_inner_mm + tol) t = 2.0 + (rp_outer_mm - r) / w;
      else if (std::abs(r - rp_inner_mm) <= tol) t = 3.0 + (top - p.z()) / h;
      else continue;  // inside the cross-section: no body reaches there
      outline.emplace_back(t, static_cast<int>(i));
    }
    std::sort(outline.begin(), outline.end());
    if (outline.size() < 4)
      throw ComputeError("sector boundary at " + num(rad_to_deg(a)) + " deg: the magnet's outline has " +
                         std::to_string(outline.size()) + " points in its plane (4 or more expected)");
    // The cross-section as a fan of triangles about its middle: no facet holds three nearly collinear
    // vertices (the rings a touching body adds on an edge lie on the ray only to rounding, and a polygon
    // with such flat corners makes TetGen's segment recovery fail).
    const double rm = 0.5 * (rp_inner_mm + rp_outer_mm);
    const int middle = plc.add_point({rm * c, rm * s, 0.0});
    for (size_t i = 0; i < outline.size(); ++i)
      plc.facets.push_back({{middle, outline[i].second, outline[(i + 1) % outline.size()].second}});
    // A disk: the facet's top and bottom edges run from the axis across the end faces (the disk facets
    // around the axis); they are constraints of those faces.
    if (disk)
      for (const int centre : {centre_top, centre_bottom}) {
        const double z = plc.points[static_cast<size_t>(centre)].z();
        int nearest = -1;  // the outline's point on this end face nearest the axis
        for (const auto& [t, id] : outline) {
          const Eigen::Vector3d& p = plc.points[static_cast<size_t>(id)];
          if (id == centre || std::abs(p.z() - z) > tol) continue;
          if (nearest < 0 || p.head<2>().norm() < plc.points[static_cast<size_t>(nearest)].head<2>().norm()) nearest = id;
        }
        for (Plc::Facet& face : plc.facets) {
          const bool holds = std::find(face.polygon.begin(), face.polygon.end(), nearest) != face.polygon.end();
          const bool flat = std::all_of(face.polygon.begin(), face.polygon.end(), [&](int q) {
            return plc.points[static_cast<size_t>(q)].z() == z;
          });
          // The face around the axis: flat at z, through the nearest point, and every point at its radius.
          const double rn = plc.points[static_cast<size_t>(nearest)].head<2>().norm();
          const bool round = std::all_of(face.polygon.begin(), face.polygon.end(), [&](int q) {
            return std::abs(plc.points[static_cast<size_t>(q)].head<2>().norm() - rn) <= tol;
          });
          if (holds && flat && round && static_cast<int>(face.polygon.size()) == segments)
            face.constraints.push_back({centre, nearest});
        }
      }
    // Every sector is a closed region now: a magnet seed in each (mid-azimuth, mid-radius, mid-plane).
    const double mid = 0.5 * (sec.phi_a_rad + sec.phi_b_rad);
    plc.regions.push_back({{rm * std::cos(mid), rm * std::sin(mid), 0.0}, kRegionMagnet, max_volume_mm3});
  }
}

Eigen::Matrix3Xd magnet_cell_remanence(const TetMesh& mesh, const Magnet& magnet) {
  Eigen::Matrix3Xd b = Eigen::Matrix3Xd::Zero(3, mesh.num_tets());
  if (magnet.is_uniform()) {
    const Eigen::Vector3d br_T = magnet.remanence_T();
    for (int t = 0; t < mesh.num_tets(); ++t)
      if (mesh.region[t] == kRegionMagnet) b.col(t) = br_T;
    return b;
  }
  const std::vector<MagnetSector> sectors = pattern_sectors(magnet);
  const bool axial = magnet.pattern == MagnetPattern::AxialMultipole;
  const double tol = 1e-9 * magnet.radius_mm;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (mesh.region[t] != kRegionMagnet) continue;
    Eigen::Vector3d cen = Eigen::Vector3d::Zero();
    for (int v = 0; v < 4; ++v) cen += 0.25 * mesh.nodes.col(mesh.tets(v, t));
    const double phi = std::atan2(cen.y(), cen.x());
    const MagnetSector* in = nullptr;
    for (const MagnetSector& s : sectors)
      if (std::fmod(phi - s.phi_a_rad + 8 * kPi, 2 * kPi) < s.phi_b_rad - s.phi_a_rad) in = &s;
    if (!in) throw ComputeError("magnet cell " + std::to_string(t) + " lies in no sector of magnet.pattern");
    // Every vertex in the closed sector (off the axis): the cell does not straddle a boundary.
    const double mid = 0.5 * (in->phi_a_rad + in->phi_b_rad), half = 0.5 * (in->phi_b_rad - in->phi_a_rad);
    for (int v = 0; v < 4; ++v) {
      const Eigen::Vector3d x = mesh.nodes.col(mesh.tets(v, t));
      const double r = x.head<2>().norm();
      if (r > tol && std::abs(std::remainder(std::atan2(x.y(), x.x()) - mid, 2 * kPi)) > half + tol / r)
        throw ComputeError("magnet cell " + std::to_string(t) + " straddles a sector boundary of magnet.pattern = " +
                           pattern_name(magnet.pattern) + " (the mesh does not conform to the sectors)");
    }
    const double rc = cen.head<2>().norm();
    b.col(t) = axial ? Eigen::Vector3d(0.0, 0.0, magnet.br_T * in->q)
                     : Eigen::Vector3d(magnet.br_T * in->q * cen.x() / rc, magnet.br_T * in->q * cen.y() / rc, 0.0);
  }
  return b;
}

}  // namespace magenc::fem
