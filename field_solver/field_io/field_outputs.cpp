#include "field_solver/field_io/field_outputs.hpp"

#include <sys/resource.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "fields/grid.hpp"
#include "magenc_version.hpp"
#include "field_solver/mesh/mesh.hpp"
#include "field_solver/solve/linear_solver.hpp"
#include "field_solver/field_io/vtk_io.hpp"

namespace magenc::fem {

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss in KiB on Linux
}

namespace {
// solve.json's "magnet": the keys a reader checks against a study's (SolvedFieldDir::mismatch).
nlohmann::json magnet_record(const Magnet& m) {
  nlohmann::json j = {{"radius_mm", m.radius_mm}, {"height_mm", m.height_mm}, {"br_T", m.br_T}, {"mu_r", m.mu_r},
                      {"magnetization_deg", m.magnetization_deg}, {"magnetization_elevation_deg", m.magnetization_elevation_deg}};
  if (m.is_ring()) j["inner_radius_mm"] = m.inner_radius_mm;  // solid cylinders: no key, as before
  if (!m.is_uniform()) {  // the uniform magnet: no keys, as before
    j["pattern"] = pattern_name(m.pattern);
    if (m.is_multipole()) j["pole_pairs"] = m.pole_pairs;
    if (m.pole_amplitude_sigma != 0.0) {
      j["pole_amplitude_sigma"] = m.pole_amplitude_sigma;
      j["pole_seed"] = m.pole_seed;
    }
  }
  return j;
}
}  // namespace

void write_field_outputs(const std::filesystem::path& dir, const FemSettings& s, const MagnetostaticSolver& solver,
                         const std::string& config_json) {
  const auto t0 = std::chrono::steady_clock::now();
  // 1. Grids: B from the FE solution at every grid point.
  GridData plane = s.plane, box = s.box;
  const Eigen::Matrix3Xd B_plane = solver.evaluator().B_T(plane.points_mm());
  const Eigen::Matrix3Xd B_box = solver.evaluator().B_T(box.points_mm());
  if (!B_plane.allFinite() || !B_box.allFinite()) throw ComputeError("B on the grids contains NaN");
  plane.set_B(B_plane);
  box.set_B(B_box);
  plane.source = (dir / "plane.vti").string();
  box.source = (dir / "box.vti").string();
  // 2. VTK files: raw binary appended data, zlib blocks with output.compress; box.vti has B only.
  if (s.write_mesh_vtu) write_solution_vtu(dir / "mesh.vtu", solver.solution(), solver.B_cell(), s.compress);
  write_grid_vti(dir / "plane.vti", plane, {.compress = s.compress, .base64 = false, .with_bz = true});
  write_grid_vti(dir / "box.vti", box, {.compress = s.compress, .base64 = false, .with_bz = false});
  const double t_out = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // 3. solve.json.
  const SolveStats& st = solver.stats();
  const DomainSpec& d = s.domain;
  nlohmann::json j;
  j["elements"] = st.elements;
  j["nodes"] = st.nodes;
  j["dofs"] = st.dofs;
  j["solved_dofs"] = st.solved_dofs;
  j["solves"] = st.solves;
  j["nonzeros"] = st.nonzeros;
  j["order"] = st.order;
  j["iterations"] = st.iterations;
  j["residual"] = st.residual;
  const SolverOptions& o = solver.options();  // solver and potential resolved (no "auto")
  j["solver"] = to_string(o.solver);
  j["potential"] = to_string(o.potential);
  j["preconditioner"] = o.solver == LinearSolverKind::EigenPcg     ? to_string(o.preconditioner)
                        : o.solver == LinearSolverKind::PetscHypre ? std::string("boomeramg")
                                                                   : std::string("gamg");
  j["mpi_ranks"] = mpi_world_size();
  j["rank_peak_rss_mib"] = mpi_rank_peak_rss_mib();  // per MPI rank, after the last linear solve
  j["tolerance"] = solver.options().tolerance;
  j["t_mesh_s"] = st.t_mesh_s;
  j["t_setup_s"] = st.t_setup_s;
  j["t_assemble_s"] = st.t_assemble_s;
  j["t_solve_s"] = st.t_solve_s;
  j["t_post_s"] = st.t_post_s;
  j["t_output_s"] = t_out;
  j["mesh_vtu"] = s.write_mesh_vtu;
  j["compress"] = s.compress;
  j["t_total_s"] = st.t_total_s + t_out;
  j["threads"] = st.threads;
  j["peak_rss_mib"] = peak_rss_mib();
  j["git_revision"] = kGitRevision;
  j["magnet"] = magnet_record(d.magnet);
  j["domain"] = {{"outer_radius_mm", d.mesh.outer_radius_mm},
                 {"boundary", solver.options().robin ? "robin" : "dirichlet"},
                 {"segments", d.mesh.segments},
                 {"equal_area", d.mesh.equal_area},
                 {"symmetric", d.mesh.symmetric},
                 {"symmetry_order", d.mesh.symmetric ? d.mesh.symmetry_order : 1},
                 {"polygon_radius_mm", polygon_radius(d.magnet.radius_mm, d.mesh.segments, d.mesh.equal_area)},
                 {"h_magnet_mm", d.mesh.h_magnet_mm},
                 {"h_zone_mm", d.mesh.h_zone_mm},
                 {"h_air_mm", d.mesh.h_air_mm},
                 {"zone", {{"half_width_mm", d.zone.half_width_mm},
                           {"z_min_mm", d.zone.core_to_magnet() ? 0.5 * d.magnet.height_mm : d.zone.z_min_mm},
                           {"z_max_mm", d.zone.z_max_mm},
                           {"core_radius_mm", d.zone.core() ? d.zone.core_radius_mm : 0.0},
                           {"core_z_min_mm", d.zone.core() ? (d.zone.core_to_magnet() ? 0.5 * d.magnet.height_mm : d.zone.core_z_min_mm) : 0.0},
                           {"core_z_max_mm", d.zone.core() ? d.zone.core_z_max_mm : 0.0},
                           {"h_core_mm", d.zone.core() ? d.mesh.h_core_mm : 0.0}}},
                 {"shaft", {{"enabled", d.shaft.enabled}, {"radius_mm", d.shaft.radius_mm}, {"length_mm", d.shaft.length_mm},
                            {"gap_mm", d.shaft.gap_mm}, {"mu_r", d.shaft.mu_r}}}};
  j["mesh_layout"] = solver.mesh_layout();
  j["nonlinear_iterations"] = st.nonlinear_iterations;
  j["nonlinear_residuals"] = st.nonlinear_residuals;
  j["nonlinear_tolerance"] = solver.options().nonlinear_tolerance;
  j["nonlinear_method"] = solver.options().newton ? "newton" : "picard";
  j["newton_steps"] = st.newton_steps;
  j["parts"] = nlohmann::json::array();
  for (std::size_t i = 0; i < d.parts.size(); ++i) {
    const PartSpec& p = d.parts[i];
    j["parts"].push_back({{"name", p.name}, {"shape", to_string(p.shape)}, {"region", kRegionPartFirst + static_cast<int>(i)},
                          {"r_inner_mm", p.r_inner_mm}, {"r_outer_mm", p.r_outer_mm}, {"z_min_mm", p.z_min_mm},
                          {"z_max_mm", p.z_max_mm}, {"base_mm", p.base_mm}, {"offset_mm", {p.offset_x_mm, p.offset_y_mm}},
                          {"material", p.material}, {"mu_r", p.mu_r}, {"nonlinear", p.bh != nullptr},
                          {"material_source", p.material.rfind("bh:", 0) == 0 ? p.material.substr(3) : part_material_source(p.material)}});
  }
  j["plane_z_mm"] = s.plane_z_mm;
  j["plane_grid"] = {{"origin_mm", {s.plane.origin_mm[0], s.plane.origin_mm[1], s.plane.origin_mm[2]}},
                     {"step_mm", s.plane.spacing_mm[0]}, {"dims", {s.plane.dims[0], s.plane.dims[1]}}};
  j["box_grid"] = {{"origin_mm", {s.box.origin_mm[0], s.box.origin_mm[1], s.box.origin_mm[2]}},
                   {"step_mm", s.box.spacing_mm[0]}, {"dims", {s.box.dims[0], s.box.dims[1], s.box.dims[2]}}};
  j["config"] = nlohmann::json::parse(config_json);
  std::ofstream out(dir / "solve.json");
  out << j.dump(2) << "\n";
  if (!out) throw ComputeError("cannot write " + (dir / "solve.json").string());
}

void write_bodies_vtu(const std::filesystem::path& file, const MagnetostaticSolver& solver) {
  const FeSolution& sol = solver.solution();
  const Eigen::Matrix3Xd& B_cell = solver.B_cell();
  std::vector<int> cells;
  for (int c = 0; c < sol.num_cells(); ++c)
    if (sol.region[c] == kRegionMagnet || sol.region[c] >= kRegionPartFirst) cells.push_back(c);
  // Corner nodes of the kept cells, renumbered in first-use order.
  std::vector<int> node_of(static_cast<std::size_t>(sol.points_mm.cols()), -1);
  std::vector<int> nodes;
  FeSolution b;
  b.order = 1;
  b.cell_dofs.resize(4, static_cast<Eigen::Index>(cells.size()));
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (int k = 0; k < 4; ++k) {
      int& n = node_of[static_cast<std::size_t>(sol.cell_dofs(k, cells[i]))];
      if (n < 0) {
        n = static_cast<int>(nodes.size());
        nodes.push_back(sol.cell_dofs(k, cells[i]));
      }
      b.cell_dofs(k, static_cast<Eigen::Index>(i)) = n;
    }
  b.points_mm.resize(3, static_cast<Eigen::Index>(nodes.size()));
  b.psi_Tmm.resize(static_cast<Eigen::Index>(nodes.size()));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    b.points_mm.col(static_cast<Eigen::Index>(i)) = sol.points_mm.col(nodes[i]);
    b.psi_Tmm[static_cast<Eigen::Index>(i)] = sol.psi_Tmm[nodes[i]];
  }
  const auto n_cells = static_cast<Eigen::Index>(cells.size());
  b.region.resize(n_cells);
  b.mu_r.resize(n_cells);
  b.br_T.resize(3, n_cells);
  Eigen::Matrix3Xd B(3, n_cells);
  for (Eigen::Index i = 0; i < n_cells; ++i) {
    const int c = cells[static_cast<std::size_t>(i)];
    b.region[i] = sol.region[c];
    b.mu_r[i] = sol.mu_r[c];
    b.br_T.col(i) = sol.br_T.col(c);
    B.col(i) = B_cell.col(c);
  }
  write_solution_vtu(file, b, B);
}

void write_B_grid_vti(const std::filesystem::path& file, GridData grid, const MagnetostaticSolver& solver) {
  const Eigen::Matrix3Xd B = solver.evaluator().B_T(grid.points_mm());
  if (!B.allFinite()) throw ComputeError("B on the grid of " + file.string() + " contains NaN");
  grid.set_B(B);
  grid.source = file.string();
  write_grid_vti(file, grid, {.compress = false, .base64 = false, .with_bz = false});
}

}  // namespace magenc::fem
