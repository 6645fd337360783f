// Symmetric meshing. Every geometry of this solver (a coaxial magnet, zone
// box and core, shaft, truncation sphere) is symmetric under the reflections
// x -> -x and y -> -y, and all but the square zone box also under the
// reflections across the planes at phi = k*pi/N through the z axis (the
// dihedral group D_N; N a power of two dividing mesh.segments). An
// unstructured TetGen mesh of the whole domain is not, and its asymmetry
// shows up as small spurious angle-error harmonics (ideal-mount c1, c3 of
// ~0.002 deg on the 0.1.0 default mesh) that move at random with any mesh
// change. Meshing one wedge 0 <= phi <= pi/N and reflecting it gives a mesh
// with the D_N symmetry, so the discrete solution has it too (to the CG
// tolerance): for magnetization along x it has, besides its cos(phi) part,
// only the angular harmonics kN +- 1, and the ideal-mount angle error of
// `two` and `diff4` has no harmonics below N (N = 2: only 4, 8, ...).
//
//   clip_plc_to_wedge           the full PLC cut to the wedge, plus the two
//                               symmetry facets carrying every intersection
//                               line of an internal surface
//   replicate_wedge_to_quadrant the wedge's tets reflected N/2 - 1 times to
//                               fill the quadrant x, y >= 0 (N = 2: as is)
//   snap_quadrant_mesh          nodes onto x = 0, y = 0; outer boundary only
//   mirror_quadrant_mesh        the quadrant reflected into all four quadrants
//   mirror_dof_map              dof images, for solving on the quadrant only
#pragma once
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

// Cuts every facet of `full` to the wedge 0 <= phi <= pi/N (N = `sectors`:
// 2, 4, ..., 64; N = 2 is the quadrant x, y >= 0; points within 1e-12 of the
// domain size of a plane count as on it, and on x = 0 or y = 0 are snapped
// onto it), drops the pieces outside, and adds the two symmetry facets, closed
// by their cut edges of the outer boundary (facets with `outer` set) and the
// z axis. Region seeds must lie strictly inside the wedge. Parts that are not
// D_N symmetric (the square zone box for N > 4) become their wedge's mirror
// images (an N-gon prism of the box's inradius). Throws ComputeError when the
// cut does not close (a geometry that does not contain the z axis).
Plc clip_plc_to_wedge(const Plc& full, int sectors);

// Reflects a mesh of the wedge N/2 - 1 times (alternately across its two
// planes) to fill the quadrant; the nodes on the shared planes keep one id,
// so the result is conforming. N = 2 returns the mesh as is.
TetMesh replicate_wedge_to_quadrant(const TetMesh& wedge, int sectors);

// Prepares a TetGen mesh of the quadrant for solving and mirroring: nodes
// within 1e-9 of the domain size of a symmetry plane are snapped onto it
// (ComputeError for a node outside the quadrant), and boundary_faces keeps
// only the outer boundary (faces on x = 0 or y = 0 are symmetry faces).
void snap_quadrant_mesh(TetMesh& quadrant);

// Reflects a mesh of the quadrant (all nodes x >= 0, y >= 0 up to 1e-9 of the
// domain size; nodes that close to a plane are snapped onto it) across x = 0
// and y = 0. Nodes on a symmetry plane are shared, so the result is
// conforming; finalize_mesh recomputes orientation and the outer boundary, and
// reorder_for_locality numbers nodes and tets for memory locality.
// Throws ComputeError if a face on a symmetry plane has no partner (the
// boundary would then contain symmetry-plane faces).
TetMesh mirror_quadrant_mesh(const TetMesh& quadrant);

// Solving on the quadrant: for magnetization along x the potential is odd in
// x and even in y (psi = 0 on x = 0, natural condition on y = 0), along y the
// reverse.
// Maps every dof point of the whole domain (3 x n, mm) to the quadrant's dof
// at (|x|, |y|, z) (3 x m points, mm; exact coordinates, as mirroring
// produces them). ComputeError if a point has no image.
std::vector<int> mirror_dof_map(const Eigen::Matrix3Xd& full_points_mm, const Eigen::Matrix3Xd& quadrant_points_mm);

}  // namespace magenc::fem
