#include "studies/harmonic_provenance/provenance_report.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "io/plot.hpp"
#include "io/tables.hpp"
#include "report/study_plots.hpp"

namespace magenc {

namespace {
// Log-scale plots need a floor for exact zeros; values below it are drawn at it and the
// axis labels say so. 1e-12 deg: below the solver-tolerance level of the D16 solutions'
// ideal-mount harmonics (~1e-11..1e-10 deg at fem.tolerance 1e-8), which a 1e-9 floor hid.
constexpr double kLogFloorDeg = 1e-12;
// v for a log-scale panel: at least the floor; a panel that drew a value at the floor says so.
double on_log_axis(double v, PlotPanel& p) {
  if (v >= kLogFloorDeg) return v;
  const std::string note = " (< 1e-12 drawn at 1e-12)";
  if (p.ylabel.find(note) == std::string::npos) p.ylabel += note;
  return kLogFloorDeg;
}

// The provenance run's views shared by the report's parts.
auto row_finder(const ProvenanceRun& run) {
  return [&run](const std::string& source, const std::string& variant, const std::string& case_label) {
    return &run.row(source, variant, case_label);
  };
}

// provenance.csv: one exact row per case, then every sampled row.
void write_provenance_table(StudyOutput& out, const ProvenanceRun& run) {
  const ProbeSetup& setup = run.options.setup;
  const auto& cases = run.options.cases;
  const auto& rows = run.rows;
  std::vector<SpectrumRow> table;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto& c = cases[i];
    table.push_back({"analytic", setup.array.name, setup.r0_mm, c.mount, run.exact_spectra[i],
                     {{"source", "exact"}, {"variant", "exact"}, {"h_mm", "0"}, {"interp", ""}, {"case", c.label}}});
  }
  for (const auto& r : rows) {
    const Mount m = std::find_if(cases.begin(), cases.end(), [&](auto& c) { return c.label == r.case_label; })->mount;
    table.push_back({r.source, setup.array.name, setup.r0_mm, m, r.sampled,
                     {{"source", r.source}, {"variant", r.variant}, {"h_mm", fmt_sig(r.h_mm, 6)}, {"interp", r.interp}, {"case", r.case_label}}});
  }
  out.write_text("provenance.csv", spectra_csv(table));
}

// artefacts_vs_h: artefact of c4 and pp vs h per mode and case (log-log); ideal_harmonics: ideal-mount bars.
void write_grid_plots(StudyOutput& out, const ProvenanceRun& run) {
  const auto& cases = run.options.cases;
  const auto& rows = run.rows;
  const std::size_t n_grid_rows = run.n_grid_rows;
  const auto& spacings = run.options.spacings_mm;
  const auto& modes = run.options.modes;
  std::vector<PlotPanel> panels;
  for (const auto& c : cases) {
    for (const std::string what : {"c4", "pp"}) {
      PlotPanel p;
      p.title = c.label + ": " + (what == "pp" ? std::string("peak-to-peak error") : "artefact |c_4 - c_4^{exact}|");
      p.xlabel = "grid spacing h [mm]";
      p.ylabel = what == "pp" ? "pp(grid) - pp(exact) [deg]" : "artefact [deg]";
      p.logx = p.logy = true;
      for (const Interp m : modes) {
        PlotSeries s;
        s.title = interp_name(m);
        s.style = "linespoints";
        for (std::size_t i = 0; i < n_grid_rows; ++i) {
          const auto& r = rows[i];
          if (r.case_label != c.label || r.interp != interp_name(m)) continue;
          s.x.push_back(r.h_mm);
          const double a = what == "pp" ? std::abs(r.sampled.pp_deg - r.exact.pp_deg)
                                        : std::abs(r.sampled.c_deg[4] - r.exact.c_deg[4]);
          s.y.push_back(on_log_axis(a, p));
        }
        p.series.push_back(s);
      }
      panels.push_back(p);
    }
  }
  write_plot(out.dir(), "artefacts_vs_h",
             {"Grid-sampling artefacts vs spacing (exact field sampled on a Cartesian plane grid)", panels, 2, 1100, 1200});
  std::vector<SpectrumCase> bars;
  for (const auto& r : rows) {
    if (r.case_label != "ideal") continue;
    const bool coarse_nn = r.source == "grid" && r.h_mm == spacings.front() && r.interp == "nearest";
    const bool fine_nn = r.source == "grid" && r.h_mm == spacings.back() && r.interp == "nearest";
    const bool fine_cubic = r.source == "grid" && r.h_mm == spacings.back() && r.interp == "cubic";
    if (coarse_nn || fine_nn || fine_cubic || r.source == "fem") bars.push_back({plot_literal(r.source + " " + r.variant), r.sampled});
  }
  write_plot(out.dir(), "ideal_harmonics",
             {"Ideal mount: every harmonic is an artefact (exact field gives none)",
              {harmonics_panel("logarithmic amplitude axis", bars, false, true, 1e-7)}, 1, 1100, 600});
}

// fem_artefacts: FE artefacts vs DOFs, one series per element order and mesh symmetry (direct evaluation).
void write_fe_plot(StudyOutput& out, const ProvenanceRun& run) {
  const auto& fe = run.fe;
  const auto row_of = row_finder(run);
  const std::string dx_label = run.options.cases[2].label;
  // Key at the bottom left: the series span the whole height on the right.
  PlotPanel ideal{"ideal mount (exact: all zero)", "degrees of freedom", "c_n or pp [deg]", {}, true, true,
                  {"set key bottom left box opaque samplen 2 spacing 1.1"}};
  PlotPanel dx{plot_literal(dx_label) + ": |c_n - c_n^{exact}| (mu_r = 1 solutions)", "degrees of freedom",
               "artefact [deg]", {}, true, true, {}};
  std::set<std::pair<int, int>> groups;  // (order, symmetry order)
  for (const auto& e : fe) groups.insert({e.facts.order, e.facts.symmetry_order});
  for (const auto& [order, sym] : groups) {
    std::vector<const FeSolution*> es;
    for (const auto& e : fe)
      if (e.facts.order == order && e.facts.symmetry_order == sym) es.push_back(&e);
    std::sort(es.begin(), es.end(), [](auto* x, auto* y) { return x->facts.dofs < y->facts.dofs; });
    const std::string P = "P" + std::to_string(order) + (sym > 2 ? " D" + std::to_string(sym) : "") + " ";
    PlotSeries c4{P + "c_4", {}, {}, "linespoints", "pt 7"}, c8{P + "c_8", {}, {}, "linespoints", "pt 5"},
        pp{P + "pp", {}, {}, "linespoints", "dt 2"};
    PlotSeries d1{P + "c_1", {}, {}, "linespoints", "pt 7"}, d3{P + "c_3", {}, {}, "linespoints", "pt 5"};
    for (const auto* e : es) {
      const auto& s = row_of("fem", e->label, "ideal")->sampled;
      c4.x.push_back(double(e->facts.dofs));
      c4.y.push_back(on_log_axis(s.c_deg[4], ideal));
      c8.x.push_back(double(e->facts.dofs));
      c8.y.push_back(on_log_axis(s.c_deg[8], ideal));
      pp.x.push_back(double(e->facts.dofs));
      pp.y.push_back(on_log_axis(s.pp_deg, ideal));
      if (e->facts.mu_r != 1.0) continue;
      const auto* r = row_of("fem", e->label, dx_label);
      d1.x.push_back(double(e->facts.dofs));
      d1.y.push_back(on_log_axis(std::abs(r->sampled.c_deg[1] - r->exact.c_deg[1]), dx));
      d3.x.push_back(double(e->facts.dofs));
      d3.y.push_back(on_log_axis(std::abs(r->sampled.c_deg[3] - r->exact.c_deg[3]), dx));
    }
    ideal.series.insert(ideal.series.end(), {c4, c8, pp});
    dx.series.insert(dx.series.end(), {d1, d3});
  }
  write_plot(out.dir(), "fem_artefacts",
             {"FE artefacts vs degrees of freedom (FE solution evaluated directly)", {ideal, dx}, 2, 1200, 550});
}

// summary.md, first part: what was sampled, and the grid-sampling table of the ideal mount.
void summary_grid_section(std::ostringstream& md, const ProvenanceRun& run) {
  const ProvenanceOptions& o = run.options;
  const ProbeSetup& setup = o.setup;
  const auto& rows = run.rows;
  const std::size_t n_grid_rows = run.n_grid_rows;
  const auto& fe = run.fe;
  const auto& spacings = o.spacings_mm;
  const auto& modes = o.modes;
  const double off = o.offset_mm;
  md << "# harmonic_provenance: physical harmonics vs sampling artefacts\n\n"
     << "Array `" << setup.array.name << "`, r0 = " << fmt(setup.r0_mm, 3) << " mm, " << setup.steps
     << " samples per turn; cases: ideal mount, sx and dx of " << fmt(off, 3) << " mm. "
     << "The exact field was sampled on Cartesian plane grids (nodes on multiples of h, z = z_s) with h = "
     << o.spacings_text << " mm and interpolated with " << o.interps_text << ". "
     << (fe.empty() ? std::string("No FE solutions were included (provenance.fem_variants and provenance.fem_dirs empty).")
                    : std::to_string(fe.size()) + " FE solutions (next section).")
     << " Table: `provenance.csv`.\n\n";
  md << "## Ideal mount: grid sampling, c4 and peak-to-peak by spacing and mode (deg; exact field: all zero)\n\n";
  std::vector<std::vector<std::string>> grid_table;
  for (std::size_t i = 0; i < n_grid_rows; ++i)
    if (const auto& r = rows[i]; r.case_label == "ideal")
      grid_table.push_back({r.source, r.variant, fmt(r.sampled.c_deg[1], 5), fmt(r.sampled.c_deg[2], 5), fmt(r.sampled.c_deg[3], 5),
                   fmt(r.sampled.c_deg[4], 5), fmt(r.sampled.c_deg[8], 5), fmt(r.sampled.pp_deg, 5)});
  md << md_table({"source", "variant", "c1", "c2", "c3", "c4", "c8", "pp"}, grid_table) << "\n";
  // Observed convergence order of the ideal-mount c4 artefact between the two finest spacings.
  if (spacings.size() >= 2) {
    md << "Observed order of the ideal-mount c4 artefact between h = " << fmt_sig(spacings[spacings.size() - 2], 6)
       << " and " << fmt_sig(spacings.back(), 6) << " mm: ";
    for (const Interp m : modes) {
      double a = 0, b = 0;
      for (std::size_t i = 0; i < n_grid_rows; ++i) {
        const auto& r = rows[i];
        if (r.case_label != "ideal" || r.interp != interp_name(m)) continue;
        if (r.h_mm == spacings[spacings.size() - 2]) a = r.sampled.c_deg[4];
        if (r.h_mm == spacings.back()) b = r.sampled.c_deg[4];
      }
      md << interp_name(m) << " " << fmt(std::log(a / b) / std::log(spacings[spacings.size() - 2] / spacings.back()), 2) << "; ";
    }
    md << "\n\n";
  }
}

// summary.md: the FE solutions' artefacts (ideal mount, then under the offsets).
void summary_fe_section(std::ostringstream& md, const ProvenanceRun& run) {
  const auto& cases = run.options.cases;
  const auto& fe = run.fe;
  const bool via_grid = run.options.via_grid();
  const std::string& grid_interp = run.options.grid_interp;
  const auto row_of = row_finder(run);
  md << "## FE artefacts against mesh size and element order\n\n"
     << "Each FE solution is evaluated directly at the probe points (`fem`)"
     << (via_grid ? " and through its plane grid with " + grid_interp + " interpolation (`via plane grid`, grid spacing in the table)"
                  : std::string(""))
     << ". Variants of `provenance.fem_variants` were solved here with magnet.mu_r = 1, so the exact field is "
        "their reference and every ideal-mount harmonic they give is numerical. ";
  bool other_mu = false;
  for (const auto& e : fe) other_mu = other_mu || e.facts.mu_r != 1.0;
  if (other_mu)
    md << "Solutions with mu_r != 1 (column mu_r): their ideal-mount harmonics are numerical too (an axisymmetric, "
          "linear, diametrically magnetized magnet has a pure cos(phi) field at any mu_r), but their differences from "
          "the exact field under sx and dx include the physical effect of mu_r and are not artefacts alone. ";
  md << "h: target tet edge length (mm) in the refinement zone / the core cylinder about the sensing plane "
        "(none: no core); solve: mesh + assemble + CG + post-processing (s). Order column: `P2` a mesh mirrored "
        "about x = 0 and y = 0 (mesh.symmetry_order 2: a D2-symmetric field, ideal-mount artefacts at c4, c8, ...), "
        "`P2 D16` a wedge mesh with the magnet's D16 symmetry (artefacts only at c16 and above), `whole` one "
        "unsymmetric mesh of the whole domain (artefacts at any harmonic).\n\n";
  std::vector<std::vector<std::string>> fe_table, offset_table;
  for (const auto& e : fe) {
    const auto& f = e.facts;
    const std::string h = fmt_auto(f.h_zone_mm, 3) + " / " + (f.h_core_mm > 0 ? fmt_auto(f.h_core_mm, 3) : std::string("none"));
    for (const bool grid : {false, true}) {
      if (grid && !via_grid) continue;
      const std::string source = grid ? "fem_grid" : "fem", variant = grid ? e.label + " via plane grid" : e.label;
      const auto& s = row_of(source, variant, "ideal")->sampled;
      const std::string label = grid ? "… via plane grid (" + grid_interp + ", h = " + fmt_auto(f.plane_step_mm, 3) + " mm)" : e.label;
      if (grid)
        fe_table.push_back({label, "", "", "", "", "", "", "", fmt_deg(s.c_deg[1]), fmt_deg(s.c_deg[2]), fmt_deg(s.c_deg[3]), fmt_deg(s.c_deg[4]),
                      fmt_deg(s.c_deg[8]), fmt_deg(s.pp_deg)});
      else
        fe_table.push_back({label, e.origin, fmt_auto(f.mu_r, 3), "P" + std::to_string(f.order) + (f.symmetry_order > 2 ? " D" + std::to_string(f.symmetry_order) : f.symmetry_order == 1 ? " whole" : ""), std::to_string(f.elements),
                      std::to_string(f.dofs), h, fmt(f.t_total_s, 2), fmt_deg(s.c_deg[1]), fmt_deg(s.c_deg[2]), fmt_deg(s.c_deg[3]),
                      fmt_deg(s.c_deg[4]), fmt_deg(s.c_deg[8]), fmt_deg(s.pp_deg)});
      std::vector<std::string> o{label};
      for (std::size_t c = 1; c < cases.size(); ++c) {
        const auto* r = row_of(source, variant, cases[c].label);
        for (int n = 1; n <= 4; ++n) o.push_back(fmt_deg(std::abs(r->sampled.c_deg[n] - r->exact.c_deg[n])));
        o.push_back(fmt_deg(std::abs(r->sampled.pp_deg - r->exact.pp_deg)));
      }
      offset_table.push_back(o);
    }
  }
  md << "### Ideal mount (deg; exact field: all zero)\n\n"
     << md_table({"FE solution", "solved", "mu_r", "order", "tets", "DOFs", "h zone / core", "solve s", "c1", "c2", "c3", "c4",
                  "c8", "pp"},
                 fe_table)
     << "\n";
  std::vector<const FeSolution*> by_dofs;
  for (const auto& e : fe) by_dofs.push_back(&e);
  std::stable_sort(by_dofs.begin(), by_dofs.end(), [](auto* x, auto* y) { return x->facts.dofs < y->facts.dofs; });
  md << "Ideal-mount c4 by DOFs (evaluated directly): ";
  for (std::size_t i = 0; i < by_dofs.size(); ++i)
    md << (i ? " → " : "") << fmt_deg(row_of("fem", by_dofs[i]->label, "ideal")->sampled.c_deg[4]) << " (" << by_dofs[i]->label
       << ", P" << by_dofs[i]->facts.order << ", " << by_dofs[i]->facts.dofs << " DOFs)";
  md << " deg.\n\n### Under the offsets: |c_n(FE) - c_n(exact)| and |pp(FE) - pp(exact)| (deg)\n\nExact field: ";
  for (std::size_t c = 1; c < cases.size(); ++c) {
    const auto& e = row_of("fem", fe.front().label, cases[c].label)->exact;
    md << (c > 1 ? "; " : "") << cases[c].label << ": c1 " << fmt_deg(e.c_deg[1]) << ", c2 " << fmt_deg(e.c_deg[2]) << ", c3 "
       << fmt_deg(e.c_deg[3]) << ", c4 " << fmt_deg(e.c_deg[4]) << ", pp " << fmt_deg(e.pp_deg);
  }
  md << " deg.\n\n";
  std::vector<std::string> offset_header{"FE solution"};
  for (std::size_t c = 1; c < cases.size(); ++c)
    for (const std::string n : {"c1", "c2", "c3", "c4", "pp"}) offset_header.push_back(cases[c].label + " " + n);
  md << md_table(offset_header, offset_table) << "\n" << md_image("FE artefacts vs DOFs", "fem_artefacts.png") << "\n";
}

// summary.md: physical or artefact, per harmonic and case; the plots.
void summary_verdicts(std::ostringstream& md, const ProvenanceRun& run) {
  const auto& rows = run.rows;
  const std::size_t n_grid_rows = run.n_grid_rows;
  const auto& fe = run.fe;
  const double floor_deg = run.options.floor_deg;
  md << "## Verdict per harmonic and case\n\n"
     << "Physical = the exact field gives c_n >= " << fmt_sig(floor_deg, 6)
     << " deg. Artefact = |c_n(sampled) - c_n(exact)|, largest (where) and smallest (where) over the grid variants"
     << (fe.empty() ? "" : " and, separately, over the FE solutions (directly and via plane grid)") << ".\n\n";
  const std::vector<ProvenanceRow> grid_rows(rows.begin(), rows.begin() + n_grid_rows), fe_rows(rows.begin() + n_grid_rows, rows.end());
  const auto grid_verdicts = harmonic_verdicts(grid_rows, floor_deg);
  const auto fe_verdicts = fe.empty() ? std::vector<HarmonicVerdict>{} : harmonic_verdicts(fe_rows, floor_deg);
  std::vector<std::vector<std::string>> verdict_rows;
  const auto cell = [](double a, const std::string& where) { return fmt(a, 5) + " (" + where + ")"; };
  for (std::size_t i = 0; i < grid_verdicts.size(); ++i) {
    const auto& h = grid_verdicts[i];
    std::vector<std::string> line{h.case_label, "c" + std::to_string(h.n), fmt(h.exact_deg, 5),
                                  h.physical ? "physical" : "artefact only", cell(h.worst_artifact_deg, h.worst_variant),
                                  cell(h.best_artifact_deg, h.best_variant)};
    if (!fe_verdicts.empty()) {
      if (fe_verdicts[i].case_label != h.case_label || fe_verdicts[i].n != h.n) throw ComputeError("harmonic_provenance: verdict rows out of step");
      line.push_back(cell(fe_verdicts[i].worst_artifact_deg, fe_verdicts[i].worst_variant));
      line.push_back(cell(fe_verdicts[i].best_artifact_deg, fe_verdicts[i].best_variant));
    }
    verdict_rows.push_back(line);
  }
  std::vector<std::string> verdict_header{"case", "harmonic", "exact", "verdict", "grid: worst artefact", "grid: best artefact"};
  if (!fe_verdicts.empty()) verdict_header.insert(verdict_header.end(), {"FE: worst artefact", "FE: best artefact"});
  md << md_table(verdict_header, verdict_rows) << "\n## Plots\n\n"
     << md_image("artefacts vs grid spacing", "artefacts_vs_h.png") << "\n"
     << md_image("ideal-mount harmonics", "ideal_harmonics.png") << "\n";
}

}  // namespace

void write_provenance_report(StudyOutput& out, const ProvenanceRun& run) {
  // 1. Table.
  write_provenance_table(out, run);
  // 2. Plots.
  write_grid_plots(out, run);
  if (!run.fe.empty()) write_fe_plot(out, run);
  // 3. Summary (all numbers from the rows above).
  std::ostringstream md;
  summary_grid_section(md, run);
  if (!run.fe.empty()) summary_fe_section(md, run);
  summary_verdicts(md, run);
  out.write_text("summary.md", md.str());
}


}  // namespace magenc
