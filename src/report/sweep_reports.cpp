#include "report/sweep_reports.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "report/setup_text.hpp"
#include "io/plot.hpp"
#include "probe/spectrum.hpp"
#include "report/study_plots.hpp"

namespace magenc {

namespace {

// "sx, sy, dx, dy": the symbols of the swept offsets.
std::string offset_list(const std::vector<std::string>& offsets) {
  std::string t;
  for (std::size_t i = 0; i < offsets.size(); ++i) t += (i ? ", " : "") + offset_symbol(offsets[i]);
  return t;
}

// eps.png and harmonics.png per array, coefficients_<offset>.png per swept offset; returns the latter's names.
std::vector<std::string> write_exact_field_plots(StudyOutput& out, const ExactFieldResult& r) {
  const auto& o = r.options;
  const auto& arrays = r.arrays;
  const ProbeSetup& first = arrays.front().setup;
  const std::string what = r.field + " field, r_0 = " + fmt(first.r0_mm, 2) + " mm";
  PlotSpec eps_fig{"Angle error at the reference offsets (" + what + ")", {}, 1, 1100,
                   60 + 330 * static_cast<int>(arrays.size())};
  PlotSpec bar_fig{"Error harmonics at the reference offsets (" + what + ", log axis)", {}, 1, 1100,
                   60 + 330 * static_cast<int>(arrays.size())};
  for (const auto& a : arrays) {
    std::vector<EpsCase> ec;
    std::vector<SpectrumCase> bc;
    for (const auto& c : a.refs) {
      ec.push_back({c.label, &c.field});
      bc.push_back({c.label, c.field.spectrum});
    }
    eps_fig.panels.push_back(eps_panel("array " + plot_literal(a.setup.array.name), ec));
    bar_fig.panels.push_back(harmonics_panel("array " + plot_literal(a.setup.array.name), bc, true, true));
  }
  write_plot(out.dir(), "eps", eps_fig);
  write_plot(out.dir(), "harmonics", bar_fig);
  std::vector<std::string> coef_pngs;
  for (std::size_t k = 0; k < arrays.front().sweeps.size(); ++k) {
    const SweepResult& sweep0 = arrays.front().sweeps[k];
    std::vector<SweepCase> sc;
    for (const auto& a : arrays) sc.push_back({plot_literal(a.setup.array.name), &a.sweeps[k]});
    const std::string sym = offset_symbol(sweep0.spec.swept);
    std::string title = offset_description(sweep0.spec.swept);
    if (sweep0.spec.swept == "dz_mm") title += " with dx = " + fmt(r.dz_base.dx_mm, 2) + " mm";
    const std::string name = "coefficients_" + sym;
    write_plot(out.dir(), name, coefficient_figure(title + " (" + what + ")", sym + " [mm]", sc, r.fits, o.coefs));
    coef_pngs.push_back(name + ".png");
  }
  return coef_pngs;
}

// summary.md: the field, the arrays and what was swept.
void exact_field_intro(std::ostringstream& md, const ExactFieldResult& r, const StudySetup& setup) {
  const auto& o = r.options;
  const auto& arrays = r.arrays;
  const ProbeSetup& first = arrays.front().setup;
  const auto& dz_values = r.dz_values_mm;
  md << "# exact_field: mounting errors on the exact field of the magnet\n\n"
     << "Field `" << r.field << "` (magnet " << magnet_text(setup) << "; sensing plane " << fmt(setup.plane_height_mm, 2) << " mm above the top face), r0 = "
     << fmt(first.r0_mm, 3) << " mm, " << first.steps << " samples per turn, arrays ";
  for (std::size_t i = 0; i < arrays.size(); ++i) md << (i ? ", " : "") << "`" << arrays[i].setup.array.name << "`";
  md << " (`sensor.array` is not used; `study.arrays` lists them).\n"
     << "Each of " << offset_list(o.offsets) << " alone swept over " << fmt(o.values_mm.front(), 2) << ".."
     << fmt(o.values_mm.back(), 2) << " mm (" << o.values_mm.size() << " values); dz swept over "
     << fmt(dz_values.front(), 2) << ".." << fmt(dz_values.back(), 2) << " mm (" << dz_values.size()
     << " values) with dx = " << fmt(r.dz_base.dx_mm, 3)
     << " mm. Tables: `spectra.csv` (column `sweep` names the case), `fits.csv`. "
     << "The reference cases were also run on the linear field Bz = k*x for comparison.\n\n";
}

// summary.md: peak-to-peak and the largest harmonic of the ideal mount per array.
void exact_field_ideal_section(std::ostringstream& md, const ExactFieldResult& r) {
  const auto& arrays = r.arrays;
  md << "## Ideal mount\n\n";
  std::vector<std::vector<std::string>> t;
  double worst_pp = 0;
  for (const auto& a : arrays) {
    double cmax = 0;
    for (int n = 1; n <= kHarmonics; ++n) cmax = std::max(cmax, a.ideal.spectrum.c_deg[n]);
    t.push_back({"`" + a.setup.array.name + "`", fmt_auto(a.ideal.spectrum.pp_deg, 2), fmt_auto(cmax, 2)});
    worst_pp = std::max(worst_pp, a.ideal.spectrum.pp_deg);
  }
  md << md_table({"array", "peak-to-peak [deg]", "largest c_n [deg]"}, t) << "\n"
     << (worst_pp < 1e-9 ? "No error with an ideal mount (peak-to-peak below 1e-9 deg on every array), as "
                           "docs/physics.md predicts for a uniformly magnetized cylinder.\n\n"
                         : "The ideal mount shows error (peak-to-peak up to " + fmt_auto(worst_pp, 4) +
                               " deg): with an exact field this is a field or pipeline artefact to investigate.\n\n");
}

// summary.md: the dominant harmonics of every reference case, exact and linear field.
void exact_field_dominant_section(std::ostringstream& md, const ExactFieldResult& r) {
  const auto& arrays = r.arrays;
  const double ref_mm = r.options.reference_mm;
  const double floor_deg = r.floor_deg, rel = r.relative;
  md << "## Dominant harmonics at " << fmt(ref_mm, 2) << " mm (deg)\n\n"
     << "Harmonics n >= 1 with c_n >= max(" << fmt_sig(floor_deg, 6) << " deg, " << fmt_sig(rel, 6)
     << " x largest), largest first (at most 4); a0 is the constant offset. "
     << "`linear` is the same case on the linear field Bz = k*x.\n\n";
  std::vector<std::vector<std::string>> t;
  for (std::size_t c = 0; c < arrays.front().refs.size(); ++c) {
    for (const auto& a : arrays) {
      const ReferenceCase& rc = a.refs[c];
      const Spectrum& f = rc.field.spectrum;
      const Spectrum& l = rc.linear.spectrum;
      t.push_back({rc.label, "`" + a.setup.array.name + "`", fmt_deg(f.a0_deg),
                   harmonics_text(dominant_harmonics(f, floor_deg, rel, 4), f, 4), fmt_deg(f.pp_deg),
                   harmonics_text(dominant_harmonics(l, floor_deg, rel, 4), l, 4), fmt_deg(l.pp_deg)});
    }
  }
  md << md_table({"mounting case", "array", "a0 " + r.field, "dominant harmonics " + r.field, "pp " + r.field,
                  "dominant harmonics linear", "pp linear"},
                 t)
     << "\n";
}

// summary.md: named comparisons from docs/physics.md, in numbers (dynamic eccentricity against the linear model).
void exact_field_linear_section(std::ostringstream& md, const ExactFieldResult& r) {
  const auto& arrays = r.arrays;
  const double floor_deg = r.floor_deg;
  md << "## Against the linear model\n\n";
  for (const auto& a : arrays) {
    for (const auto& rc : a.refs) {
      if (rc.swept != "dx_mm") continue;
      const Spectrum& e = rc.field.spectrum;
      const Spectrum& l = rc.linear.spectrum;
      md << "- `" << a.setup.array.name << "`, " << rc.label << " (dynamic eccentricity): " << r.field
         << " c1 = " << fmt_deg(e.c_deg[1]) << ", c3 = " << fmt_deg(e.c_deg[3]) << ", c4 = " << fmt_deg(e.c_deg[4])
         << " deg";
      if (e.c_deg[1] > floor_deg) md << " (c3/c1 = " << fmt(e.c_deg[3] / e.c_deg[1], 3) << ")";
      md << "; linear c1 = " << fmt_deg(l.c_deg[1]) << ", c3 = " << fmt_deg(l.c_deg[3])
         << ", c4 = " << fmt_deg(l.c_deg[4]) << " deg.\n";
    }
  }
  md << "\ndocs/physics.md expects: with `two`, dynamic eccentricity gives a 3rd harmonic of size similar to the "
        "1st on the real field but (to first order) none on the linear one; with `diff4` the 1st harmonic "
        "cancels and a 4th appears.\n\n";
}

// summary.md: c1 and c3 over the dz sweep with their slopes at 0.
void exact_field_airgap_section(std::ostringstream& md, const ExactFieldResult& r) {
  const auto& arrays = r.arrays;
  const auto& dz_values = r.dz_values_mm;
  md << "## Air gap: dz with dx = " << fmt(r.dz_base.dx_mm, 3) << " mm\n\n";
  std::vector<std::vector<std::string>> t;
  for (const auto& a : arrays) {
    const SweepResult& s = a.sweeps.back();
    const auto c1 = s.column("c1_deg"), c3 = s.column("c3_deg");
    const FitRow* f1 = find_fit(r.fits, s, "c1_deg");
    const FitRow* f3 = find_fit(r.fits, s, "c3_deg");
    t.push_back({"`" + a.setup.array.name + "`", fmt_deg(c1.front()), fmt_deg(c1.back()),
                 f1 ? fmt_deg(f1->p[2]) : "-", fmt_deg(c3.front()), fmt_deg(c3.back()),
                 f3 ? fmt_deg(f3->p[2]) : "-"});
  }
  md << md_table({"array", "c1 at dz = " + fmt(dz_values.front(), 2), "c1 at dz = " + fmt(dz_values.back(), 2),
                  "dc1/ddz at 0 [deg/mm]", "c3 at dz = " + fmt(dz_values.front(), 2),
                  "c3 at dz = " + fmt(dz_values.back(), 2), "dc3/ddz at 0 [deg/mm]"},
                 t)
     << "\n(slopes are p1 of the cubic fits in `fits.csv`; c1 and c3 in deg)\n\n";
}

}  // namespace

void write_linear_model_report(StudyOutput& out, const LinearModelResult& r) {
  const auto& o = r.options;
  const ProbeSetup& setup = r.setup;

  // 1. Tables.
  std::vector<SpectrumRow> rows;
  rows.push_back({"linear", setup.array.name, setup.r0_mm, r.base, r.ideal.spectrum, {{"sweep", "ideal"}}});
  for (const auto& s : r.sweeps) rows.insert(rows.end(), s.rows.begin(), s.rows.end());
  out.write_text("spectra.csv", spectra_csv(rows));
  out.write_text("fits.csv", fits_csv(r.fits));

  // 2. Plots.
  const std::string at = fmt(o.reference_mm, 2) + " mm";
  const std::string what = "linear field B_z = kx, array " + plot_literal(setup.array.name) +
                           ", r_0 = " + fmt(setup.r0_mm, 2) + " mm";
  std::vector<EpsCase> eps_cases;
  std::vector<SpectrumCase> bar_cases;
  for (std::size_t i = 0; i < o.offsets.size(); ++i) {
    eps_cases.push_back({offset_symbol(o.offsets[i]) + " = " + at, &r.refs[i]});
    bar_cases.push_back({offset_symbol(o.offsets[i]) + " = " + at, r.refs[i].spectrum});
  }
  PlotSpec eps_fig{"Angle error, each offset alone at " + at + " (" + what + ")",
                   {eps_panel("", eps_cases)}, 1, 1100, 600};
  write_plot(out.dir(), "eps", eps_fig);
  PlotSpec bars{"Error harmonics, each offset alone at " + at + " (" + what + ")",
                {harmonics_panel("linear amplitude axis", bar_cases),
                 harmonics_panel("logarithmic amplitude axis", bar_cases, true, true)},
                1, 1100, 900};
  write_plot(out.dir(), "harmonics", bars);
  std::vector<SweepCase> sweep_cases;
  for (const auto& s : r.sweeps) sweep_cases.push_back({s.spec.label, &s});
  write_plot(out.dir(), "coefficients",
             coefficient_figure("Spectrum coefficients vs offset, each alone (" + what + ")",
                                "offset [mm]", sweep_cases, r.fits, o.coefs));

  // 3. Summary.
  std::ostringstream md;
  md << "# linear_model: the linear field model Bz = k*x\n\n"
     << "Array `" << setup.array.name << "`, r0 = " << fmt(setup.r0_mm, 3) << " mm, " << setup.steps
     << " samples per turn. Ideal mount, then each of " << offset_list(o.offsets)
     << " alone swept over " << fmt(o.values_mm.front(), 2) << ".." << fmt(o.values_mm.back(), 2) << " mm ("
     << o.values_mm.size() << " values). Tables: `spectra.csv` (column `sweep` names the case), "
     << "`fits.csv` (cubic fits). Configuration used: `config.toml`.\n\n";
  md << "Ideal mount: peak-to-peak error " << fmt(r.ideal.spectrum.pp_deg, 6) << " deg.\n\n";
  md << "## Spectrum at " << at << " of each offset alone (deg)\n\n";
  const std::vector<std::string> cols = {"a0_deg", "a1_deg", "b1_deg", "a2_deg", "b2_deg", "c1_deg",
                                         "c2_deg", "c3_deg", "c4_deg", "pp_deg"};
  std::vector<std::vector<std::string>> spectrum_table;
  for (std::size_t i = 0; i < o.offsets.size(); ++i) {
    std::vector<std::string> row = {offset_symbol(o.offsets[i])};
    for (const auto& c : cols) row.push_back(fmt(r.refs[i].spectrum.column(c), 3));
    spectrum_table.push_back(row);
  }
  std::vector<std::string> header = {"offset"};
  for (const auto& c : cols) header.push_back(c.substr(0, c.size() - 4));
  md << md_table(header, spectrum_table) << "\n";

  md << "## Check against docs/physics.md sanity values\n\n";
  if (!r.physics_md_applies) {
    md << "Not applicable: docs/physics.md quotes r0 = 2.4 mm, array `two`, 0.1 mm offsets, no base offset.\n\n";
  } else {
    std::vector<std::vector<std::string>> check_table;
    for (const auto& c : r.physics_md)
      check_table.push_back({offset_symbol(c.swept) + " = 0.1 mm", c.coef, fmt(c.computed_deg, 4),
                             fmt(c.quoted_deg, 3), c.agrees ? "ok" : "**MISMATCH**"});
    const int bad = r.physics_md_mismatches();
    md << md_table({"case", "coefficient", "computed", "docs/physics.md", "within 0.0015 deg"}, check_table) << "\n"
       << (bad == 0 ? "All listed values agree.\n\n"
                    : std::to_string(bad) + " value(s) disagree with docs/physics.md.\n\n");
  }

  md << "## Cubic fits (coefficient = p3 x^3 + p2 x^2 + p1 x + p0, x in mm)\n\n";
  std::vector<std::vector<std::string>> fit_table;
  for (const auto& f : r.fits)
    fit_table.push_back(
        {offset_symbol(f.swept), f.coef, fmt(f.p[0], 4), fmt(f.p[1], 4), fmt(f.p[2], 4), fmt(f.p[3], 5)});
  md << md_table({"offset", "coef", "p3", "p2", "p1", "p0"}, fit_table) << "\n";
  md << "## Plots\n\n"
     << md_image("eps(theta) for each offset alone at " + at, "eps.png") << "\n"
     << md_image("harmonic amplitudes at " + at, "harmonics.png") << "\n"
     << md_image("coefficients vs offset with cubic fits", "coefficients.png");
  out.write_text("summary.md", md.str());
}

void write_exact_field_report(StudyOutput& out, const ExactFieldResult& r, const StudySetup& setup) {
  // 1. Tables.
  std::vector<SpectrumRow> rows;
  for (const auto& a : r.arrays) {
    rows.push_back({r.field, a.setup.array.name, a.setup.r0_mm, r.base, a.ideal.spectrum, {{"sweep", "ideal"}}});
    for (const auto& s : a.sweeps) rows.insert(rows.end(), s.rows.begin(), s.rows.end());
  }
  out.write_text("spectra.csv", spectra_csv(rows));
  out.write_text("fits.csv", fits_csv(r.fits));

  // 2. Plots: eps(theta) and harmonic bars per array, coefficients per swept offset.
  const std::vector<std::string> coef_pngs = write_exact_field_plots(out, r);

  // 3. Summary.
  std::ostringstream md;
  exact_field_intro(md, r, setup);
  exact_field_ideal_section(md, r);
  exact_field_dominant_section(md, r);
  exact_field_linear_section(md, r);
  exact_field_airgap_section(md, r);
  md << "## Plots\n\n" << md_image("eps(theta) at the reference offsets, per array", "eps.png") << "\n"
     << md_image("harmonic amplitudes at the reference offsets, per array", "harmonics.png") << "\n";
  for (const auto& p : coef_pngs) md << md_image("coefficients vs offset with cubic fits", p) << "\n";
  out.write_text("summary.md", md.str());
}

}  // namespace magenc
