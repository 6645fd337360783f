#include "studies/fem_convergence/fem_convergence_report.hpp"

#include <cmath>

#include "core/format.hpp"
#include "io/plot.hpp"

namespace magenc {

namespace {

// A CSV line; numbers as fmt_sig(v, 6).
std::string row(const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + cells[i];
  return s + "\n";
}
std::string num6(double v) { return fmt_sig(v, 6); }
std::string rate_cell(double rate) { return std::isnan(rate) ? "" : fmt(rate, 2); }
// "P1", "P2" (not "P" + std::to_string(order): GCC 12 -Wrestrict false positive, GCC bug 105651).
std::string order_name(int order) {
  const std::string n = std::to_string(order);
  return "P" + n;
}

std::string refinement_md(const FemConvergenceResult& r) {
  std::vector<std::vector<std::string>> table;
  for (const auto& s : r.refinement)
    for (const auto& c : s.runs)
      table.push_back({order_name(s.order), fmt(c.h_zone_mm, 2), std::to_string(c.dofs),
                       std::to_string(c.iterations), fmt_auto(c.rms_rel, 3), fmt_auto(c.max_rel, 3), rate_cell(c.rate_h),
                       rate_cell(c.rate_dofs), fmt(c.t_mesh_s, 2), fmt(c.t_assemble_s, 2), fmt(c.t_solve_s, 2),
                       fmt(c.t_total_s, 2)});
  return "## Mesh refinement (magnet edge = " + fmt(r.h_magnet_factor, 1) + " x zone edge)\n\n" +
         md_table({"order", "h_zone mm", "DOFs", "CG it.", "RMS err", "max err", "rate (h)", "rate (DOFs)", "t_mesh s",
                   "t_asm s", "t_solve s", "t_total s"},
                  table) +
         "\nRates: e ~ h^p from the zone edge length, and e ~ DOFs^(-p) (p_h = 3 p_DOFs for uniform refinement; "
         "theory for B: P1 p_h = 1, P2 p_h = 2).\n\n" + md_image("error vs DOFs", "convergence.png") + "\n";
}

void write_convergence_plot(StudyOutput& out, const FemConvergenceResult& r) {
  PlotPanel panel{"Bz error on the sensing plane vs exact field", "degrees of freedom", "error / peak |Bz|", {}, true, true, {}};
  for (const auto& s : r.refinement) {
    PlotSeries rms{order_name(s.order) + " RMS", {}, {}, "linespoints", "lw 2"};
    PlotSeries mx{order_name(s.order) + " max", {}, {}, "linespoints", "dt 2"};
    for (const auto& c : s.runs) {
      rms.x.push_back(double(c.dofs));
      rms.y.push_back(c.rms_rel);
      mx.x.push_back(double(c.dofs));
      mx.y.push_back(c.max_rel);
    }
    panel.series.push_back(rms);
    panel.series.push_back(mx);
  }
  PlotSpec spec;
  spec.title = "fem\\_convergence: FEM vs exact field, mu_r = 1";
  spec.panels.push_back(panel);
  write_plot(out.dir(), "convergence", spec);
}

std::string faceting_md(const FemConvergenceResult& r) {
  std::vector<std::vector<std::string>> table;
  for (const auto& f : r.faceting)
    table.push_back({std::to_string(f.segments), f.equal_area ? "yes" : "no", std::to_string(f.dofs),
                     fmt_auto(f.rms_rel, 3), fmt_auto(f.max_rel, 3)});
  return "## Faceting of the curved face (P2, zone edge " + fmt(r.side_h_zone_mm, 2) + " mm)\n\nWith vertices on the circle the "
         "N-gon's area (hence the dipole moment) is low by sin(2pi/N)/(2pi/N); equal_area scales the radius to fix it.\n\n" +
         md_table({"segments", "equal area", "DOFs", "RMS err", "max err"}, table) + "\n";
}

std::string truncation_md(const FemConvergenceResult& r) {
  std::vector<std::vector<std::string>> table;
  for (const auto& t : r.truncation)
    table.push_back({fmt(t.outer_radius_mm, 0), t.robin ? "Robin" : "psi = 0", std::to_string(t.dofs),
                     fmt_auto(t.rms_rel, 3), fmt_auto(t.max_rel, 3), fmt_auto(t.rms_vec_rel, 3)});
  return "## Truncation radius (P2, zone edge " + fmt(r.side_h_zone_mm, 2) + " mm)\n\n"
         "Bz errors relative to peak |Bz|; `RMS |dB|` is the RMS of the full vector error relative to peak |B|. "
         "Truncating a dipole field with psi = 0 adds, to leading order, a uniform field along M (x) of size m/R^3: "
         "invisible in Bz, visible in the vector error.\n\n" +
         md_table({"outer radius mm", "boundary", "DOFs", "RMS err Bz", "max err Bz", "RMS |dB|"}, table) + "\n";
}

// Rows of a potential comparison's table: zone edge, total's DOFs and errors, the other's errors.
std::vector<std::vector<std::string>> potential_table(const PotentialComparison& pc) {
  std::vector<std::vector<std::string>> table;
  for (const auto& p : pc.rows) {
    std::vector<std::string> cells = {fmt(p.h_zone_mm, 2), std::to_string(p.total.dofs), fmt_auto(p.total.rms_rel, 3),
                                      fmt_auto(p.total.max_rel, 3)};
    if (p.other)
      cells.insert(cells.end(), {fmt_auto(p.other->rms_rel, 3), fmt_auto(p.other->max_rel, 3)});
    else
      cells.insert(cells.end(), {"(reference)", ""});
    table.push_back(cells);
  }
  return table;
}

// One "total vs <other> potential" section: heading, what the other formulation does, the error table.
std::string potential_md(const PotentialComparison& pc, const std::string& heading, const std::string& other,
                         const std::string& explanation) {
  return "## " + heading + "\n\nBz on the plane against the " + other + "-potential solve at zone edge " +
         fmt(pc.h_ref_mm, 2) + " mm" + explanation + "\n\n" +
         md_table({"h_zone mm", "DOFs", "total: RMS err", "total: max err", other + ": RMS err", other + ": max err"},
                  potential_table(pc)) +
         "\n";
}

std::string reduced_md(const PotentialComparison& pc) {
  return potential_md(pc, "Total vs reduced potential (P2, magnet mu_r = " + fmt(pc.mu_r, 3) + ")", "reduced",
                      " (the exact field has no permeability). The reduced potential takes the magnet's free-space "
                      "field from the exact solution and solves only the reaction of the permeable magnet, so only "
                      "that ~(mu_r - 1) share carries discretization error (fem.potential).");
}

std::string shaft_md(const PotentialComparison& pc) {
  return potential_md(pc,
                      "Total vs split potential with a shaft (P2, shaft mu_r = " + fmt(pc.mu_r, 4) + ", magnet mu_r = 1)",
                      "split",
                      ". The split keeps the total potential inside the shaft (where H ~ 0) and the reduced potential "
                      "elsewhere, so only the shaft's reaction carries discretization error (fem.potential = split, the "
                      "default with a shaft).");
}

}  // namespace

std::string convergence_csv(const FemConvergenceResult& r) {
  std::string csv = row({"order", "h_zone_mm", "h_magnet_mm", "elements", "dofs", "iterations", "rms_rel", "max_rel",
                         "rate_rms_h", "rate_rms_dofs", "t_mesh_s", "t_assemble_s", "t_solve_s", "t_total_s", "peak_rss_mib"});
  for (const auto& s : r.refinement)
    for (const auto& c : s.runs)
      csv += row({std::to_string(s.order), num6(c.h_zone_mm), num6(c.h_magnet_mm), std::to_string(c.elements),
                  std::to_string(c.dofs), std::to_string(c.iterations), num6(c.rms_rel), num6(c.max_rel), num6(c.rate_h),
                  num6(c.rate_dofs), num6(c.t_mesh_s), num6(c.t_assemble_s), num6(c.t_solve_s), num6(c.t_total_s),
                  num6(c.peak_rss_mib)});
  return csv;
}

std::string faceting_csv(const std::vector<FacetingRun>& runs) {
  std::string csv = row({"segments", "equal_area", "dofs", "rms_rel", "max_rel"});
  for (const auto& f : runs)
    csv += row({std::to_string(f.segments), f.equal_area ? "true" : "false", std::to_string(f.dofs), num6(f.rms_rel),
                num6(f.max_rel)});
  return csv;
}

std::string truncation_csv(const std::vector<TruncationRun>& runs) {
  std::string csv = row({"outer_radius_mm", "boundary", "dofs", "rms_rel", "max_rel", "rms_vec_rel"});
  for (const auto& t : runs)
    csv += row({num6(t.outer_radius_mm), t.robin ? "robin" : "dirichlet", std::to_string(t.dofs), num6(t.rms_rel),
                num6(t.max_rel), num6(t.rms_vec_rel)});
  return csv;
}

std::string potential_csv(const PotentialComparison& pc) {
  std::string csv = row({"h_zone_mm", "dofs", "potential", "rms_rel", "max_rel", "iterations"});
  auto line = [&](double h, const std::string& pot, const PotentialSolve& s) {
    csv += row({num6(h), std::to_string(s.dofs), pot, num6(s.rms_rel), num6(s.max_rel), std::to_string(s.iterations)});
  };
  for (const auto& p : pc.rows) {
    line(p.h_zone_mm, "total", p.total);
    if (p.other) line(p.h_zone_mm, pc.other, *p.other);
  }
  return csv;
}

void write_fem_convergence_report(StudyOutput& out, const FemConvergenceResult& r) {
  std::string md = "# fem_convergence\n\nBz of the FEM on the sensing plane (z_s = " + fmt(r.plane_z_mm, 2) +
                   " mm, grid " + std::to_string(r.plane_nx) + "x" + std::to_string(r.plane_ny) + ", step " +
                   fmt(r.plane_step_mm, 3) + " mm) against the exact field, with the magnet's mu_r forced to 1 (exact field: no permeability). Errors relative to the peak |Bz| on the grid. B from the " +
                   std::string(r.recovery ? "recovered (node-averaged) gradient of psi (fem.recovery = true)"
                                          : "raw FE gradient (fem.recovery = false)") + ".\n\n";
  out.write_text("convergence.csv", convergence_csv(r));
  write_convergence_plot(out, r);
  md += refinement_md(r);
  if (!r.faceting.empty()) {
    out.write_text("faceting.csv", faceting_csv(r.faceting));
    md += faceting_md(r);
  }
  if (!r.truncation.empty()) {
    out.write_text("truncation.csv", truncation_csv(r.truncation));
    md += truncation_md(r);
  }
  if (r.reduced.ran()) {
    out.write_text("potential.csv", potential_csv(r.reduced));
    md += reduced_md(r.reduced);
  }
  if (r.shaft.ran()) {
    out.write_text("shaft_potential.csv", potential_csv(r.shaft));
    md += shaft_md(r.shaft);
  }
  out.write_text("summary.md", md);
}

}  // namespace magenc
