// The magnetization of a magnet with a sector pattern (magnet.pattern = radial, axial_multipole,
// radial_multipole; fields/multipole_field.hpp) on a mesh: the sector boundaries as facets of the PLC, so
// that no cell straddles two sectors, and Br per cell, piecewise constant.
//
// Facets: every boundary between two sectors (phi = (2 j - 1) 90/p deg, j = 1..2p) is a plane facet of the
// magnet's cross-section at that azimuth (Ri..R, -L/2..L/2; from the axis for a disk). It lies on polygon
// vertices of the faceted magnet only when mesh.segments is a multiple of 4 p (2 polygon edges per
// sector); DomainSpec::validate asks for that. Its outline takes every PLC point on its edges (rings that
// bodies touching the magnet add), and it is given as a fan of triangles about the cross-section's middle
// (a new point), so that no facet has nearly collinear vertices; for a disk the axis points at z = +-L/2
// and the facet's top and bottom edges are added as constraints of the magnet's end faces. Shifted sector boundaries (pole edge
// errors) do not lie on polygon vertices: the FEM refuses them. The radial pattern has no boundary.
//
// Cells: a magnet cell takes the sector of its centroid's azimuth: Br = q Br e_z (axial) or q Br e_rho at
// the centroid (radial, so a radial magnetization is piecewise constant per cell). Every vertex of the
// cell must lie in that closed sector (the facets make it so), else ComputeError.
#pragma once
#include <Eigen/Core>

#include "fields/magnet.hpp"
#include "field_solver/mesh/mesh.hpp"

namespace magenc::fem {

// Adds the sector boundary facets of `magnet` (a multipole pattern) to a PLC that already holds the
// magnet as N-gon rings of `segments` points (polygon radii rp_inner, rp_outer; rp_inner = 0 for a disk).
// Every sector becomes a closed region: a magnet seed (kRegionMagnet, max_volume_mm3) goes into each.
void add_sector_facets(Plc& plc, const Magnet& magnet, int segments, double rp_inner_mm, double rp_outer_mm,
                       double max_volume_mm3);

// Br (T, 3 x n_cells) of the cells of region kRegionMagnet, 0 elsewhere: the uniform magnet's
// remanence_T(), or the sector pattern's value per cell (above).
Eigen::Matrix3Xd magnet_cell_remanence(const TetMesh& mesh, const Magnet& magnet);

}  // namespace magenc::fem
