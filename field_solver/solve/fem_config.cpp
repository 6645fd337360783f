#include "field_solver/solve/fem_config.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <variant>

#include "core/errors.hpp"
#include "probe/common_keys.hpp"

namespace magenc::fem {

namespace {

// The [mesh] keys (fem_keys() begins with them).
std::vector<KeySpec> mesh_keys() {
  return {
      int_key("mesh.segments", mesh_defaults::kSegments, 8, 4096, "polygon segments around the magnet's (and shaft's) curved face"),
      bool_key("mesh.equal_area", mesh_defaults::kEqualArea, "scale the polygon radius so its area equals pi R^2 (dipole moment exact)"),
      real_key("mesh.h_magnet_mm", mesh_defaults::kHMagnet_mm, 0.01, 100, "mm", "target tet edge length in the magnet and shaft", true),
      real_key("mesh.h_zone_mm", mesh_defaults::kHZone_mm, 0.01, 100, "mm", "target tet edge length in the refinement zone", true),
      real_key("mesh.h_air_mm", mesh_defaults::kHAir_mm, 0.01, 1000, "mm", "maximum tet edge length in the far air", true),
      real_key("mesh.outer_radius_mm", mesh_defaults::kOuterRadius_mm, 0, 1e5, "mm", "radius of the truncation sphere (>= ~10x magnet size)", true),
      int_key("mesh.sphere_subdivisions", mesh_defaults::kSphereSubdivisions, 1, 6, "icosphere level of the faceted truncation sphere"),
      bool_key("mesh.symmetric", mesh_defaults::kSymmetric,
               "mesh one quadrant (x, y >= 0) and mirror it, so the mesh has the magnet's symmetry about x = 0 and "
               "y = 0 (false: one TetGen mesh of the whole domain)"),
      int_key("mesh.symmetry_order", mesh_defaults::kSymmetryOrder, 2, 64,
              "with mesh.symmetric: order N of the mesh's dihedral symmetry (2: mirror planes x = 0, y = 0 only; "
              "4..64, a power of two dividing mesh.segments: a wedge of 180/N deg is meshed and reflected, which "
              "moves the mesh's ideal-mount artefacts to harmonics >= N; the zone box becomes an N-gon prism)"),
      real_key("mesh.zone_half_width_mm", mesh_defaults::kZoneHalfWidth_mm, 0, 1000, "mm",
               "refinement zone half width in x and y (with mesh.symmetry_order N > 4 the inradius of the zone's "
               "N-gon prism; 7 mm: the prism covers the plane grid's corners)", true),
      real_key("mesh.zone_half_height_mm", mesh_defaults::kZoneHalfHeight_mm, 0, 1000, "mm", "refinement zone half height about the sensing plane", true),
      real_key("mesh.core_radius_mm", mesh_defaults::kCoreRadius_mm, 0, 1000, "mm",
               "radius of the core cylinder about the sensing plane inside the zone, meshed with mesh.h_core_mm "
               "(0 = none; > magnet radius, < 0.8x zone half width)"),
      real_key("mesh.h_core_mm", mesh_defaults::kHCore_mm, 0.01, 100, "mm", "target tet edge length in the zone's core cylinder", true),
      real_key("mesh.core_top_above_plane_mm", mesh_defaults::kCoreTopAbovePlane_mm, 0, 1000, "mm",
               "core cylinder top above the sensing plane (< mesh.zone_half_height_mm)"),
      real_key("mesh.core_below_plane_mm", mesh_defaults::kCoreBelowPlane_mm, 0, 1000, "mm",
               "core cylinder bottom below the sensing plane; reaching the zone box's bottom (z_s - "
               "mesh.zone_half_height_mm, clamped above the magnet) takes core and zone down to the magnet's top face"),
      real_key("mesh.quality_ratio", mesh_defaults::kQualityRatio, 1.05, 10, "", "TetGen radius-edge quality bound (-q)"),
      real_key("mesh.min_dihedral_deg", mesh_defaults::kMinDihedral_deg, 0, 30, "deg", "TetGen minimum dihedral angle (-q)"),
      real_key("mesh.max_mesher_seconds", 900, 0, 1e6, "s",
               "time budget of each TetGen run (in a child process, stopped and refused past it; with the point "
               "budget of 4 per 5 estimated tetrahedra it bounds a mesh that would not end; 0: no budget, TetGen in "
               "this process)"),
  };
}

}  // namespace

std::vector<KeySpec> fem_keys() {
  std::vector<KeySpec> keys = mesh_keys();
  const std::vector<KeySpec> rest = {
      int_key("fem.order", 2, 1, 2, "Lagrange order of the elements (1 or 2)"),
      string_key("fem.boundary", "robin", {"robin", "dirichlet"}, "far boundary: dipole Robin or psi = 0"),
      string_key("fem.solver", to_string(LinearSolverKind::Auto), linear_solver_names(),
                 "linear solver: CG with PETSc GAMG or hypre BoomerAMG algebraic multigrid (MPI-parallel under "
                 "mpirun), or Eigen's CG with fem.preconditioner (no PETSc needed); auto: petsc-hypre when built with "
                 "PETSc, else eigen-pcg"),
      string_key("fem.potential", to_string(SolverOptions{}.potential), potential_names(),
                 "total: psi of the whole field; reduced: the magnet's exact free-space field (analytic) plus an FE "
                 "reaction potential of the permeable parts (zero for mu_r = 1; not for a mu_r ~ 1000 shaft); split: "
                 "total potential in the shaft, reduced elsewhere; auto: split with a shaft, else reduced"),
      string_key("fem.preconditioner", to_string(SolverOptions{}.preconditioner), preconditioner_names(), "CG preconditioner of fem.solver = eigen-pcg"),
      real_key("fem.tolerance", 1e-8, 0, 1, "",
               "CG relative residual tolerance |f - K x| / |f| (1e-8: the default solve's B on the grids within "
               "1.3e-10 of peak of a 1e-10 solve; the D16 mesh's ideal-mount harmonics c1..c8 are zero only to the "
               "tolerance (total potential, meshes/coarse.toml: c4 7.5e-8 deg at 1e-8, 4.9e-10 deg at 1e-10), so "
               "checks of that symmetry set 1e-10)", true),
      int_key("fem.max_iterations", 20000, 1, 100000000, "CG iteration cap (failure when reached)"),
      real_key("fem.bh_iron_max_mu_r", kBhIronMaxMuR, 1, 1e6, "",
               "B-H curves whose polarization B - mu0 H reaches 1.7 T (iron, steels, Fe-Si, Fe-Co): the largest "
               "secant relative permeability allowed; above it the curve is refused as H in Oe, A/cm, kA/m or mT "
               "of mu0 H under the H_A_per_m header (isotropic steels and irons stay below 5e4; raise it for "
               "grain-oriented Fe-Si or hydrogen-annealed iron)"),
      int_key("fem.threads", 0, 0, 1024, "OpenMP threads (0 = all)"),
      bool_key("fem.quadrant_solve", true,
               "with mesh.symmetric: solve on the quadrant x, y >= 0 with symmetry conditions and mirror the "
               "solution (same result, 1/4 of the unknowns); false: solve the whole mirrored mesh"),
      bool_key("fem.recovery", true, "B from the node-averaged (recovered) gradient of psi inside each material"),
      real_key("fem.nonlinear_tolerance", 1e-6, 0, 1, "",
               "parts with a B-H curve: stop when the nonlinear residual |f - K(mu(psi)) psi| / |f| is below this", true),
      int_key("fem.nonlinear_max_iterations", 300, 1, 10000,
              "parts with a B-H curve: most nonlinear iterations (computation error, exit 3, when reached)"),
      string_key("fem.nonlinear_method", "newton", {"newton", "picard"},
                 "parts with a B-H curve: newton (one fixed-point step from the initial permeability, then Newton "
                 "steps with the exact Jacobian and backtracking) or picard (fixed-point iterations on the secant "
                 "permeability only; slower, ~0.9 residual reduction per iteration on a saturating cup)"),
      int_key("fem.progress_every", 500, 0, 100000000, "progress line on stderr every N CG iterations (0 = never)"),
      bool_key("output.mesh_vtu", false,
               "also write mesh.vtu (the whole FE solution: needed by --field fem:DIR, fem_field sources 'fem', "
               "harmonic_provenance's fem_dirs and ParaView's magnet_field.pvsm; ~0.5 GB for the default mesh)"),
      bool_key("output.compress", false, "zlib-compress the VTK files (smaller, several times slower to write)"),
      real_key("grid.plane_min_mm", -5.0, -1000, 1000, "mm", "plane grid: x and y from (offset from sensor.center_mm; r0 + 1 mm where it misses the probe circle)"),
      real_key("grid.plane_max_mm", 5.0, -1000, 1000, "mm", "plane grid: x and y to (offset from sensor.center_mm)"),
      real_key("grid.plane_step_mm", 0.05, 0, 100, "mm", "plane grid spacing", true),
      real_key("grid.box_xy_min_mm", -4.0, -1000, 1000, "mm", "box grid: x and y from (offset from sensor.center_mm; r0 + 1 mm where it misses the probe circle)"),
      real_key("grid.box_xy_max_mm", 4.0, -1000, 1000, "mm", "box grid: x and y to (offset from sensor.center_mm)"),
      real_key("grid.box_z_below_mm", 0.5, 0, 1000, "mm", "box grid: from z_s minus this"),
      real_key("grid.box_z_above_mm", 0.5, 0, 1000, "mm", "box grid: to z_s plus this"),
      real_key("grid.box_step_mm", 0.05, 0, 100, "mm", "box grid spacing (x, y and z)", true),
      bool_key("shaft.enabled", false, "add a coaxial soft-magnetic cylinder under the magnet"),
      real_key("shaft.radius_mm", 3.0, 0, 1000, "mm", "shaft radius", true),
      real_key("shaft.length_mm", 10.0, 0, 1000, "mm", "shaft length", true),
      real_key("shaft.gap_mm", 1.0, 0, 1000, "mm", "gap between the magnet's bottom face and the shaft", true),
      real_key("shaft.mu_r", 1000.0, 1, 1e6, "", "relative permeability of the shaft"),
      table_list_key(
          "parts",
          {required(string_key("name", "part", {}, "the part's name (in errors and solve.json)")),
           required(string_key("shape", "cylinder", {"cylinder", "tube", "cup", "disk"},
                               "cylinder | tube | cup (tube + base at z_min) | disk (with a hole if r_inner_mm > 0)")),
           real_key("r_inner_mm", 0, 0, 1000, "mm", "inner radius (0: solid cylinder or disk; cup: the bore)"),
           required(real_key("r_outer_mm", 1, 0, 1000, "mm", "outer radius", true)),
           required(real_key("z_min_mm", 0, -1000, 1000, "mm", "bottom (magnet frame: magnet centre at z = 0)")),
           required(real_key("z_max_mm", 0, -1000, 1000, "mm", "top")),
           real_key("base_mm", 0, 0, 1000, "mm", "cup only: base thickness at z_min"),
           real_array_field("offset_mm", 2, -1000, 1000, "mm",
                            "[x, y] of the part's axis, default [0, 0] (non-zero: no mesh symmetry)"),
           required(string_key("material", "mu_r:1000", {},
                               "mu_r:VALUE (linear, 1..1e6), bh:FILE.csv (B-H curve, columns H_A_per_m,B_T; nonlinear solve) or a named material: " + part_material_names()))},
          "",
          "permeable parts around the magnet (holders, shafts, shields), any number; coaxial or off the axis; "
          "may touch the magnet or each other, never overlap"),
  };
  keys.insert(keys.end(), rest.begin(), rest.end());
  return keys;
}

namespace {

struct NamedMaterial {
  const char* name;
  double mu_r;          // linear materials: the relative permeability
  const char* bh_file;  // B-H materials: materials/NAME_bh.csv (its header names the source), else nullptr
  const char* source;
};

// The library of named holder materials (materials/README.md). The steels with a
// published curve solve nonlinearly on it; structural_steel stays linear (the
// steel_parts study compares it with the B-H file); the near non-magnetic ones are
// linear.
const std::vector<NamedMaterial>& named_materials() {
  static const std::vector<NamedMaterial> m{
      {"structural_steel", 1000.0, nullptr,
       "S235/1.0038-class low-carbon steel, linear: the order of the secant permeability of the hot-rolled "
       "low-carbon steel curve materials/low_carbon_steel_hot_rolled_bh.csv (ASM Metals Handbook 8th ed. "
       "Vol. 1 Fig. 17: 810 at 54 A/m, ~2900 at 270 A/m, ~1130 at 1 kA/m)"},
      {"low_carbon_steel", 0.0, "materials/low_carbon_steel_hot_rolled_bh.csv",
       "hot-rolled low-carbon steel (S235, AISI 1010-1020 class), measured DC curve "
       "materials/low_carbon_steel_hot_rolled_bh.csv (ASM Metals Handbook 8th ed. Vol. 1 Fig. 17, digitized "
       "for FEMM 4.2); the nonlinear counterpart of structural_steel"},
      {"free_cutting_steel", 0.0, "materials/free_cutting_steel_bh.csv",
       "free-cutting steel AISI 1117 (11SMn30/1.0715 class), B-H curve materials/free_cutting_steel_bh.csv "
       "(FEMM 4.2 library block '1117 Steel', DC curve)"},
      {"electrical_steel", 0.0, "materials/electrical_steel_bh.csv",
       "non-oriented electrical steel M400-50A, B-H curve materials/electrical_steel_bh.csv (typical 50 Hz "
       "datasheet table via the Modelica Standard Library RawData.M400_50A)"},
      {"stainless_1.4305", 1.02, nullptr,
       "austenitic stainless 1.4305 (303), annealed: mu_r 1.003-1.05 for fully annealed austenitic grades "
       "(British Stainless Steel Association), 1.003-1.005 at 16 kA/m well annealed (Carpenter Technology); "
       "cold work raises it; materials/README.md"},
      {"brass", 1.0, nullptr,
       "brass CuZn39Pb3 (CW614N, C36000 class): 'non-magnetic' in datasheets, no number found; mu_r 1, "
       "materials/README.md"},
  };
  return m;
}

const NamedMaterial* find_named_material(const std::string& name) {
  for (const auto& m : named_materials())
    if (name == m.name) return &m;
  return nullptr;
}

}  // namespace

std::string part_material_names() {
  std::string out;
  for (const auto& m : named_materials()) out += (out.empty() ? "" : ", ") + std::string(m.name);
  return out;
}

std::string part_material_source(const std::string& name) {
  const NamedMaterial* m = find_named_material(name);
  return m ? m->source : "";
}

std::filesystem::path part_material_bh_file(const std::string& material) {
  if (material.rfind("bh:", 0) == 0) return material.substr(3);
  const NamedMaterial* m = find_named_material(material);
  if (!m || !m->bh_file) return {};
  const std::filesystem::path f(m->bh_file);
  if (std::filesystem::exists(f)) return f;  // the working directory first, then the source tree
  return std::filesystem::path(MAGENC_SOURCE_DIR) / f;
}

double part_material_mu_r(const std::string& material, const std::string& what, double iron_max_mu_r) {
  auto bad = [&]() -> double {
    throw InputError(what + ": material = '" + material + "' is out of range: allowed mu_r:VALUE (VALUE in [1, 1e6]) or one of " +
                     part_material_names());
  };
  if (const std::filesystem::path f = part_material_bh_file(material); !f.empty()) {
    const BhCurve c = read_bh_csv(f, iron_max_mu_r);
    return c.mu_r(0.0);
  }
  if (material.rfind("mu_r:", 0) == 0) {
    const std::string v = material.substr(5);
    try {
      std::size_t used = 0;
      const double mu = std::stod(v, &used);
      if (used != v.size() || !std::isfinite(mu) || mu < 1 || mu > 1e6) return bad();
      return mu;
    } catch (const std::exception&) {
      return bad();
    }
  }
  const NamedMaterial* m = find_named_material(material);
  return m ? m->mu_r : bad();
}

std::vector<PartSpec> parts_from_config(const Config& cfg) {
  std::vector<PartSpec> out;
  const ConfigTables tables = cfg.tables("parts");
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const ConfigTable& t = tables[i];
    PartSpec p;
    p.name = t.text("name");
    const std::string what = "parts element " + std::to_string(i + 1) + " of " + std::to_string(tables.size()) + " ('" +
                             p.name + "')";
    const std::string shape = t.text("shape");
    p.shape = shape == "tube" ? PartShape::Tube : shape == "cup" ? PartShape::Cup : shape == "disk" ? PartShape::Disk
                                                                                                   : PartShape::Cylinder;
    auto real = [&](const char* field, double def) {
      for (const auto& e : t.entries)
        if (e.field == field && e.key.empty()) {
          if (auto d = std::get_if<double>(&e.value)) return *d;
          if (auto l = std::get_if<long>(&e.value)) return static_cast<double>(*l);
        }
      return def;
    };
    p.r_inner_mm = real("r_inner_mm", 0);
    p.r_outer_mm = real("r_outer_mm", 0);
    p.z_min_mm = real("z_min_mm", 0);
    p.z_max_mm = real("z_max_mm", 0);
    p.base_mm = real("base_mm", 0);
    if (const std::vector<double> offset = t.numbers("offset_mm"); offset.size() == 2) {  // checked when set
      p.offset_x_mm = offset[0];
      p.offset_y_mm = offset[1];
    }
    p.material = t.text("material");
    if (const std::filesystem::path f = part_material_bh_file(p.material); !f.empty()) {
      try {
        p.bh = std::make_shared<const BhCurve>(read_bh_csv(f, cfg.real("fem.bh_iron_max_mu_r")));
      } catch (const InputError& e) {
        throw InputError(what + ": " + e.what());
      }
      p.mu_r = std::min(1e6, std::max(1.0, p.bh->mu_r(0.0)));
    } else {
      p.mu_r = part_material_mu_r(p.material, what, cfg.real("fem.bh_iron_max_mu_r"));
    }
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<KeySpec> solve_field_schema() { return merge_schemas(common_keys(), fem_keys()); }

namespace {

double physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? double(pages) * double(page) : 16e9;
}

// Absurd sizes are refused before meshing, with an estimate, instead of after minutes of TetGen or an
// out-of-memory kill. Tetrahedra: each refinement region's volume / (h^3 / (6 sqrt 2)) (regular tets),
// times 3.6, the ratio TetGen's quality meshes show on the default mesh (1,831,072 tets against an
// estimate of 508k). Memory per tet: measured peak RSS / tets (docs/benchmarks.md): 1.0 KiB (P2, quadrant
// solve of a symmetric mesh), 3.3 KiB (P2, whole mesh); P1 one third. Refused when the estimate
// exceeds the machine's physical memory. Grid nodes: checked as doubles, before any integer cast.
// Returns the estimate of tetrahedra.
double check_memory_estimate(const Config& cfg, const FemSettings& s) {
  const double pi = 3.14159265358979323846, per_h3 = 6 * std::sqrt(2.0) * 3.6;
  const auto& d = s.domain;
  const auto& m = d.mesh;
  struct Part {
    const char* key;
    double tets;
  };
  const double zone_h = std::max(0.0, d.zone.z_max_mm - d.zone.z_min_mm);
  const Part parts[] = {
      {"mesh.h_magnet_mm", pi * d.magnet.radius_mm * d.magnet.radius_mm * d.magnet.height_mm * per_h3 /
                               std::pow(m.h_magnet_mm, 3)},
      {"mesh.h_zone_mm", 4 * d.zone.half_width_mm * d.zone.half_width_mm * zone_h * per_h3 / std::pow(m.h_zone_mm, 3)},
      {"mesh.h_core_mm", pi * d.zone.core_radius_mm * d.zone.core_radius_mm *
                             std::max(0.0, d.zone.core_z_max_mm - d.zone.core_z_min_mm) * per_h3 /
                             std::pow(m.h_core_mm, 3)},
      {"mesh.h_air_mm", 4.0 / 3.0 * pi * std::pow(m.outer_radius_mm, 3) * per_h3 / std::pow(m.h_air_mm, 3)},
  };
  double tets = 0;
  const Part* worst = &parts[0];
  for (const auto& p : parts) {
    tets += p.tets;
    if (p.tets > worst->tets) worst = &p;
  }
  const bool quadrant = m.symmetric && cfg.flag("fem.quadrant_solve");
  const double per_tet = (quadrant ? 1.0 : 3.3) * 1024 * (cfg.integer("fem.order") == 2 ? 1.0 : 1.0 / 3);
  const double need = tets * per_tet, have = physical_memory_bytes();
  if (need > have)
    throw InputError("mesh would have about " + num(tets) + " tetrahedra, needing about " + num(need / 1073741824.0) +
                     " GiB (this machine has " + num(have / 1073741824.0) + " GiB): " + worst->key + " = " +
                     num(cfg.real(worst->key)) + " mm is too small for this domain");
  // Grids: nodes = prod(floor(extent / step) + 1), B (3 doubles) held by the solver, VTK and the writer.
  const auto nodes = [](double lo, double hi, double step) { return std::floor((hi - lo) / step + 1e-9) + 1; };
  const double np = std::pow(nodes(cfg.real("grid.plane_min_mm"), cfg.real("grid.plane_max_mm"),
                                   cfg.real("grid.plane_step_mm")), 2);
  const double bs = cfg.real("grid.box_step_mm");
  const double nb = std::pow(nodes(cfg.real("grid.box_xy_min_mm"), cfg.real("grid.box_xy_max_mm"), bs), 2) *
                    nodes(-cfg.real("grid.box_z_below_mm"), cfg.real("grid.box_z_above_mm"), bs);
  for (const auto& [key, n] : {std::pair<const char*, double>{"grid.plane_step_mm", np}, {"grid.box_step_mm", nb}})
    if (n > 2e8)
      throw InputError(std::string(key) + " = " + num(cfg.real(key)) + " mm gives " + num(n) + " grid nodes (about " +
                       num(n * 72 / 1073741824.0) + " GiB): allowed at most 2e8 nodes, increase the step");
  return tets;
}

// The refinement zone where the probes travel. On the axis above the magnet (the probes' circles
// within the box, less the margin a = mesh.zone_half_height_mm) the box stays as it was; else (a plane
// at or below the top face, a die centre off the axis, a large r0) the zone is the annulus of the
// probes' radii +- a, z_s +- a, cut back to touch the magnet's faces where it would reach into them.
void set_zone_annulus(DomainSpec& d, const SensorWindow& w, double z_s, double a, double plane_height_mm) {
  const double rho = std::hypot(w.centre_mm[0], w.centre_mm[1]);
  const double r0 = w.r0_mm;
  if (plane_height_mm > 0 && rho + r0 + a <= d.zone.half_width_mm) return;
  const double top = 0.5 * d.magnet.height_mm, R = d.magnet.radius_mm, Ri = d.magnet.inner_radius_mm;
  ZoneSpec& z = d.zone;
  z.annulus_r0_mm = std::max(0.0, std::abs(rho - r0) - a);  // a probe at r0 from the centre: |rho - r0| .. rho + r0
  z.annulus_r1_mm = rho + r0 + a;
  z.z_min_mm = z_s - a;
  z.z_max_mm = z_s + a;
  if (z.annulus_r1_mm > Ri && z.annulus_r0_mm < R) {  // over the magnet's material in r
    if (z_s > top) z.z_min_mm = std::max(z.z_min_mm, top);
    else if (z_s < -top) z.z_max_mm = std::min(z.z_max_mm, -top);
    else if (std::abs(rho - r0) >= R) z.annulus_r0_mm = std::max(z.annulus_r0_mm, R);  // every probe beside it
    else if (rho + r0 <= Ri) z.annulus_r1_mm = std::min(z.annulus_r1_mm, Ri);
  }
}

}  // namespace

SensorWindow sensor_window(const Config& cfg) {
  SensorWindow w;
  if (cfg.has("sensor.center_mm")) {
    const std::vector<double> c = cfg.reals("sensor.center_mm");
    if (c.size() == 2) w.centre_mm = {c[0], c[1]};
  }
  const bool point = cfg.has("sensor.array") && cfg.str("sensor.array") == "point";
  if (cfg.has("sensor.r0_mm") && !point) w.r0_mm = cfg.real("sensor.r0_mm");
  return w;
}

namespace {
// The plane and box grids (FemSettings::plane, box): the windows are taken about the die centre and
// widened to hold the probe circle (sensor_window); both must lie well inside the truncation sphere.
void set_grids(const Config& cfg, FemSettings& s) {
  const MeshSpec& m = s.domain.mesh;
  const double pmin = cfg.real("grid.plane_min_mm"), pmax = cfg.real("grid.plane_max_mm");
  if (!(pmax > pmin))
    throw InputError("grid.plane_max_mm = " + num(pmax) + " must be > grid.plane_min_mm = " + num(pmin));
  const double bmin = cfg.real("grid.box_xy_min_mm"), bmax = cfg.real("grid.box_xy_max_mm");
  if (!(bmax > bmin))
    throw InputError("grid.box_xy_max_mm = " + num(bmax) + " must be > grid.box_xy_min_mm = " + num(bmin));
  const SensorWindow w = sensor_window(cfg);
  const auto lo = [&](double v, int axis) { return w.lo(v, axis); };
  const auto hi = [&](double v, int axis) { return w.hi(v, axis); };
  const double ps = cfg.real("grid.plane_step_mm");
  s.plane = GridData::from_range({lo(pmin, 0), lo(pmin, 1), s.plane_z_mm}, {hi(pmax, 0), hi(pmax, 1), s.plane_z_mm},
                                 {ps, ps, 1.0});
  const double bs = cfg.real("grid.box_step_mm");
  const double z0 = s.plane_z_mm - cfg.real("grid.box_z_below_mm"), z1 = s.plane_z_mm + cfg.real("grid.box_z_above_mm");
  s.box = GridData::from_range({lo(bmin, 0), lo(bmin, 1), z0}, {hi(bmax, 0), hi(bmax, 1), z1}, {bs, bs, bs});
  // Both grids must lie well inside the truncation sphere (inscribed polyhedron).
  auto check_inside = [&](const GridData& g, const char* what) {
    const Eigen::Vector3d g_lo = g.origin_mm,
                          g_hi = g.origin_mm + g.spacing_mm.cwiseProduct(Eigen::Vector3d(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1));
    const double far = g_lo.cwiseAbs().cwiseMax(g_hi.cwiseAbs()).norm();
    if (far >= 0.9 * m.outer_radius_mm)
      throw InputError(std::string(what) + " reaches " + num(far) +
                       " mm from the origin, outside the domain: mesh.outer_radius_mm = " + num(m.outer_radius_mm) +
                       " must be > " + num(far / 0.9) + " mm");
    if (g.nodes() > 200'000'000UL) throw InputError(std::string(what) + " has too many points (> 2e8): increase its step");
  };
  check_inside(s.plane, "grid plane");
  check_inside(s.box, "grid box");
}

}  // namespace

FemSettings fem_settings_from_config(const Config& cfg) {
  FemSettings s;
  DomainSpec& d = s.domain;
  d.magnet = Magnet::from_config(cfg);
  s.plane_z_mm = sensing_plane_z_mm(cfg);
  const double top = 0.5 * d.magnet.height_mm, h = cfg.real("sensor.plane_height_mm");
  MeshSpec& m = d.mesh;
  m.segments = static_cast<int>(cfg.integer("mesh.segments"));
  m.equal_area = cfg.flag("mesh.equal_area");
  m.h_magnet_mm = cfg.real("mesh.h_magnet_mm");
  m.h_zone_mm = cfg.real("mesh.h_zone_mm");
  m.h_core_mm = cfg.real("mesh.h_core_mm");
  m.h_air_mm = cfg.real("mesh.h_air_mm");
  m.outer_radius_mm = cfg.real("mesh.outer_radius_mm");
  m.sphere_subdivisions = static_cast<int>(cfg.integer("mesh.sphere_subdivisions"));
  m.symmetric = cfg.flag("mesh.symmetric");
  m.symmetry_order = static_cast<int>(cfg.integer("mesh.symmetry_order"));
  m.mesher.radius_edge_ratio = cfg.real("mesh.quality_ratio");
  m.mesher.min_dihedral_deg = cfg.real("mesh.min_dihedral_deg");
  m.mesher.max_seconds = cfg.real("mesh.max_mesher_seconds");
  // Refinement zone: z_s +- half height, but never closer to the magnet than h/2.
  d.zone.half_width_mm = cfg.real("mesh.zone_half_width_mm");
  d.zone.z_min_mm = std::max(s.plane_z_mm - cfg.real("mesh.zone_half_height_mm"), top + 0.5 * h);
  d.zone.z_max_mm = s.plane_z_mm + cfg.real("mesh.zone_half_height_mm");
  d.zone.core_radius_mm = cfg.real("mesh.core_radius_mm");
  d.zone.core_z_max_mm = s.plane_z_mm + cfg.real("mesh.core_top_above_plane_mm");
  d.zone.core_z_min_mm = s.plane_z_mm - cfg.real("mesh.core_below_plane_mm");
  set_zone_annulus(d, sensor_window(cfg), s.plane_z_mm, cfg.real("mesh.zone_half_height_mm"), h);
  d.shaft.enabled = cfg.flag("shaft.enabled");
  d.shaft.radius_mm = cfg.real("shaft.radius_mm");
  d.shaft.length_mm = cfg.real("shaft.length_mm");
  d.shaft.gap_mm = cfg.real("shaft.gap_mm");
  d.shaft.mu_r = cfg.real("shaft.mu_r");
  d.parts = parts_from_config(cfg);
  d.validate();

  SolverOptions& o = s.solver;
  o.order = static_cast<int>(cfg.integer("fem.order"));
  o.robin = cfg.str("fem.boundary") == "robin";
  o.solver = linear_solver_from_string(cfg.str("fem.solver"));
  o.potential = potential_from_string(cfg.str("fem.potential"));
  if (o.potential == Potential::Reduced && d.shaft.enabled)
    throw InputError("fem.potential = reduced with shaft.enabled = true is not supported: in the shaft (mu_r = " +
                     num(d.shaft.mu_r) +
                     ") H ~ 0 while the source field is not, and the reaction potential cancels it; use "
                     "fem.potential = split (or auto) or total");
  if (o.potential == Potential::Reduced && d.has_permeable_part())
    throw InputError("fem.potential = reduced with a permeable part (parts material mu_r != 1) is not supported: "
                     "the reaction potential would cancel the source field inside it; use fem.potential = split (or auto) or total");
  s.write_mesh_vtu = cfg.flag("output.mesh_vtu");
  s.compress = cfg.flag("output.compress");
  o.preconditioner = preconditioner_from_string(cfg.str("fem.preconditioner"));
  o.tolerance = cfg.real("fem.tolerance");
  o.max_iterations = static_cast<int>(cfg.integer("fem.max_iterations"));
  o.threads = static_cast<int>(cfg.integer("fem.threads"));
  o.progress_every = static_cast<int>(cfg.integer("fem.progress_every"));
  o.recovery = cfg.flag("fem.recovery");
  o.nonlinear_tolerance = cfg.real("fem.nonlinear_tolerance");
  o.nonlinear_max_iterations = static_cast<int>(cfg.integer("fem.nonlinear_max_iterations"));
  o.newton = cfg.str("fem.nonlinear_method") == "newton";
  o.quadrant = cfg.flag("fem.quadrant_solve");

  // The mesher's budget: TetGen adds at most 4 points per tetrahedron of the estimate's node count (about
  // tets / 5) plus 2e5; a wall or gap too thin for the mesh sizes (which TetGen would refine without end)
  // stops there and is refused, instead of filling the memory.
  const double tets = check_memory_estimate(cfg, s);
  s.domain.mesh.mesher.max_added_points = static_cast<long>(std::min(4.0 * tets / 5.0 + 2e5, 1e9));

  set_grids(cfg, s);
  return s;
}

}  // namespace magenc::fem
