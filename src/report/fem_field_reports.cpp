#include "report/fem_field_reports.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "report/setup_text.hpp"
#include "io/plot.hpp"
#include "report/comparison_run.hpp"
#include "report/study_plots.hpp"

namespace magenc {

namespace {

// Whether the solve had a magnet permeability the exact field lacks (mu_r recorded and != 1).
bool permeable(double mu_r) { return std::isfinite(mu_r) && mu_r != 1.0; }

// summary.md: the acceptance rule and every cell's verdict at the reference offset.
void real_field_acceptance_section(std::ostringstream& md, const RealFieldResult& result) {
  const auto& offsets = result.options.offsets;
  const double ref_mm = result.options.reference_mm;
  const AcceptanceResult& acc = result.acceptance;
  md << "## Acceptance at " << fmt(ref_mm, 2) << " mm: FEM vs exact\n\n"
     << "Rule (docs/studies/real_field.md): for arrays ";
  for (std::size_t i = 0; i < acc.arrays.size(); ++i) md << (i ? ", " : "") << "`" << acc.arrays[i] << "`";
  md << ", each of ";
  for (std::size_t i = 0; i < acc.coefs.size(); ++i) md << (i ? ", " : "") << acc.coefs[i];
  md << " through every FEM source agrees with the exact field within max(" << fmt(100 * acc.rule.rel, 0)
     << " % of |exact|, " << fmt_sig(acc.rule.abs_deg, 6) << " deg). Values in deg; diff = FEM - exact.\n\n";
  std::vector<std::string> failures;
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& c : acc.cells) {
      const std::string sym = offset_symbol(offsets[c.offset]), coef = c.coef.substr(0, c.coef.find('_'));
      if (c.judged && !c.pass) failures.push_back(sym + " " + c.array + " " + c.source + " " + coef);
      t.push_back({sym + " = " + fmt(ref_mm, 2) + " mm", "`" + c.array + "`", c.source, coef, fmt(c.value_deg, 5),
                   fmt(c.exact_deg, 5), fmt(c.value_deg - c.exact_deg, 5), fmt(c.tolerance_deg, 5),
                   !c.judged ? "(not judged)" : c.pass ? "pass" : "**FAIL**"});
    }
    md << md_table({"case", "array", "source", "coef", "FEM", "exact", "diff", "tolerance", "verdict"}, t) << "\n";
  }
  const int n_pass = acc.passed(), n_cells = acc.judged();
  md << "**Acceptance: " << n_pass << " of " << n_cells << " cells pass"
     << (n_pass == n_cells ? " - all pass.**\n\n" : ".**");
  if (n_pass != n_cells) {
    md << " Failing cells: ";
    for (std::size_t i = 0; i < failures.size(); ++i) md << (i ? "; " : "") << failures[i];
    md << ".\n\n";
  }
}

// eps.png and harmonics.png on the first FEM source; coefficients (first FEM source and exact) and
// FEM - exact (every source) per offset. Returns the per-offset PNG names.
std::vector<std::string> write_real_field_plots(StudyOutput& out, const RealFieldResult& result) {
  const ComparisonInputs& in = result.inputs;
  const ComparisonRun& cr = result.run;
  const auto& runs = cr.arrays;
  const auto& offsets = result.options.offsets;
  const double ref_mm = result.options.reference_mm;
  const AcceptanceResult& acc = result.acceptance;
  const std::string primary = in.sources.front().label;
  const std::string what = "FEM field via " + primary + ", r_0 = " + fmt(in.setups.front().r0_mm, 2) + " mm";
  const int h = 60 + 330 * static_cast<int>(runs.size());
  PlotSpec eps_fig{"Angle error, ideal mount and reference offsets (" + what + ")", {}, 1, 1100, h};
  PlotSpec bar_fig{"Error harmonics, ideal mount and reference offsets (" + what + ", log axis)", {}, 1, 1100, h};
  for (const auto& r : runs) {
    const SourceRun& f = r.fem.front();
    std::vector<EpsCase> ec{{"ideal mount", &*f.ideal}};
    std::vector<SpectrumCase> bc{{"ideal mount", f.ideal->spectrum}};
    for (std::size_t k = 0; k < offsets.size(); ++k) {
      const std::string label = offset_symbol(offsets[k]) + " = " + fmt(ref_mm, 2) + " mm";
      ec.push_back({label, &f.points[k]});
      bc.push_back({label, f.points[k].spectrum});
    }
    eps_fig.panels.push_back(eps_panel("array " + plot_literal(r.setup.array.name), ec));
    bar_fig.panels.push_back(harmonics_panel("array " + plot_literal(r.setup.array.name), bc, true, true));
  }
  write_plot(out.dir(), "eps", eps_fig);
  write_plot(out.dir(), "harmonics", bar_fig);
  std::vector<std::string> pngs;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    const std::string sym = offset_symbol(offsets[k]);
    const SweepPlotText text{sym, sym + " [mm]",
                             offset_description(offsets[k]) + " (" + what + "; exact field beside it)",
                             "FEM - exact field, " + offset_description(offsets[k]) + " (r_0 = " +
                                 fmt(in.setups.front().r0_mm, 2) + " mm)"};
    for (const auto& p : write_comparison_plots(out.dir(), cr, k, text, acc.coefs)) pngs.push_back(p);
  }
  return pngs;
}

// summary.md: the largest error and harmonics over the dz sweep with the base mount.
void airgap_dz_alone_section(std::ostringstream& md, const AirgapResult& result) {
  const ComparisonInputs& in = result.inputs;
  const auto& runs = result.run.arrays;
  const Mount& base = in.base;
  md << "## dz alone (" << (base.sx_mm == 0 && base.sy_mm == 0 && base.dx_mm == 0 && base.dy_mm == 0
                                ? std::string("ideal mount")
                                : "base mount of [mount]")
     << ")\n\nLargest peak-to-peak error and largest c1..c4 over the dz sweep (deg):\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& r : runs)
      for (const SourceRun* sr : r.all()) {
        const SweepResult& s = sr->sweeps.front();
        std::vector<std::string> row{"`" + r.setup.array.name + "`", sr->label};
        for (const char* c : {"pp_deg", "c1_deg", "c2_deg", "c3_deg", "c4_deg"}) {
          double m = 0;
          for (double v : s.column(c)) m = std::max(m, std::abs(v));
          row.push_back(fmt_deg(m));
        }
        t.push_back(row);
      }
    md << md_table({"array", "source", "max pp", "max c1", "max c2", "max c3", "max c4"}, t) << "\n";
    double exact_worst = 0;
    for (const auto& r : runs)
      for (double v : r.exact.sweeps.front().column("pp_deg")) exact_worst = std::max(exact_worst, v);
    md << (exact_worst < 1e-9 ? "On the exact field dz alone gives no error at any dz (peak-to-peak < 1e-9 deg), as "
                                "docs/physics.md predicts; the FEM rows show the FE field's ideal-mount artefacts.\n\n"
                              : "The exact field shows error with dz alone (peak-to-peak up to " +
                                    fmt_auto(exact_worst, 4) + " deg): the base mount is not ideal.\n\n");
  }
}

// summary.md: how dz moves c1 and c3 with the residual eccentricities (slopes and sweep ends).
void airgap_harmonic_slopes_section(std::ostringstream& md, const AirgapResult& result) {
  const auto& runs = result.run.arrays;
  const auto& fits = result.run.fits;
  const auto& dz = result.dz_mm;
  const auto& cases = result.cases;
  md << "## How dz moves the 1st and 3rd harmonics\n\n"
     << "Slopes at dz = 0 (p1 of the cubic fits in `fits.csv`, deg/mm) and the values at the sweep ends (deg); "
        "FEM rows with the exact field's slope beside them.\n\n";
  {
    const auto slope = [&](const SweepResult& s, const char* coef) {
      const FitRow* f = find_fit(fits, s, coef);
      return f ? fmt_deg(f->p[2]) : std::string("-");
    };
    std::vector<std::vector<std::string>> t;
    for (std::size_t k = 1; k < cases.size(); ++k)
      for (const auto& r : runs) {
        const SweepResult& ex = r.exact.sweeps[k];
        for (const auto& f : r.fem) {
          const SweepResult& s = f.sweeps[k];
          const auto c1 = s.column("c1_deg"), c3 = s.column("c3_deg");
          t.push_back({cases[k].residual, "`" + r.setup.array.name + "`", f.label, fmt_deg(c1.front()),
                       fmt_deg(c1.back()), slope(s, "c1_deg"), slope(ex, "c1_deg"), fmt_deg(c3.front()),
                       fmt_deg(c3.back()), slope(s, "c3_deg"), slope(ex, "c3_deg")});
        }
      }
    const std::string lo = fmt(dz.front(), 2), hi = fmt(dz.back(), 2);
    md << md_table({"residual [mm]", "array", "source", "c1 at dz=" + lo, "c1 at dz=" + hi, "dc1/ddz FEM",
                    "dc1/ddz exact", "c3 at dz=" + lo, "c3 at dz=" + hi, "dc3/ddz FEM", "dc3/ddz exact"},
                   t)
       << "\n(fits.csv has the full cubics; a slope needs c_n well above the FEM artefacts of the 'dz alone' table to "
          "mean anything)\n\n";
  }
}

}  // namespace

void write_real_field_report(StudyOutput& out, const RealFieldResult& result, const StudySetup& setup) {
  const ComparisonInputs& in = result.inputs;
  const ComparisonRun& cr = result.run;
  const auto& runs = cr.arrays;
  const auto& offsets = result.options.offsets;
  const auto& values = result.options.values_mm;
  const AcceptanceResult& acc = result.acceptance;

  // 1. Tables.
  write_comparison_tables(out, cr);

  // 2. Plots.
  const std::string primary = in.sources.front().label;
  const std::vector<std::string> pngs = write_real_field_plots(out, result);

  // 3. Summary (every number from the runs above).
  std::ostringstream md;
  md << "# real_field: mounting errors on the FEM field of the magnet, beside the exact field\n\n"
     << fe_solution_text(in.dir, in.solve_description, in.sources, result.interp)
     << ". Exact field of the same magnet (" << magnet_text(setup) << ", plane " << fmt(setup.plane_height_mm, 2) << " mm above the top face) beside every case. r0 = "
     << fmt(in.setups.front().r0_mm, 3) << " mm, " << in.setups.front().steps << " samples per turn. Each of ";
  for (std::size_t i = 0; i < offsets.size(); ++i) md << (i ? ", " : "") << offset_symbol(offsets[i]);
  md << " alone swept over " << fmt(values.front(), 2) << ".." << fmt(values.back(), 2) << " mm (" << values.size()
     << " values) with cubic fits. Tables: `spectra.csv` (columns `sweep`, `source`), `comparison.csv` "
        "(each FEM coefficient beside the exact one, diff = FEM - exact), `fits.csv`.\n\n";
  if (permeable(result.solve_mu_r))
    md << "Note: the solve used magnet mu_r = " << fmt(result.solve_mu_r, 3)
       << "; the exact field has no permeability (mu_r = 1), so part of each difference below is that physics, "
          "not discretization error (solve with --set magnet.mu_r=1 to separate them).\n\n";

  md << "## Ideal mount (exact field: no error; every FEM harmonic is an artefact)\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& r : runs)
      for (const auto& f : r.fem) {
        const Spectrum& s = f.ideal->spectrum;
        t.push_back({"`" + r.setup.array.name + "`", f.label, fmt_deg(s.c_deg[1]), fmt_deg(s.c_deg[2]),
                     fmt_deg(s.c_deg[3]), fmt_deg(s.c_deg[4]), fmt_deg(s.pp_deg),
                     fmt_deg(r.exact.ideal->spectrum.pp_deg)});
      }
    md << md_table({"array", "source", "c1", "c2", "c3", "c4", "pp", "pp exact"}, t) << "\n(deg)\n\n";
  }

  real_field_acceptance_section(md, result);

  md << "## Largest |FEM - exact| over each sweep (deg)\n\n" << max_difference_table(cr, "offset", acc.coefs) << "\n";

  md << "## Plots\n\n"
     << md_image("eps(theta), ideal mount and reference offsets, per array (" + primary + ")", "eps.png") << "\n"
     << md_image("harmonic amplitudes, ideal mount and reference offsets (" + primary + ")", "harmonics.png") << "\n";
  for (const auto& p : pngs) md << md_image(p.substr(0, p.find('.')), p) << "\n";
  out.write_text("summary.md", md.str());
}

void write_airgap_report(StudyOutput& out, const AirgapResult& result) {
  const ComparisonInputs& in = result.inputs;
  const ComparisonRun& cr = result.run;
  const auto& runs = cr.arrays;
  const auto& dz = result.dz_mm;
  const auto& cases = result.cases;

  // 1. Tables.
  write_comparison_tables(out, cr);

  // 2. Plots.
  const std::string primary = in.sources.front().label;
  const std::string what = "FEM field via " + primary + ", r_0 = " + fmt(in.setups.front().r0_mm, 2) + " mm";
  PlotSpec eps_fig{"Angle error vs air gap with " + cases.back().residual + " mm (" + what + ")", {}, 1, 1100,
                   60 + 330 * static_cast<int>(runs.size())};
  for (std::size_t a = 0; a < runs.size(); ++a) {
    std::vector<EpsCase> ec;
    for (int j = 0; j < 3; ++j) ec.push_back({"dz = " + fmt(dz[result.eps_index[j]], 2) + " mm", &result.eps[a][j]});
    eps_fig.panels.push_back(eps_panel("array " + plot_literal(runs[a].setup.array.name), ec));
  }
  write_plot(out.dir(), "eps", eps_fig);
  std::vector<std::string> pngs;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string title = "air gap dz, " + (k == 0 ? std::string("no residual offset") : cases[k].residual + " mm");
    const SweepPlotText text{cases[k].tag, "dz [mm]", title + " (" + what + "; exact field beside it)",
                             "FEM - exact field, " + title};
    for (const auto& p : write_comparison_plots(out.dir(), cr, k, text, result.diff_coefs)) pngs.push_back(p);
  }

  // 3. Summary (all numbers from the runs above).
  std::ostringstream md;
  md << "# airgap: the air-gap offset dz on the FEM field, beside the exact field\n\n"
     << fe_solution_text(in.dir, in.solve_description, in.sources, result.interp)
     << "; the exact field of the same magnet beside every case. r0 = " << fmt(in.setups.front().r0_mm, 3) << " mm, "
     << in.setups.front().steps << " samples per turn; dz swept over " << fmt(dz.front(), 2) << ".."
     << fmt(dz.back(), 2)
     << " mm (" << dz.size() << " values, + = farther from the magnet) alone and with residual eccentricities sx = "
     << fmt(result.residual_sx_mm, 3) << " mm, dx = " << fmt(result.residual_dx_mm, 3)
     << " mm (each alone and both). Tables: `spectra.csv` (columns "
     << "`sweep`, `source`), `comparison.csv` (FEM beside exact, diff = FEM - exact), `fits.csv` (cubics in dz_mm).\n\n";
  if (permeable(result.solve_mu_r))
    md << "Note: the solve used magnet mu_r = " << fmt(result.solve_mu_r, 3)
       << "; the exact field has mu_r = 1, so part of each FEM - exact difference is that physics.\n\n";

  airgap_dz_alone_section(md, result);

  airgap_harmonic_slopes_section(md, result);

  md << "## Largest |FEM - exact| over each dz sweep (deg)\n\n"
     << max_difference_table(cr, "case", result.diff_coefs) << "\n";

  md << "## Plots\n\n" << md_image("eps(theta) at three air gaps, per array", "eps.png") << "\n";
  for (const auto& p : pngs) md << md_image(p.substr(0, p.find('.')), p) << "\n";
  out.write_text("summary.md", md.str());
}

}  // namespace magenc
