// Geometry of the magnetostatic problem: the magnet, air out to a truncation
// sphere, a refinement zone around the sensing plane and optional extra
// regions (a soft-magnetic shaft under the magnet). Builds the PLC that the
// mesher adapter turns into tets. Magnet frame, all lengths in mm.
#pragma once
#include <string>
#include <vector>

#include <memory>

#include "field_solver/mesh/bh_curve.hpp"
#include "fields/magnet.hpp"
#include "field_solver/mesh/mesh.hpp"
#include "field_solver/mesh/tetgen_mesher.hpp"

namespace magenc::fem {

enum class MagnetShape { Cylinder, Sphere };  // Sphere: radius = magnet.radius_mm (validation case)

// Defaults of the [mesh] keys: fem_keys() (fem_config.cpp) declares the keys
// with these values and MeshSpec and ZoneSpec start from them, so a default
// DomainSpec meshes like a default solve_field run. Test meshes set their own
// values (meshes/coarse.toml, tests/fem/fem_test_util.hpp).
namespace mesh_defaults {
inline constexpr int kSegments = 64;
inline constexpr bool kEqualArea = true;
inline constexpr double kHMagnet_mm = 0.3;
inline constexpr double kHZone_mm = 0.3;
inline constexpr double kHCore_mm = 0.10;
inline constexpr double kHAir_mm = 12.0;
inline constexpr double kOuterRadius_mm = 60.0;
inline constexpr int kSphereSubdivisions = 3;
inline constexpr bool kSymmetric = true;
inline constexpr int kSymmetryOrder = 16;
inline constexpr double kZoneHalfWidth_mm = 7.0;
inline constexpr double kZoneHalfHeight_mm = 1.3;
inline constexpr double kCoreRadius_mm = 3.2;
inline constexpr double kCoreTopAbovePlane_mm = 0.6;
inline constexpr double kCoreBelowPlane_mm = 0.6;
inline constexpr double kQualityRatio = 2.0;
inline constexpr double kMinDihedral_deg = 15.0;
}  // namespace mesh_defaults  // Sphere: radius = magnet.radius_mm (validation case)

// Refinement zone: the box [-half_width, half_width]^2 x [z_min, z_max] (mm) of air
// meshed with the zone's edge length.
// Optional core (core_radius_mm > 0, cylinder magnets only): a coaxial air
// cylinder of that radius from core_z_min_mm up to core_z_max_mm inside the
// box, meshed with mesh.h_core_mm, where the probes are. With core_z_min_mm <=
// z_min the core starts at the magnet's top face and the zone box reaches down
// to it too (z_min unused), so the air gap between magnet and sensing plane is
// refined instead of being graded by TetGen's quality bound alone.
// The z range and the core are set about the sensing plane by
// fem_settings_from_config (mesh.zone_half_height_mm, mesh.core_*); a ZoneSpec
// made without a configuration has no core.
struct ZoneSpec {
  bool enabled = true;
  double half_width_mm = mesh_defaults::kZoneHalfWidth_mm;
  double z_min_mm = 3.55;  // must lie above the magnet's top face
  double z_max_mm = 5.55;
  double core_radius_mm = 0;  // 0: no core; else > magnet polygon radius, < 0.8 half_width
  double core_z_max_mm = 0;   // core top: above the magnet's top face, below z_max
  double core_z_min_mm = 0;   // core bottom; <= z_min: core and zone reach down to the magnet's top face
  // Annulus (annulus_r1_mm > 0): the zone is instead the coaxial ring annulus_r0_mm..annulus_r1_mm,
  // z_min..z_max, where probes off the axis travel (a sensor beside a ring magnet, a circle of probes
  // larger than the box). It may lie beside the magnet (z below its top face) and touch its faces; no core.
  double annulus_r0_mm = 0;
  double annulus_r1_mm = 0;
  bool annulus() const { return enabled && annulus_r1_mm > 0; }
  bool core() const { return enabled && !annulus() && core_radius_mm > 0; }
  bool core_to_magnet() const { return core() && core_z_min_mm <= z_min_mm; }
};

// Optional coaxial cylinder below the magnet (e.g. a steel shaft).
struct ShaftSpec {
  bool enabled = false;
  double radius_mm = 3.0;  // > 0
  double length_mm = 10.0; // > 0
  double gap_mm = 1.0;     // > 0: distance from the magnet's bottom face to the shaft's top
  double mu_r = 1000.0;    // relative permeability (>= 1)
};

// A permeable part around the magnet ([[parts]] in the configuration): a body
// of revolution about the axis through (offset_x_mm, offset_y_mm), magnet frame
// (the configuration's offset_mm = [x, y]).
//   cylinder: r <= r_outer, z_min..z_max (r_inner must be 0)
//   tube:     r_inner..r_outer (r_inner > 0), z_min..z_max
//   cup:      a tube plus a base r <= r_outer, z_min..z_min + base_mm (open at z_max)
//   disk:     like tube (r_inner > 0) or cylinder (r_inner = 0); named for thin plates
// Material: a linear relative permeability mu_r (>= 1).
enum class PartShape { Cylinder, Tube, Cup, Disk };
std::string to_string(PartShape s);

struct PartSpec {
  std::string name = "part";
  PartShape shape = PartShape::Cylinder;
  double r_inner_mm = 0;
  double r_outer_mm = 1;
  double z_min_mm = -1;
  double z_max_mm = 0;
  double base_mm = 0;  // cup only
  double offset_x_mm = 0, offset_y_mm = 0;  // the field offset_mm = [x, y]
  std::string material = "mu_r:1000";  // as configured (recorded in solve.json)
  double mu_r = 1000.0;                 // linear relative permeability (with bh: the initial one, a start value)
  std::shared_ptr<const BhCurve> bh;    // bh:FILE.csv: nonlinear B(H) (the solver iterates mu_r per cell)
  bool coaxial() const { return offset_x_mm == 0.0 && offset_y_mm == 0.0; }
  // The part as rectangles [r0, r1] x [z0, z1] of its meridian half-plane (cup: wall and base).
  struct Rect {
    double r0, r1, z0, z1;
  };
  std::vector<Rect> rects() const;
};

struct MeshSpec {
  int segments = mesh_defaults::kSegments;  // polygon segments around every curved (cylindrical) face
  bool equal_area = mesh_defaults::kEqualArea;  // polygon radius scaled so the cross-section area (sphere: volume) is exact
  double h_magnet_mm = mesh_defaults::kHMagnet_mm;  // target edge length in the magnet (and shaft)
  double h_zone_mm = mesh_defaults::kHZone_mm;      // target edge length in the refinement zone
  double h_core_mm = mesh_defaults::kHCore_mm;      // target edge length in the zone's core cylinder (if any)
  double h_air_mm = mesh_defaults::kHAir_mm;        // maximum edge length in the far air
  double outer_radius_mm = mesh_defaults::kOuterRadius_mm;        // truncation sphere radius
  int sphere_subdivisions = mesh_defaults::kSphereSubdivisions;  // icosphere level of the faceted outer sphere (and sphere magnets: +1)
  // Mesh the quadrant x >= 0, y >= 0 and mirror it (symmetric_mesh.hpp): the
  // mesh, and so the solution, has the domain's symmetry about x = 0 and y = 0.
  bool symmetric = mesh_defaults::kSymmetric;
  // Order N of the mesh's dihedral symmetry with `symmetric` (2: mirror x and
  // y only; 4..64, a power of two dividing `segments`: a wedge of pi/N is
  // meshed and reflected, see symmetric_mesh.hpp).
  int symmetry_order = mesh_defaults::kSymmetryOrder;
  MesherOptions mesher{mesh_defaults::kQualityRatio, mesh_defaults::kMinDihedral_deg};
};

struct DomainSpec {
  Magnet magnet;
  MagnetShape shape = MagnetShape::Cylinder;
  ZoneSpec zone;
  ShaftSpec shaft;
  std::vector<PartSpec> parts;  // [[parts]]: part i has region kRegionPartFirst + i
  MeshSpec mesh;

  // True when a part's axis is off the z axis: the domain has no mirror
  // symmetry, and a symmetric mesh would be wrong (the solver meshes the whole domain).
  bool has_off_axis_part() const;
  // True when a part has mu_r != 1 or a B-H curve (fem.potential = auto then takes the split potential).
  bool has_permeable_part() const;
  // True when a part has a B-H curve (a nonlinear solve).
  bool has_nonlinear_part() const;
  // region is a [[parts]] region whose part is permeable (mu_r != 1 or a B-H curve).
  bool permeable_part_region(int region) const;
  // True when a part with mu_r != 1 or a B-H curve touches the magnet (its faces on the magnet's faces):
  // the split potential does not hold there (see reduced_potential.hpp), fem.potential = auto takes the total.
  bool has_permeable_part_touching_magnet() const;

  // Throws InputError naming the offending key for degenerate or overlapping
  // geometry (non-positive sizes, zone touching the magnet, anything outside
  // the truncation sphere).
  void validate() const;
  // The [[parts]] checks of validate(): sizes, overlaps (touching allowed for
  // coaxial bodies), the domain, the refinement zone. InputError naming the part.
  void validate_parts() const;
  // The FEM's limits of a sector pattern (sector_magnetization.hpp): a cylinder magnet; multipoles without
  // pole edge errors and with mesh.segments a multiple of 4 pole_pairs. InputError naming the keys.
  void validate_pattern_mesh() const;
  // The checks of an annulus zone (ZoneSpec::annulus): not empty, clear of the magnet's material.
  void validate_zone_annulus() const;
  // Relative permeability of a region id.
  double mu_r(int region) const;
};

// Max volume (mm^3) of a regular tet with edge h (mm): h^3/(6 sqrt 2).
double tet_volume_for_edge(double h_mm);

// Radius (mm) of the N-gon vertices: R itself, or with equal_area the radius
// whose N-gon has area pi R^2: R*sqrt(t/sin t), t = 2 pi/N.
double polygon_radius(double R_mm, int segments, bool equal_area);

// The PLC of the whole domain (closed facets + region seeds).
Plc build_plc(const DomainSpec& spec);

// Mesh the domain: build_plc + tetrahedralize_plc; with mesh.symmetric the
// PLC cut to one quadrant, meshed and mirrored into the other three. Nodes and
// tets are numbered for locality (reorder_for_locality).
TetMesh mesh_domain(const DomainSpec& spec);

// The quadrant x >= 0, y >= 0 of the domain, meshed (snap_quadrant_mesh:
// boundary_faces = the outer boundary only; numbered by reorder_for_locality).
// mesh_domain with mesh.symmetric is its mirror image.
TetMesh mesh_quadrant(const DomainSpec& spec);

}  // namespace magenc::fem
