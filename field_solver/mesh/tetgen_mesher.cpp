// TetGen adapter: PLC in, plain TetMesh out. The only file that includes tetgen.h.
#define TETLIBRARY
#include <tetgen.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "field_solver/mesh/tetgen_mesher.hpp"

namespace magenc::fem {
namespace {

std::string tetgen_reason(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "self-intersecting input facets (regions overlap or touch)";
    case 4: return "input feature smaller than TetGen's tolerance";
    case 5: return "two input facets too close to each other";
    case 10: return "invalid input";
    default: return "error code " + std::to_string(code);
  }
}

}  // namespace

TetMesh tetrahedralize_plc(const Plc& plc, const MesherOptions& options) {
  if (plc.points.empty() || plc.facets.empty())
    throw ComputeError("TetGen: empty geometry (no facets)");
  tetgenio in, out;
  // 1. Points.
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(plc.points.size());
  in.pointlist = new REAL[3 * in.numberofpoints];
  for (int i = 0; i < in.numberofpoints; ++i)
    for (int d = 0; d < 3; ++d) in.pointlist[3 * i + d] = plc.points[i][d];
  // 2. Facets: the boundary polygon, then any constraint segments / vertices in its plane.
  in.numberoffacets = static_cast<int>(plc.facets.size());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  in.facetmarkerlist = new int[in.numberoffacets];
  for (int f = 0; f < in.numberoffacets; ++f) {
    tetgenio::facet& tf = in.facetlist[f];
    tetgenio::init(&tf);
    const auto& facet = plc.facets[f];
    tf.numberofpolygons = 1 + static_cast<int>(facet.constraints.size());
    tf.polygonlist = new tetgenio::polygon[tf.numberofpolygons];
    for (int p = 0; p < tf.numberofpolygons; ++p) {
      const auto& poly = p == 0 ? facet.polygon : facet.constraints[static_cast<size_t>(p - 1)];
      tetgenio::polygon& tp = tf.polygonlist[p];
      tetgenio::init(&tp);
      tp.numberofvertices = static_cast<int>(poly.size());
      tp.vertexlist = new int[poly.size()];
      for (size_t k = 0; k < poly.size(); ++k) tp.vertexlist[k] = poly[k];
    }
    in.facetmarkerlist[f] = 1;
  }
  // 3. Regions: seed, attribute (region id), max volume.
  in.numberofregions = static_cast<int>(plc.regions.size());
  in.regionlist = new REAL[5 * in.numberofregions];
  for (int r = 0; r < in.numberofregions; ++r) {
    const auto& reg = plc.regions[r];
    for (int d = 0; d < 3; ++d) in.regionlist[5 * r + d] = reg.seed_mm[d];
    in.regionlist[5 * r + 3] = reg.id;
    in.regionlist[5 * r + 4] = reg.max_volume_mm3 > 0 ? reg.max_volume_mm3 : -1.0;
  }
  // 4. Tetrahedralize: p (PLC), q (quality), A (region attributes), a (region volumes).
  std::ostringstream sw;
  sw << "pq" << options.radius_edge_ratio << "/" << options.min_dihedral_deg << "Aa"
     << (options.verbose ? "V" : "Q");
  if (options.max_added_points > 0) sw << "S" << options.max_added_points;
  std::string switches = sw.str();
  try {
    std::fflush(stdout);
    tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    throw ComputeError("TetGen failed: " + tetgen_reason(code));
  }
  if (options.max_added_points > 0 && long(out.numberofpoints) - long(in.numberofpoints) >= options.max_added_points)
    throw InputError("the mesher reached its budget of " + std::to_string(options.max_added_points) +
                     " added points (4 per 5 tetrahedra of the mesh sizes' estimate): allowed geometry the mesh "
                     "sizes resolve (a wall or gap of [[parts]] far below mesh.h_* makes the mesh grow without end)");
  if (out.numberoftetrahedra <= 0 || out.numberoftetrahedronattributes < 1)
    throw ComputeError("TetGen failed: no tetrahedra with region attributes produced");
  // 5. Copy out into the plain mesh struct.
  TetMesh mesh;
  mesh.nodes.resize(3, out.numberofpoints);
  for (int i = 0; i < out.numberofpoints; ++i)
    for (int d = 0; d < 3; ++d) mesh.nodes(d, i) = out.pointlist[3 * i + d];
  mesh.tets.resize(4, out.numberoftetrahedra);
  mesh.region.resize(out.numberoftetrahedra);
  const int nc = out.numberofcorners;  // 4 (linear)
  const int na = out.numberoftetrahedronattributes;
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    for (int k = 0; k < 4; ++k) mesh.tets(k, t) = out.tetrahedronlist[nc * t + k] - out.firstnumber;
    mesh.region[t] = static_cast<int>(out.tetrahedronattributelist[na * t] + 0.5);
  }
  finalize_mesh(mesh);
  return mesh;
}

}  // namespace magenc::fem
