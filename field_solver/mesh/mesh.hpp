// Plain mesh data shared by the mesher adapter and the FEM: a piecewise linear
// complex (PLC, the mesher's input) and a tetrahedral mesh (its output).
// All coordinates in mm (units.hpp). No mesher types leak out of here.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace magenc::fem {

// Region ids carried by every tetrahedron (cell data `region` in mesh.vtu).
enum RegionId : int {
  kRegionMagnet = 1,  // permanent magnet: mu_r = magnet.mu_r, remanence Br
  kRegionAir = 2,     // air out to the truncation sphere, mu_r = 1
  kRegionZone = 3,    // air in the refinement zone around the sensing plane
  kRegionShaft = 4,   // optional soft-magnetic shaft under the magnet
  kRegionPartFirst = 10,  // [[parts]]: part i carries kRegionPartFirst + i
};

// Piecewise linear complex: closed polygonal facets bounding the regions,
// plus one seed point per region with its id and maximum tet volume.
struct Plc {
  struct Facet {
    std::vector<int> polygon;  // indices into points, planar polygon, >= 3 vertices
    // Further polygons in the same plane that the facet's triangulation must
    // contain: segments (2 vertices) and isolated vertices (1), e.g. where an
    // internal surface meets a symmetry plane.
    std::vector<std::vector<int>> constraints = {};  // (= {}: facets are brace-initialized from polygons)
    bool outer = false;  // part of the domain's outer boundary (the truncation sphere)
  };
  struct Region {
    Eigen::Vector3d seed_mm;   // a point strictly inside the region
    int id = 0;                // RegionId
    double max_volume_mm3 = 0; // TetGen volume constraint (<= 0: none)
  };
  std::vector<Eigen::Vector3d> points;  // vertices (mm)
  std::vector<Facet> facets;
  std::vector<Region> regions;

  int add_point(const Eigen::Vector3d& p) {
    points.push_back(p);
    return static_cast<int>(points.size()) - 1;
  }
};

// Conforming tetrahedral mesh (linear geometry).
struct TetMesh {
  Eigen::Matrix3Xd nodes;           // 3 x n_nodes vertex coordinates (mm)
  Eigen::Matrix4Xi tets;            // 4 x n_tets vertex indices, positively oriented
  Eigen::VectorXi region;           // n_tets region ids (RegionId)
  Eigen::Matrix3Xi boundary_faces;  // 3 x n_faces triangles of the outer boundary

  int num_nodes() const { return static_cast<int>(nodes.cols()); }
  int num_tets() const { return static_cast<int>(tets.cols()); }
};

// For every face of tets (face 4 t + k: the one opposite vertex k of tet t), the face of another
// tet with the same three vertices, or -1 when no other tet has them (a boundary face). Faces with
// the same vertices pair up in the order of their index; the odd one of three or more gets -2.
std::vector<int> face_partners(const Eigen::Matrix4Xi& tets, int num_nodes);

// Renumbers nodes and tets for memory locality (the mesh itself is unchanged): nodes in the
// order of their Morton (Z-order) code over the bounding box, tets by their smallest new
// vertex id (ties in their previous order); tets keep their local vertex order, and
// boundary_faces are renumbered and sorted as finalize_mesh sorts them. Neighbouring
// nodes get nearby ids, so the gathers and scatters of assembly, sparse products and
// point location touch few cache lines. Deterministic.
void reorder_for_locality(TetMesh& mesh);

// Fills boundary_faces with the faces that belong to exactly one tet and makes
// every tet positively oriented (det of its edge matrix > 0).
void finalize_mesh(TetMesh& mesh);

}  // namespace magenc::fem
