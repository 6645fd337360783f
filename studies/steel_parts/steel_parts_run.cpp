#include "studies/steel_parts/steel_parts_run.hpp"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include "analysis/offset_sweeps.hpp"
#include "analysis/sweep.hpp"
#include "field_solver/mesh/bh_curve.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "field_solver/field_io/fem_field.hpp"
#include "field_solver/field_io/field_outputs.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"

namespace magenc::fem {

std::vector<KeySpec> steel_parts_keys() {
  auto keys = fem_keys();
  for (auto k : std::vector<KeySpec>{
           study_arrays_key(),
           real_key("steel_parts.offset_mm", 0.1, 0, 10, "mm", "each mounting offset sx, sy, dx, dy alone at this value"),
           string_key("steel_parts.linear_material", "structural_steel", {},
                      "the steel parts' linear material: mu_r:VALUE or a named material (docs/interfaces.md)"),
           string_key("steel_parts.bh_file", "materials/structural_steel_bh.csv", {},
                      "the steel parts' B-H curve (CSV H_A_per_m,B_T) for the nonlinear solves; a relative path is "
                      "looked up in the working directory, then in the source tree"),
           bool_key("steel_parts.nonlinear", true, "also solve each steel part with the B-H curve (Newton)"),
           real_key("steel_parts.cup_wall_mm", 0.5, 0, 100, "mm", "cup: wall and base thickness", true),
           real_key("steel_parts.cup_top_mm", 0.5, 0, 100, "mm", "cup: its rim this far below the magnet's top face"),
           real_key("steel_parts.shaft_radius_mm", 3.0, 0, 100, "mm", "shaft radius (the shaft touches the magnet's bottom face)", true),
           real_key("steel_parts.shaft_length_mm", 8.0, 0, 1000, "mm", "shaft length", true),
           real_key("steel_parts.shield_bore_mm", 4.0, 0, 1000, "mm", "end shield: radius of its bore", true),
           real_key("steel_parts.shield_radius_mm", 15.0, 0, 1000, "mm", "end shield: outer radius", true),
           real_key("steel_parts.shield_gap_mm", 1.0, 0, 100, "mm", "end shield: gap between its top and the magnet's bottom face"),
           real_key("steel_parts.shield_thickness_mm", 3.0, 0, 100, "mm", "end shield: thickness", true),
       })
    keys.push_back(k);
  return keys;
}

PartSpec steel_parts_part(const std::string& variant, const Config& cfg, const std::string& material) {
  const double R = cfg.real("magnet.radius_mm"), L = cfg.real("magnet.height_mm");
  PartSpec p;
  p.name = variant;
  p.material = material;
  if (variant == "steel cup" || variant == "brass cup") {
    const double w = cfg.real("steel_parts.cup_wall_mm");
    p.shape = PartShape::Cup;
    p.r_inner_mm = R;
    p.r_outer_mm = R + w;
    p.z_min_mm = -0.5 * L - w;
    p.z_max_mm = 0.5 * L - cfg.real("steel_parts.cup_top_mm");
    p.base_mm = w;
  } else if (variant == "steel shaft") {
    p.shape = PartShape::Cylinder;
    p.r_outer_mm = cfg.real("steel_parts.shaft_radius_mm");
    p.z_max_mm = -0.5 * L;
    p.z_min_mm = p.z_max_mm - cfg.real("steel_parts.shaft_length_mm");
  } else if (variant == "end shield") {
    p.shape = PartShape::Disk;
    p.r_inner_mm = cfg.real("steel_parts.shield_bore_mm");
    p.r_outer_mm = cfg.real("steel_parts.shield_radius_mm");
    p.z_max_mm = -0.5 * L - cfg.real("steel_parts.shield_gap_mm");
    p.z_min_mm = p.z_max_mm - cfg.real("steel_parts.shield_thickness_mm");
  } else {
    throw std::logic_error("steel_parts_part: unknown variant " + variant);
  }
  return p;
}

namespace {

std::string describe(const PartSpec& p) {
  std::string s = to_string(p.shape) + " r " + fmt(p.r_inner_mm, 2) + ".." + fmt(p.r_outer_mm, 2) + " mm, z " +
                  fmt(p.z_min_mm, 2) + ".." + fmt(p.z_max_mm, 2) + " mm";
  if (p.shape == PartShape::Cup) s += ", base " + fmt(p.base_mm, 2) + " mm";
  return s;
}

std::filesystem::path find_file(const std::string& name, const std::vector<std::filesystem::path>& dirs) {
  const std::filesystem::path f(name);
  if (f.is_absolute() || std::filesystem::exists(f)) return f;
  for (const auto& d : dirs)
    if (std::filesystem::exists(d / f)) return d / f;
  return f;  // read_bh_csv names it in its error
}

}  // namespace

namespace {

// The five mounts of the study: ideal and each offset alone.
std::vector<std::pair<std::string, Mount>> study_mounts(double off) {
  std::vector<std::pair<std::string, Mount>> mounts(5);
  mounts[0].first = "ideal";
  mounts[1].first = "sx";
  mounts[1].second.sx_mm = off;
  mounts[2].first = "sy";
  mounts[2].second.sy_mm = off;
  mounts[3].first = "dx";
  mounts[3].second.dx_mm = off;
  mounts[4].first = "dy";
  mounts[4].second.dy_mm = off;
  return mounts;
}

struct Job {
  std::string variant, model;
  std::vector<PartSpec> parts;
};

// The magnet alone, then each part linear and (steel, when asked) nonlinear; geometry checked.
std::vector<Job> study_jobs(const Config& cfg, const SteelPartsResult& r, const std::shared_ptr<const BhCurve>& bh,
                            const FemSettings& base) {
  std::vector<Job> jobs{{"magnet alone", "-", {}}};
  for (const char* v : {"steel cup", "brass cup", "steel shaft", "end shield"}) {
    const bool brass = std::string(v) == "brass cup";
    PartSpec p = steel_parts_part(v, cfg, brass ? "brass" : r.linear_material);
    p.mu_r = part_material_mu_r(p.material, std::string("steel_parts ") + v);
    jobs.push_back({v, "linear", {p}});
    if (bh && !brass) {
      PartSpec q = p;
      q.material = "bh:" + r.bh_file;
      q.bh = bh;
      q.mu_r = bh->mu_r(0.0);
      jobs.push_back({v, "nonlinear", {q}});
    }
  }
  for (const Job& j : jobs) {  // geometry errors before any solve
    DomainSpec d = base.domain;
    d.parts = j.parts;
    d.validate();
  }
  return jobs;
}

// One solve: its statistics, the part's largest |B| and smallest mu_r, the Bz profile along x.
SteelPartsSolve solve_job(const Job& j, double plane_z_mm, MagnetostaticSolver& solver) {
  solver.run();
  const SolveStats& st = solver.stats();
  SteelPartsSolve s;
  s.variant = j.variant;
  s.model = j.model;
  if (!j.parts.empty()) {
    s.parts = describe(j.parts.front());
    s.material = j.parts.front().material;
  }
  s.potential = to_string(solver.options().potential);
  s.dofs = st.dofs;
  s.elements = st.elements;
  s.nonlinear_iterations = st.nonlinear_iterations;
  s.newton_steps = st.newton_steps;
  s.nonlinear_residuals = st.nonlinear_residuals;
  s.linear_iterations = st.iterations;
  s.t_solve_s = st.t_total_s;
  if (!j.parts.empty()) {
    const Eigen::Matrix3Xd& B = solver.B_cell();
    const FeSolution& sol = solver.solution();
    s.part_mu_r_min = std::numeric_limits<double>::infinity();
    for (int t = 0; t < solver.mesh().num_tets(); ++t)
      if (solver.mesh().region[t] == kRegionPartFirst) {
        s.part_B_max_T = std::max(s.part_B_max_T, B.col(t).norm());
        s.part_mu_r_min = std::min(s.part_mu_r_min, sol.mu_r[t]);
      }
  }
  Eigen::Matrix3Xd P(3, 81);
  for (int i = 0; i < 81; ++i) P.col(i) = Eigen::Vector3d(-4.0 + 0.1 * i, 0.0, plane_z_mm);
  const Eigen::Matrix3Xd Bp = solver.evaluator().B_T(P);
  for (int i = 0; i < 81; ++i) {
    s.profile_x_mm.push_back(P(0, i));
    s.profile_Bz_mT.push_back(1e3 * Bp(2, i));
  }
  return s;
}

// The files of the solve the field pictures show (steel_parts.hpp), timed.
void write_field_files(const std::filesystem::path& dir, const Config& cfg, const Job& j, MagnetostaticSolver& solver,
                       SteelPartsResult& r) {
  const auto t0 = std::chrono::steady_clock::now();
  std::filesystem::create_directories(dir);
  const GridData grid = steel_parts_slice_grid(cfg, j.parts.front(), r.plane_z_mm);
  write_bodies_vtu(dir / "bodies.vtu", solver);
  write_B_grid_vti(dir / "slice_y0.vti", grid, solver);
  r.field_files_dir = dir.filename().string();
  r.field_files_solve = j.variant + " (" + j.model + ")";
  r.field_files = {"bodies.vtu", "slice_y0.vti"};
  r.slice_step_mm = grid.spacing_mm.x();
  r.t_field_files_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cerr << "steel_parts: " << r.field_files_solve << ": wrote " << r.field_files_dir << "/bodies.vtu, "
            << r.field_files_dir << "/slice_y0.vti (" << grid.dims[0] << " x " << grid.dims[2] << " nodes) in "
            << fmt(r.t_field_files_s, 2) << " s\n";
}

void log_solve(const SteelPartsSolve& s) {
  std::ostringstream line;
  line << "steel_parts: " << s.variant << " (" << s.model << "): " << s.dofs << " dofs, " << s.potential
       << " potential, " << fmt(s.t_solve_s, 2) << " s";
  if (s.nonlinear_iterations) {
    line << ", " << s.nonlinear_iterations << " nonlinear iterations (" << s.newton_steps << " Newton):";
    for (double x : s.nonlinear_residuals) line << ' ' << fmt_sig(x, 2);
  }
  std::cerr << line.str() << "\n";
}

}  // namespace

GridData steel_parts_slice_grid(const Config& cfg, const PartSpec& part, double plane_z_mm) {
  const double R = cfg.real("magnet.radius_mm"), L = cfg.real("magnet.height_mm");
  const double margin_mm = 2.5, step_mm = 0.05;
  const double half_width_mm = std::max(R, part.r_outer_mm) + margin_mm;
  const double z_min_mm = std::min(-0.5 * L, part.z_min_mm) - margin_mm;
  const double z_max_mm = std::max(0.5 * L, plane_z_mm) + 1.5;
  return GridData::from_range({-half_width_mm, 0.0, z_min_mm}, {half_width_mm, 0.0, z_max_mm},
                              {step_mm, step_mm, step_mm});
}

SteelPartsResult run_steel_parts(const Config& cfg, const std::vector<std::filesystem::path>& search_dirs,
                                 const std::filesystem::path& field_dir) {
  // 1. Inputs, all checked before the first solve.
  if (!cfg.tables("parts").empty())
    throw InputError("parts: steel_parts places its own parts (cup, shaft, end shield); remove [[parts]] from the configuration");
  const FemSettings base = fem_settings_from_config(cfg);
  SteelPartsResult r;
  r.arrays = cfg.strings("study.arrays");
  r.offset_mm = cfg.real("steel_parts.offset_mm");
  r.linear_material = cfg.str("steel_parts.linear_material");
  if (r.linear_material.rfind("bh:", 0) == 0)
    throw InputError("steel_parts.linear_material = " + r.linear_material +
                     " is out of range: allowed mu_r:VALUE or a named material (the B-H curve is steel_parts.bh_file)");
  r.linear_mu_r = part_material_mu_r(r.linear_material, "steel_parts.linear_material");
  std::shared_ptr<const BhCurve> bh;
  if (cfg.flag("steel_parts.nonlinear")) {
    const std::filesystem::path f = find_file(cfg.str("steel_parts.bh_file"), search_dirs);
    bh = std::make_shared<const BhCurve>(read_bh_csv(f, cfg.real("fem.bh_iron_max_mu_r")));
    r.bh_file = cfg.str("steel_parts.bh_file");
  }
  std::vector<ProbeSetup> setups;
  for (const auto& a : r.arrays) setups.push_back(probe_setup_from_config(cfg, a, "study.arrays"));
  r.r0_mm = setups.front().r0_mm;
  r.plane_z_mm = base.plane_z_mm;
  r.window = setups.front().window;
  r.magnet_radius_mm = cfg.real("magnet.radius_mm");
  r.magnet_height_mm = cfg.real("magnet.height_mm");
  r.br_T = cfg.real("magnet.br_T");
  const auto mounts = study_mounts(r.offset_mm);
  const std::vector<Job> jobs = study_jobs(cfg, r, bh, base);
  const std::string field_model = bh ? "nonlinear" : "linear";  // the steel cup's solve of the field files

  // 2. Solves and spectra.
  for (const Job& j : jobs) {
    DomainSpec d = base.domain;
    d.parts = j.parts;
    MagnetostaticSolver solver(d, base.solver);
    SteelPartsSolve s = solve_job(j, r.plane_z_mm, solver);
    if (!field_dir.empty() && j.variant == "steel cup" && j.model == field_model)
      write_field_files(field_dir, cfg, j, solver, r);
    const FemField field(solver.solution());
    for (std::size_t a = 0; a < r.arrays.size(); ++a)
      for (const auto& [label, m] : mounts) {
        const AngleErrorResult e = angle_error(field, setups[a], m);
        r.cases.push_back({j.variant, j.model, r.arrays[a], label, m, e.spectrum, e.field_min_mT, e.field_max_mT, e.in_window});
      }
    log_solve(s);
    r.solves.push_back(std::move(s));
  }
  return r;
}

}  // namespace magenc::fem
