// Study fem_convergence: the FEM's Bz on the sensing plane against the exact
// field (mu_r = 1), for several mesh sizes and orders 1 and 2; then, at one
// mesh, the effect of the faceting of the curved face (segments, equal-area
// radius) and of the truncation radius (Robin vs psi = 0). Writes
//   convergence.csv, faceting.csv, truncation.csv, convergence.png, summary.md
//   fem_convergence [--config studies/fem_convergence.toml] [--set convergence.orders=2] [--out DIR]
#include <cmath>
#include <sstream>

#include "core/errors.hpp"
#include "fem_field.hpp"
#include "fem_config.hpp"
#include "io/plot.hpp"
#include "report/study_output.hpp"
#include "analysis/sweep.hpp"
#include "validation.hpp"

using namespace magenc;
using namespace magenc::fem;

namespace {

std::vector<KeySpec> study_keys() {
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

std::vector<double> numbers(const Config& cfg, const std::string& key) {
  return cfg.numbers(key);
}

std::string row(const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + cells[i];
  return s + "\n";
}
std::string g(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs: the solver settings of the config, plane grid for the comparison.
  FemSettings base = fem_settings_from_config(cfg);
  base.solver.progress_every = 0;
  // This study measures the total potential's discretization error against the exact field (with
  // mu_r = 1 the reduced potential, fem.potential = auto, is the exact field); section 5 compares the
  // formulations explicitly.
  base.solver.potential = "total";
  // The exact field has no permeability: the comparison is made with mu_r = 1
  // whatever magnet.mu_r says (stated in summary.md).
  base.domain.magnet.mu_r = 1.0;
  // The runs refine the zone box (and the magnet) only: no core cylinder with
  // its own fixed edge length, so the rates are rates in h_zone.
  base.domain.zone.core_radius_mm = 0;
  const GridData& plane = base.plane;
  const auto hs = numbers(cfg, "convergence.h_zone_list");
  const auto orders = numbers(cfg, "convergence.orders");
  if (hs.size() < 2) throw InputError("convergence.h_zone_list needs at least 2 sizes");
  const double factor = cfg.real("convergence.h_magnet_factor");
  std::string md = "# fem_convergence\n\nBz of the FEM on the sensing plane (z_s = " + fmt(base.plane_z_mm, 2) +
                   " mm, grid " + std::to_string(plane.dims[0]) + "x" + std::to_string(plane.dims[1]) + ", step " +
                   fmt(plane.spacing_mm[0], 3) + " mm) against the exact field, with the magnet's mu_r forced to 1 (exact field: no permeability). Errors relative to the peak |Bz| on the grid. B from the " +
                   std::string(base.solver.recovery ? "recovered (node-averaged) gradient of psi (fem.recovery = true)"
                                                    : "raw FE gradient (fem.recovery = false)") + ".\n\n";

  // 2. Mesh-size sweep per order.
  std::string csv = row({"order", "h_zone_mm", "h_magnet_mm", "elements", "dofs", "iterations", "rms_rel", "max_rel",
                         "rate_rms_h", "rate_rms_dofs", "t_mesh_s", "t_assemble_s", "t_solve_s", "t_total_s", "peak_rss_mib"});
  std::vector<std::vector<std::string>> table;
  PlotPanel panel{"Bz error on the sensing plane vs exact field", "degrees of freedom", "error / peak |Bz|", {}, true, true, {}};
  for (double od : orders) {
    const int order = static_cast<int>(od);
    PlotSeries rms{"P" + std::to_string(order) + " RMS", {}, {}, "linespoints", "lw 2"};
    PlotSeries mx{"P" + std::to_string(order) + " max", {}, {}, "linespoints", "dt 2"};
    double prev_h = 0, prev_e = 0, prev_d = 0;
    for (double h : hs) {
      DomainSpec d = base.domain;
      d.mesh.h_zone_mm = h;
      d.mesh.h_magnet_mm = factor * h;
      SolverOptions o = base.solver;
      o.order = order;
      const ExactComparison c = solve_and_compare_with_exact(d, o, plane);
      const double rate_h = prev_h > 0 ? observed_rate(1.0 / prev_h, prev_e, 1.0 / h, c.error.rms_rel()) : NAN;
      const double rate_d = prev_h > 0 ? observed_rate(prev_d, prev_e, double(c.stats.dofs), c.error.rms_rel()) : NAN;
      std::fprintf(stderr, "fem_convergence: P%d h %.3g: dofs %ld, RMS %.3e, max %.3e, %.1f s\n", order, h, c.stats.dofs,
                   c.error.rms_rel(), c.error.max_rel(), c.stats.t_total_s);
      csv += row({std::to_string(order), g(h), g(factor * h), std::to_string(c.stats.elements), std::to_string(c.stats.dofs),
                  std::to_string(c.stats.iterations), g(c.error.rms_rel()), g(c.error.max_rel()), g(rate_h), g(rate_d),
                  g(c.stats.t_mesh_s), g(c.stats.t_assemble_s), g(c.stats.t_solve_s), g(c.stats.t_total_s), g(c.peak_rss_mib)});
      table.push_back({"P" + std::to_string(order), fmt(h, 2), std::to_string(c.stats.dofs), std::to_string(c.stats.iterations),
                       fmt_auto(c.error.rms_rel(), 3), fmt_auto(c.error.max_rel(), 3), std::isnan(rate_h) ? "" : fmt(rate_h, 2),
                       std::isnan(rate_d) ? "" : fmt(rate_d, 2), fmt(c.stats.t_mesh_s, 2), fmt(c.stats.t_assemble_s, 2),
                       fmt(c.stats.t_solve_s, 2), fmt(c.stats.t_total_s, 2)});
      rms.x.push_back(double(c.stats.dofs));
      rms.y.push_back(c.error.rms_rel());
      mx.x.push_back(double(c.stats.dofs));
      mx.y.push_back(c.error.max_rel());
      prev_h = h;
      prev_e = c.error.rms_rel();
      prev_d = double(c.stats.dofs);
    }
    panel.series.push_back(rms);
    panel.series.push_back(mx);
  }
  out.write_text("convergence.csv", csv);
  PlotSpec spec;
  spec.title = "fem\\_convergence: FEM vs exact field, mu_r = 1";
  spec.panels.push_back(panel);
  write_plot(out.dir(), "convergence", spec);
  md += "## Mesh refinement (magnet edge = " + fmt(factor, 1) + " x zone edge)\n\n" +
        md_table({"order", "h_zone mm", "DOFs", "CG it.", "RMS err", "max err", "rate (h)", "rate (DOFs)", "t_mesh s",
                  "t_asm s", "t_solve s", "t_total s"},
                 table) +
        "\nRates: e ~ h^p from the zone edge length, and e ~ DOFs^(-p) (p_h = 3 p_DOFs for uniform refinement; "
        "theory for B: P1 p_h = 1, P2 p_h = 2).\n\n" + md_image("error vs DOFs", "convergence.png") + "\n";

  // 3. Faceting: segments around the curved face, with and without the equal-area radius.
  const auto segs = numbers(cfg, "convergence.faceting_segments");
  const double hs_side = cfg.real("convergence.side_h_zone_mm");
  if (!segs.empty()) {
    std::string fcsv = row({"segments", "equal_area", "dofs", "rms_rel", "max_rel"});
    std::vector<std::vector<std::string>> ft;
    for (double n : segs)
      for (bool eq : {false, true}) {
        DomainSpec d = base.domain;
        d.mesh.segments = static_cast<int>(n);
        d.mesh.equal_area = eq;
        d.mesh.h_zone_mm = hs_side;
        d.mesh.h_magnet_mm = factor * hs_side;
        SolverOptions o = base.solver;
        o.order = 2;
        const ExactComparison c = solve_and_compare_with_exact(d, o, plane);
        fcsv += row({std::to_string(int(n)), eq ? "true" : "false", std::to_string(c.stats.dofs), g(c.error.rms_rel()),
                     g(c.error.max_rel())});
        ft.push_back({std::to_string(int(n)), eq ? "yes" : "no", std::to_string(c.stats.dofs), fmt_auto(c.error.rms_rel(), 3),
                      fmt_auto(c.error.max_rel(), 3)});
      }
    out.write_text("faceting.csv", fcsv);
    md += "## Faceting of the curved face (P2, zone edge " + fmt(hs_side, 2) + " mm)\n\nWith vertices on the circle the "
          "N-gon's area (hence the dipole moment) is low by sin(2pi/N)/(2pi/N); equal_area scales the radius to fix it.\n\n" +
          md_table({"segments", "equal area", "DOFs", "RMS err", "max err"}, ft) + "\n";
  }

  // 4. Truncation: outer radius, Robin vs Dirichlet.
  const auto radii = numbers(cfg, "convergence.truncation_radii");
  if (!radii.empty()) {
    std::string tcsv = row({"outer_radius_mm", "boundary", "dofs", "rms_rel", "max_rel", "rms_vec_rel"});
    std::vector<std::vector<std::string>> tt;
    for (double R : radii)
      for (bool robin : {false, true}) {
        DomainSpec d = base.domain;
        d.mesh.outer_radius_mm = R;
        d.mesh.h_zone_mm = hs_side;
        d.mesh.h_magnet_mm = factor * hs_side;
        SolverOptions o = base.solver;
        o.order = 2;
        o.robin = robin;
        const ExactComparison c = solve_and_compare_with_exact(d, o, plane);
        tcsv += row({g(R), robin ? "robin" : "dirichlet", std::to_string(c.stats.dofs), g(c.error.rms_rel()), g(c.error.max_rel()),
                     g(c.error.rms_vec_rel())});
        tt.push_back({fmt(R, 0), robin ? "Robin" : "psi = 0", std::to_string(c.stats.dofs), fmt_auto(c.error.rms_rel(), 3),
                      fmt_auto(c.error.max_rel(), 3), fmt_auto(c.error.rms_vec_rel(), 3)});
      }
    out.write_text("truncation.csv", tcsv);
    md += "## Truncation radius (P2, zone edge " + fmt(hs_side, 2) + " mm)\n\n"
          "Bz errors relative to peak |Bz|; `RMS |dB|` is the RMS of the full vector error relative to peak |B|. "
          "Truncating a dipole field with psi = 0 adds, to leading order, a uniform field along M (x) of size m/R^3: "
          "invisible in Bz, visible in the vector error.\n\n" +
          md_table({"outer radius mm", "boundary", "DOFs", "RMS err Bz", "max err Bz", "RMS |dB|"}, tt) + "\n";
  }
  // 5./6. Total against a reduced-kind potential on the same meshes, P2; the reference is the
  //       reduced-kind solve of the finest mesh. Returns the CSV and the table rows.
  auto potential_comparison = [&](const DomainSpec& dom, const std::string& other) {
    auto solve_at = [&](double h, const std::string& pot) {
      DomainSpec d = dom;
      d.mesh.h_zone_mm = h;
      d.mesh.h_magnet_mm = factor * h;
      SolverOptions o = base.solver;
      o.order = 2;
      o.potential = pot;
      auto s = std::make_unique<MagnetostaticSolver>(d, o);
      s->run();
      return s;
    };
    const double h_ref = hs.back();
    const FemField ref(solve_at(h_ref, other)->solution());
    std::string csv = row({"h_zone_mm", "dofs", "potential", "rms_rel", "max_rel", "iterations"});
    std::vector<std::vector<std::string>> table;
    for (double h : hs) {
      std::vector<std::string> cells = {fmt(h, 2)};
      for (const std::string pot : {std::string("total"), other}) {
        if (h == h_ref && pot == other) {
          cells.insert(cells.end(), {"(reference)", ""});
          continue;
        }
        const auto s = solve_at(h, pot);
        const BzErrorStats e = bz_error_on_grid(s->evaluator(), ref, plane);
        csv += row({g(h), std::to_string(s->stats().dofs), pot, g(e.rms_rel()), g(e.max_rel()),
                    std::to_string(s->stats().iterations)});
        if (pot == "total") cells.push_back(std::to_string(s->stats().dofs));
        cells.insert(cells.end(), {fmt_auto(e.rms_rel(), 3), fmt_auto(e.max_rel(), 3)});
      }
      table.push_back(cells);
    }
    return std::make_pair(csv, table);
  };
  // 5. Total vs reduced potential with a permeable magnet (no exact field).
  const double mu_p = cfg.real("convergence.potential_mu_r");
  if (mu_p > 0) {
    if (mu_p < 1) throw InputError("convergence.potential_mu_r = " + fmt(mu_p, 3) + " must be 0 (skip) or >= 1");
    DomainSpec d = base.domain;
    d.magnet.mu_r = mu_p;
    const auto [pcsv, pt] = potential_comparison(d, "reduced");
    out.write_text("potential.csv", pcsv);
    md += "## Total vs reduced potential (P2, magnet mu_r = " + fmt(mu_p, 3) + ")\n\nBz on the plane against the reduced-"
          "potential solve at zone edge " + fmt(hs.back(), 2) + " mm (the exact field has no permeability). The reduced "
          "potential takes the magnet's free-space field from the exact solution and solves only the reaction of the "
          "permeable magnet, so only that ~(mu_r - 1) share carries discretization error (fem.potential).\n\n" +
          md_table({"h_zone mm", "DOFs", "total: RMS err", "total: max err", "reduced: RMS err", "reduced: max err"}, pt) +
          "\n";
  }
  // 6. Total vs split potential with a permeable shaft (magnet mu_r = 1, so the
  //    split carries only the shaft's reaction).
  const double mu_s = cfg.real("convergence.shaft_mu_r");
  if (mu_s > 0) {
    if (mu_s < 1) throw InputError("convergence.shaft_mu_r = " + fmt(mu_s, 3) + " must be 0 (skip) or >= 1");
    DomainSpec d = base.domain;
    d.shaft.enabled = true;
    d.shaft.mu_r = mu_s;
    const auto [scsv, st] = potential_comparison(d, "split");
    out.write_text("shaft_potential.csv", scsv);
    md += "## Total vs split potential with a shaft (P2, shaft mu_r = " + fmt(mu_s, 4) + ", magnet mu_r = 1)\n\nBz on "
          "the plane against the split-potential solve at zone edge " + fmt(hs.back(), 2) + " mm. The split keeps the total "
          "potential inside the shaft (where H ~ 0) and the reduced potential elsewhere, so only the shaft's reaction "
          "carries discretization error (fem.potential = split, the default with a shaft).\n\n" +
          md_table({"h_zone mm", "DOFs", "total: RMS err", "total: max err", "split: RMS err", "split: max err"}, st) +
          "\n";
  }
  out.write_text("summary.md", md);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study("fem_convergence", "FEM Bz on the sensing plane vs the exact field: mesh size, order, faceting, truncation",
                   study_keys(), argc, argv, run);
}
