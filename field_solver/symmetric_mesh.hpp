// Mirror-symmetric meshing. Every geometry of this solver (a coaxial magnet,
// zone box and core, shaft, truncation sphere) is symmetric under the
// reflections x -> -x and y -> -y. An unstructured TetGen mesh of the whole
// domain is not, and its asymmetry shows up as small spurious angle-error
// harmonics (ideal-mount c1, c3 of ~0.002 deg on the default mesh) that move
// at random with any mesh change. Meshing one quadrant (x >= 0, y >= 0) and
// reflecting it gives a mesh with the domain's symmetry, so the discrete
// solution has it too (to the CG tolerance): for magnetization along x, psi
// is odd in x and even in y, and the ideal-mount angle error of a quadrature
// pair has only harmonics 4, 8, ...
//
//   clip_plc_to_quadrant   the full PLC cut to x >= 0, y >= 0, plus the two
//                          symmetry facets (x = 0, y = 0) carrying every
//                          intersection line of an internal surface
//   mirror_quadrant_mesh   the quadrant's tets reflected into all four
//                          quadrants, nodes on the symmetry planes shared
#pragma once
#include "mesh.hpp"

namespace magenc::fem {

// Cuts every facet of `full` to the quadrant x >= 0, y >= 0 (coordinates
// within 1e-12 of the domain size of a plane are snapped onto it), drops the
// pieces outside, and adds the symmetry facets. Facets with `outer` set bound
// the domain; the symmetry facets are closed by their cut edges and the z
// axis. Region seeds must lie strictly inside the quadrant. Throws
// ComputeError when the cut does not close (a geometry that is not
// symmetric or does not contain the z axis).
Plc clip_plc_to_quadrant(const Plc& full);

// More symmetry: every part is also symmetric under reflection across the
// planes at phi = k*pi/N through the z axis (the dihedral group D_N; N a power
// of two dividing mesh.segments). clip_plc_to_wedge cuts the PLC to the wedge
// 0 <= phi <= pi/N (N = 2: the quadrant), and replicate_wedge_to_quadrant
// reflects the wedge's mesh N/2 - 1 times to fill the quadrant with a mesh
// that has the D_N symmetry (nodes on the shared planes shared). On such a
// mesh the discrete field of magnetization along x has, besides its cos(phi)
// part, only the angular harmonics n = kN +- 1, so the ideal-mount angle error
// of `two` and `diff4` has no harmonics below N. Parts that are not D_N
// symmetric (the square zone box) become their wedge's mirror images (an
// N-gon prism of the box's inradius).
Plc clip_plc_to_wedge(const Plc& full, int sectors);
TetMesh replicate_wedge_to_quadrant(const TetMesh& wedge, int sectors);

// Prepares a TetGen mesh of the quadrant for solving and mirroring: nodes
// within 1e-9 of the domain size of a symmetry plane are snapped onto it
// (ComputeError for a node outside the quadrant), and boundary_faces keeps
// only the outer boundary (faces on x = 0 or y = 0 are symmetry faces).
void snap_quadrant_mesh(TetMesh& quadrant);

// Reflects a mesh of the quadrant (all nodes x >= 0, y >= 0 up to 1e-9 of the
// domain size; nodes that close to a plane are snapped onto it) across x = 0
// and y = 0. Nodes on a symmetry plane are shared, so the result is
// conforming; finalize_mesh recomputes orientation and the outer boundary.
// Throws ComputeError if a face on a symmetry plane has no partner (the
// boundary would then contain symmetry-plane faces).
TetMesh mirror_quadrant_mesh(const TetMesh& quadrant);

// Solving on the quadrant: for magnetization along x the potential is odd in
// x and even in y (psi = 0 on x = 0, natural condition on y = 0), along y the
// reverse. Parity of component c (0: x, 1: y) under reflecting axis d.
inline bool odd_under_reflection(int component, int axis) { return component == axis; }

// Maps every dof point of the whole domain (3 x n, mm) to the quadrant's dof
// at (|x|, |y|, z) (3 x m points, mm; exact coordinates, as mirroring
// produces them). ComputeError if a point has no image.
std::vector<int> mirror_dof_map(const Eigen::Matrix3Xd& full_points_mm, const Eigen::Matrix3Xd& quadrant_points_mm);

}  // namespace magenc::fem
