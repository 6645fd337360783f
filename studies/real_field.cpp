// Study real_field: the real-field chapter of the study on the FEM field of the
// configured (default) magnet. The FE solution comes from a solve_field output
// directory (fem_field.dir, default output/field: run solve_field first; the
// study fails with a one-line message otherwise) and is used through each of
// fem_field.sources: "grid" (grid:DIR/plane.vti, cubic interpolation by
// default) and "fem" (fem:DIR, the FE solution evaluated directly). Every case
// also runs on the exact field of the same magnet, so each FEM number stands
// beside the exact one:
//   ideal mount; sx, sy, dx, dy at sweep.reference_mm; each swept 0..max_mm
//   with cubic fits; arrays two, diff4, ring:8.
// Writes
//   spectra.csv     spectra table, one row per case and source (extra columns
//                   `sweep` = case, `source` = grid | fem | exact)
//   comparison.csv  every FEM coefficient beside the exact one and the difference
//                   (array,sweep,swept,x_mm,source,coef,value_deg,exact_deg,diff_deg)
//   fits.csv        cubic fits per array, source and offset (extra columns field, array, ...)
//   eps.png, harmonics.png, coefficients_<offset>.png, differences_<offset>.png, summary.md
// summary.md carries the acceptance check at the reference offset: for
// `two` and `diff4`, c1..c4 of every FEM source within max(2 % of exact, 0.002 deg).
//   real_field [--config studies/real_field.toml] [--set fem_field.dir=/tmp/field] [--out DIR]
#include <cmath>
#include <sstream>

#include "report/comparison_run.hpp"
#include "core/errors.hpp"
#include "fem_field_scheme.hpp"
#include "io/plot.hpp"
#include "report/study_output.hpp"
#include "report/study_plots.hpp"
#include "analysis/sweep.hpp"

using namespace magenc;

namespace {

const char* kStudy = "real_field";

std::vector<KeySpec> study_keys() {
  std::vector<KeySpec> k = {
      string_key("study.arrays", "two,diff4,ring:8", {}, "comma-separated probe arrays (two, diff4, ring:N)"),
      int_key("sweep.points", 26, 4, 100000, "values per offset sweep (>= 4 for the cubic fit)"),
      real_key("sweep.max_mm", 0.5, 0, 100, "mm", "each offset is swept over 0..max_mm", true),
      real_key("sweep.reference_mm", 0.1, 0, 100, "mm",
               "offset of the eps(theta) plot, harmonic bars and the acceptance table", true),
      string_key("sweep.offsets", "sx_mm,sy_mm,dx_mm,dy_mm", {},
                 "comma-separated offsets swept one at a time from 0 (sx_mm, sy_mm, dx_mm, dy_mm)"),
      string_key("sweep.coefs", "a0_deg,a1_deg,b1_deg,a2_deg,b2_deg,c1_deg,c2_deg,c3_deg,c4_deg", {},
                 "comma-separated spectra columns fitted with a cubic"),
      string_key("acceptance.arrays", "two,diff4", {}, "arrays the acceptance check covers"),
      string_key("acceptance.coefs", "c1_deg,c2_deg,c3_deg,c4_deg", {},
                 "coefficients the acceptance check covers (rule fixed: max(2 % of exact, 0.002 deg))"),
  };
  for (auto& f : fem_field_keys("plane.vti")) k.push_back(f);
  return k;
}

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs: the FEM sources (fails first if the solved directory is missing), the exact field, the arrays.
  register_fem_field_scheme();
  const ComparisonInputs in = comparison_inputs_from_config(cfg);
  const auto offsets = split_list(cfg.str("sweep.offsets"), "sweep.offsets");
  const auto coefs = split_list(cfg.str("sweep.coefs"), "sweep.coefs");
  const auto acc_arrays = split_list(cfg.str("acceptance.arrays"), "acceptance.arrays");
  const auto acc_coefs = split_list(cfg.str("acceptance.coefs"), "acceptance.coefs");
  check_coef_names(coefs, "sweep.coefs");
  check_coef_names(acc_coefs, "acceptance.coefs");
  for (const auto& o : offsets) {
    with_offset(in.base, o, 0.0);  // validates the names
    if (o == "dz_mm") throw InputError("sweep.offsets: dz_mm is the airgap study's (plane.vti has no dz)");
  }
  const double ref_mm = cfg.real("sweep.reference_mm");
  const auto values = linspace(0.0, cfg.real("sweep.max_mm"), static_cast<int>(cfg.integer("sweep.points")));
  const AcceptanceRule rule;  // the rule, deliberately not configurable

  // 2. Per array, on every FEM source and on the exact field: the ideal mount, each
  //    offset at the reference value (points) and swept (sweeps, with fits).
  ComparisonPlan plan{kStudy, {}, coefs, in.base, {}};
  for (const auto& o : offsets) {
    plan.sweeps.push_back({offset_symbol(o), o, values, in.base});
    plan.points.push_back(with_offset(in.base, o, ref_mm));
  }
  const ComparisonRun cr = run_comparison(in.sources, *in.exact, in.setups, plan);
  const auto& runs = cr.arrays;

  // 3. Tables.
  write_comparison_tables(out, cr);

  // 4. Plots: eps(theta) and harmonic bars on the first FEM source; coefficients
  //    (first FEM source and exact) and FEM - exact (every source) per offset.
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
    for (const auto& p : write_comparison_plots(out.dir(), cr, k, text, acc_coefs)) pngs.push_back(p);
  }

  // 5. Summary (every number from the runs above).
  const auto deg = [](double v) { return fmt_auto(v, 4, kRoundingZeroDeg); };
  const double mu_r = solve_mu_r(in.dir);
  std::ostringstream md;
  md << "# real_field: mounting errors on the FEM field of the magnet, beside the exact field\n\n"
     << fe_solution_text(in.dir, in.sources, cfg.str("fem_field.interp"))
     << ". Exact field of the same magnet (R = " << fmt(cfg.real("magnet.radius_mm"), 2)
     << " mm, L = " << fmt(cfg.real("magnet.height_mm"), 2) << " mm, Br = " << fmt(cfg.real("magnet.br_T"), 2)
     << " T, plane " << fmt(cfg.real("sensor.plane_height_mm"), 2) << " mm above the top face) beside every case. r0 = "
     << fmt(in.setups.front().r0_mm, 3) << " mm, " << in.setups.front().steps << " samples per turn. Each of ";
  for (std::size_t i = 0; i < offsets.size(); ++i) md << (i ? ", " : "") << offset_symbol(offsets[i]);
  md << " alone swept over " << fmt(values.front(), 2) << ".." << fmt(values.back(), 2) << " mm (" << values.size()
     << " values) with cubic fits. Tables: `spectra.csv` (columns `sweep`, `source`), `comparison.csv` "
        "(each FEM coefficient beside the exact one, diff = FEM - exact), `fits.csv`.\n\n";
  if (std::isfinite(mu_r) && mu_r != 1.0)
    md << "Note: the solve used magnet mu_r = " << fmt(mu_r, 3)
       << "; the exact field has no permeability (mu_r = 1), so part of each difference below is that physics, "
          "not discretization error (solve with --set magnet.mu_r=1 to separate them).\n\n";

  md << "## Ideal mount (exact field: no error; every FEM harmonic is an artefact)\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& r : runs)
      for (const auto& f : r.fem) {
        const Spectrum& s = f.ideal->spectrum;
        t.push_back({"`" + r.setup.array.name + "`", f.label, deg(s.c_deg[1]), deg(s.c_deg[2]), deg(s.c_deg[3]),
                     deg(s.c_deg[4]), deg(s.pp_deg), deg(r.exact.ideal->spectrum.pp_deg)});
      }
    md << md_table({"array", "source", "c1", "c2", "c3", "c4", "pp", "pp exact"}, t) << "\n(deg)\n\n";
  }

  md << "## Acceptance at " << fmt(ref_mm, 2) << " mm: FEM vs exact\n\n"
     << "Rule (issue \"FEM-driven probe studies\"): for arrays ";
  for (std::size_t i = 0; i < acc_arrays.size(); ++i) md << (i ? ", " : "") << "`" << acc_arrays[i] << "`";
  md << ", each of ";
  for (std::size_t i = 0; i < acc_coefs.size(); ++i) md << (i ? ", " : "") << acc_coefs[i];
  md << " through every FEM source agrees with the exact field within max(" << fmt(100 * rule.rel, 0)
     << " % of |exact|, " << rule.abs_deg << " deg). Values in deg; diff = FEM - exact.\n\n";
  int n_pass = 0, n_cells = 0;
  std::vector<std::string> failures;
  {
    std::vector<std::vector<std::string>> t;
    for (std::size_t k = 0; k < offsets.size(); ++k)
      for (const auto& r : runs) {
        bool judged = false;
        for (const auto& a : acc_arrays) judged = judged || a == r.setup.array.name;
        for (const auto& f : r.fem)
          for (const auto& coef : acc_coefs) {
            const double v = f.points[k].spectrum.column(coef), e = r.exact.points[k].spectrum.column(coef);
            const double tol = rule.tolerance_deg(e);
            std::string verdict = "(not judged)";
            if (judged) {
              const bool ok = rule.pass(v, e);
              ++n_cells;
              n_pass += ok;
              verdict = ok ? "pass" : "**FAIL**";
              if (!ok)
                failures.push_back(offset_symbol(offsets[k]) + " " + r.setup.array.name + " " + f.label + " " +
                                   coef.substr(0, coef.find('_')));
            }
            t.push_back({offset_symbol(offsets[k]) + " = " + fmt(ref_mm, 2) + " mm", "`" + r.setup.array.name + "`",
                         f.label, coef.substr(0, coef.find('_')), fmt(v, 5), fmt(e, 5), fmt(v - e, 5), fmt(tol, 5),
                         verdict});
          }
      }
    md << md_table({"case", "array", "source", "coef", "FEM", "exact", "diff", "tolerance", "verdict"}, t) << "\n";
  }
  md << "**Acceptance: " << n_pass << " of " << n_cells << " cells pass"
     << (n_pass == n_cells ? " - all pass.**\n\n" : ".**");
  if (n_pass != n_cells) {
    md << " Failing cells: ";
    for (std::size_t i = 0; i < failures.size(); ++i) md << (i ? "; " : "") << failures[i];
    md << ".\n\n";
  }

  md << "## Largest |FEM - exact| over each sweep (deg)\n\n" << max_difference_table(cr, "offset", acc_coefs) << "\n";

  md << "## Plots\n\n"
     << md_image("eps(theta), ideal mount and reference offsets, per array (" + primary + ")", "eps.png") << "\n"
     << md_image("harmonic amplitudes, ideal mount and reference offsets (" + primary + ")", "harmonics.png") << "\n";
  for (const auto& p : pngs) md << md_image(p.substr(0, p.find('.')), p) << "\n";
  out.write_text("summary.md", md.str());
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy,
                   "real_field: angle-error spectra of the FEM field (fem:DIR / grid:DIR/plane.vti) for one-offset "
                   "sweeps and several arrays, beside the exact field, with the FEM-vs-exact acceptance check",
                   study_keys(), argc, argv, run);
}
