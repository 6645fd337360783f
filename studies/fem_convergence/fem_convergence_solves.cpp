#include "studies/fem_convergence/fem_convergence_solves.hpp"

#include <iostream>
#include <memory>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "field_solver/field_io/fem_field.hpp"
#include "field_solver/field_io/validation.hpp"

namespace magenc::fem {

std::vector<KeySpec> fem_convergence_keys() {
  auto keys = fem_keys();
  for (auto k : std::vector<KeySpec>{
           real_list_key("convergence.h_zone_list", {0.8, 0.55, 0.4, 0.3}, 0, 1000, "mm", "zone edge lengths (mm), coarse to fine", true),
           real_key("convergence.h_magnet_factor", 2.0, 0, 100, "", "magnet edge length = factor x zone edge length", true),
           int_list_key("convergence.orders", {1, 2}, 1, 2, "element orders (1, 2)"),
           int_list_key("convergence.faceting_segments", {16, 32, 64, 128}, 3, 1000000, "segment counts for the faceting runs (empty: skip)", 0),
           real_list_key("convergence.truncation_radii", {15, 30, 60, 120}, 0, 1000, "mm", "outer radii (mm) for the truncation runs (empty: skip)", true, 0),
           real_key("convergence.potential_mu_r", 1.05, 0, 1000, "",
                    "total vs reduced potential at this magnet mu_r (P2, each h of h_zone_list) against the reduced "
                    "solve of the finest h (0 = skip)"),
           real_key("convergence.shaft_mu_r", 1000, 0, 1e6, "",
                    "total vs split potential with the shaft (shaft.* keys) at this mu_r (P2, each h of h_zone_list, "
                    "magnet mu_r = 1) against the split solve of the finest h (0 = skip)"),
           real_key("convergence.side_h_zone_mm", 0.4, 0, 100, "mm", "zone edge length of the faceting/truncation runs", true),
       })
    keys.push_back(k);
  return keys;
}

namespace {

// key's mu_r: 0 (skip) or >= 1.
double mu_r_or_skip(const Config& cfg, const std::string& key) {
  const double mu = cfg.real(key);
  if (mu > 0 && mu < 1) throw InputError(key + " = " + fmt(mu, 3) + " must be 0 (skip) or >= 1");
  return mu;
}

// The solver settings and zone edge lengths every solve of the study shares.
struct Setup {
  FemSettings base;
  std::vector<double> hs;
  double factor = 0;
  DomainSpec at(const DomainSpec& dom, double h_zone) const {
    DomainSpec d = dom;
    d.mesh.h_zone_mm = h_zone;
    d.mesh.h_magnet_mm = factor * h_zone;
    return d;
  }
  SolverOptions p2() const {
    SolverOptions o = base.solver;
    o.order = 2;
    return o;
  }
};

// Total against `other` on dom's meshes at every zone edge, P2; the reference is `other`'s solve at the finest.
PotentialComparison potential_comparison(const Setup& s, const DomainSpec& dom, double mu_r, Potential other) {
  auto solve_at = [&](double h, Potential pot) {
    SolverOptions o = s.p2();
    o.potential = pot;
    auto solver = std::make_unique<MagnetostaticSolver>(s.at(dom, h), o);
    solver->run();
    return solver;
  };
  PotentialComparison pc;
  pc.mu_r = mu_r;
  pc.other = to_string(other);
  pc.h_ref_mm = s.hs.back();
  const FemField ref(solve_at(pc.h_ref_mm, other)->solution());
  for (double h : s.hs) {
    PotentialRow row;
    row.h_zone_mm = h;
    for (const Potential pot : {Potential::Total, other}) {
      if (h == pc.h_ref_mm && pot == other) continue;  // the reference itself
      const auto solver = solve_at(h, pot);
      const BzErrorStats e = bz_error_on_grid(solver->evaluator(), ref, s.base.plane);
      const PotentialSolve ps{solver->stats().dofs, solver->stats().iterations, e.rms_rel(), e.max_rel()};
      if (pot == Potential::Total)
        row.total = ps;
      else
        row.other = ps;
    }
    pc.rows.push_back(row);
  }
  return pc;
}

}  // namespace

FemConvergenceResult run_fem_convergence(const Config& cfg) {
  // 1. Inputs, all checked before the first solve.
  Setup s;
  s.base = fem_settings_from_config(cfg);
  s.base.solver.progress_every = 0;
  // The study measures the total potential's discretization error against the exact field (with
  // mu_r = 1 the reduced potential, fem.potential = auto, is the exact field); the potential
  // comparisons compare the formulations explicitly.
  s.base.solver.potential = Potential::Total;
  // Rates are read from errors down to ~1e-5 of peak: the CG solves stop at 1e-10 (the solve_field
  // default 1e-8 is chosen for the reduced potential, whose correction is small).
  s.base.solver.tolerance = 1e-10;
  // The exact field has no permeability: the comparison is made with mu_r = 1
  // whatever magnet.mu_r says (stated in summary.md).
  s.base.domain.magnet.mu_r = 1.0;
  // The runs refine the zone box (and the magnet) only: no core cylinder with
  // its own fixed edge length, so the rates are rates in h_zone.
  s.base.domain.zone.core_radius_mm = 0;
  s.hs = cfg.reals("convergence.h_zone_list");
  if (s.hs.size() < 2) throw InputError("convergence.h_zone_list needs at least 2 sizes");
  s.factor = cfg.real("convergence.h_magnet_factor");
  const auto orders = cfg.integers("convergence.orders");
  const auto segments = cfg.integers("convergence.faceting_segments");
  const auto radii = cfg.reals("convergence.truncation_radii");
  const double side_h = cfg.real("convergence.side_h_zone_mm");
  const double mu_magnet = mu_r_or_skip(cfg, "convergence.potential_mu_r");
  const double mu_shaft = mu_r_or_skip(cfg, "convergence.shaft_mu_r");
  const GridData& plane = s.base.plane;

  FemConvergenceResult r;
  r.plane_z_mm = s.base.plane_z_mm;
  r.plane_step_mm = plane.spacing_mm[0];
  r.plane_nx = plane.dims[0];
  r.plane_ny = plane.dims[1];
  r.recovery = s.base.solver.recovery;
  r.h_magnet_factor = s.factor;
  r.side_h_zone_mm = side_h;

  // 2. Mesh refinement per order.
  for (long order : orders) {
    RefinementSeries series;
    series.order = static_cast<int>(order);
    for (double h : s.hs) {
      SolverOptions o = s.base.solver;
      o.order = series.order;
      const ExactComparison c = solve_and_compare_with_exact(s.at(s.base.domain, h), o, plane);
      series.runs.push_back({h, s.factor * h, c.stats.elements, c.stats.dofs, c.stats.iterations, c.error.rms_rel(),
                             c.error.max_rel(), 0, 0, c.stats.t_mesh_s, c.stats.t_assemble_s, c.stats.t_solve_s,
                             c.stats.t_total_s, c.peak_rss_mib});
      std::cerr << "fem_convergence: P" << series.order << " h " << fmt_sig(h, 3) << ": dofs " << c.stats.dofs
                << ", RMS " << fmt_sig(c.error.rms_rel(), 4) << ", max " << fmt_sig(c.error.max_rel(), 4) << ", "
                << fmt(c.stats.t_total_s, 1) << " s\n";
    }
    estimate_rates(series.runs);
    r.refinement.push_back(series);
  }

  // 3. Faceting: segments around the curved face, with and without the equal-area radius.
  for (long n : segments)
    for (bool eq : {false, true}) {
      DomainSpec d = s.at(s.base.domain, side_h);
      d.mesh.segments = static_cast<int>(n);
      d.mesh.equal_area = eq;
      const ExactComparison c = solve_and_compare_with_exact(d, s.p2(), plane);
      r.faceting.push_back({static_cast<int>(n), eq, c.stats.dofs, c.error.rms_rel(), c.error.max_rel()});
    }

  // 4. Truncation: outer radius, Robin vs psi = 0.
  for (double R : radii)
    for (bool robin : {false, true}) {
      DomainSpec d = s.at(s.base.domain, side_h);
      d.mesh.outer_radius_mm = R;
      SolverOptions o = s.p2();
      o.robin = robin;
      const ExactComparison c = solve_and_compare_with_exact(d, o, plane);
      r.truncation.push_back({R, robin, c.stats.dofs, c.error.rms_rel(), c.error.max_rel(), c.error.rms_vec_rel()});
    }

  // 5. Total vs reduced potential with a permeable magnet (no exact field).
  if (mu_magnet > 0) {
    DomainSpec d = s.base.domain;
    d.magnet.mu_r = mu_magnet;
    r.reduced = potential_comparison(s, d, mu_magnet, Potential::Reduced);
  }
  // 6. Total vs split potential with a permeable shaft (magnet mu_r = 1, so the
  //    split carries only the shaft's reaction).
  if (mu_shaft > 0) {
    DomainSpec d = s.base.domain;
    d.shaft.enabled = true;
    d.shaft.mu_r = mu_shaft;
    r.shaft = potential_comparison(s, d, mu_shaft, Potential::Split);
  }
  return r;
}

}  // namespace magenc::fem
