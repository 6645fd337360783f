// Study harmonic_provenance: which harmonics of the angle error are physical
// and which are artefacts of how the field is sampled.
//  1. The exact field is sampled on Cartesian plane grids of spacing h and
//     interpolated (nearest as the original study did, linear, cubic); every
//     case (ideal mount, sx, dx at provenance.offset_mm) runs through the
//     probe pipeline beside the exact field. Artefact = |c_n(grid) - c_n(exact)|.
//  2. Optionally FE solutions (provenance.fem_dirs: solve_field output
//     directories; use magnet.mu_r = 1 solves to compare with the exact field),
//     evaluated directly (fem:DIR).
// Writes provenance.csv (spectra table + columns source, variant, h_mm,
// interp, case), artefacts_vs_h.png, ideal_harmonics.png, summary.md.
//   harmonic_provenance [--config studies/harmonic_provenance.toml] [--out DIR]
#include <algorithm>
#include <cmath>
#include <sstream>

#include "analytic_field.hpp"
#include "errors.hpp"
#include "fem_field_scheme.hpp"
#include "field_factory.hpp"
#include "plot.hpp"
#include "provenance.hpp"
#include "study_output.hpp"
#include "study_plots.hpp"
#include "sweep.hpp"
#include "tables.hpp"

using namespace magenc;

namespace {

const char* kStudy = "harmonic_provenance";

std::vector<KeySpec> study_keys() {
  return {
      string_key("provenance.spacings_mm", "0.2,0.1,0.05,0.025", {}, "comma-separated grid spacings h (mm), coarse to fine"),
      string_key("provenance.interps", "nearest,linear,cubic", {}, "comma-separated interpolation modes"),
      real_key("provenance.half_width_mm", 3.5, 0, 100, "mm", "plane grids span [-w, w] in x and y", true),
      real_key("provenance.offset_mm", 0.1, 0, 10, "mm", "size of the sx and dx cases", true),
      string_key("provenance.fem_dirs", "", {}, "comma-separated solve_field output directories to include (may be empty)"),
      real_key("provenance.floor_deg", 1e-4, 0, 1, "deg", "exact c_n at or above this is physical", true),
  };
}

std::vector<double> parse_numbers(const std::string& text, const std::string& what) {
  std::vector<double> v;
  for (const auto& s : split_list(text, what)) {
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(s, &used);
    } catch (...) {
      used = 0;
    }
    if (used != s.size() || !(x > 0)) throw InputError(what + ": '" + s + "' is not a positive number (mm)");
    v.push_back(x);
  }
  return v;
}

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs.
  register_fem_field_scheme();
  const AnalyticField exact(Magnet::from_config(cfg));
  const ProbeSetup setup = probe_setup_from_config(cfg, cfg.str("sensor.array"));
  const auto spacings = parse_numbers(cfg.str("provenance.spacings_mm"), "provenance.spacings_mm");
  std::vector<Interp> modes;
  for (const auto& m : split_list(cfg.str("provenance.interps"), "provenance.interps"))
    modes.push_back(parse_interp(m, "provenance.interps"));
  const double off = cfg.real("provenance.offset_mm"), floor_deg = cfg.real("provenance.floor_deg");
  const Mount base = Mount::from_config(cfg);
  const std::vector<ProvenanceCase> cases = {{"ideal", base},
                                             {"sx=" + fmt(off, 2), with_offset(base, "sx_mm", off)},
                                             {"dx=" + fmt(off, 2), with_offset(base, "dx_mm", off)}};
  std::vector<std::string> fem_dirs;
  if (!cfg.str("provenance.fem_dirs").empty()) fem_dirs = split_list(cfg.str("provenance.fem_dirs"), "provenance.fem_dirs");

  // 2. Grid sampling of the exact field, then the FE solutions.
  std::vector<ProvenanceRow> rows =
      grid_sampling_scan(exact, setup, cases, spacings, modes, cfg.real("provenance.half_width_mm"));
  const std::size_t n_grid_rows = rows.size();
  for (const auto& dir : fem_dirs) {
    const auto fem = make_field_source("fem:" + dir, cfg);
    auto r = field_scan(exact, *fem, "fem", dir, setup, cases);
    rows.insert(rows.end(), r.begin(), r.end());
  }

  // 3. Table: one exact row per case, then every sampled row.
  std::vector<SpectrumRow> table;
  for (const auto& c : cases)
    table.push_back({"analytic", setup.array.name, setup.r0_mm, c.mount, error_spectrum(exact, setup, c.mount),
                     {{"source", "exact"}, {"variant", "exact"}, {"h_mm", "0"}, {"interp", ""}, {"case", c.label}}});
  for (const auto& r : rows) {
    const Mount m = std::find_if(cases.begin(), cases.end(), [&](auto& c) { return c.label == r.case_label; })->mount;
    std::ostringstream h;
    h << r.h_mm;
    table.push_back({r.source, setup.array.name, setup.r0_mm, m, r.sampled,
                     {{"source", r.source}, {"variant", r.variant}, {"h_mm", h.str()}, {"interp", r.interp}, {"case", r.case_label}}});
  }
  out.write_text("provenance.csv", spectra_csv(table));

  // 4. Plots: artefact of c4 and pp vs h per mode and case (log-log); ideal-mount bars.
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
          s.y.push_back(std::max(a, 1e-9));
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

  // 5. Summary (all numbers from the rows above).
  std::ostringstream md;
  md << "# harmonic_provenance: physical harmonics vs sampling artefacts\n\n"
     << "Array `" << setup.array.name << "`, r0 = " << fmt(setup.r0_mm, 3) << " mm, " << setup.steps
     << " samples per turn; cases: ideal mount, sx and dx of " << fmt(off, 3) << " mm. "
     << "The exact field was sampled on Cartesian plane grids (nodes on multiples of h, z = z_s) with h = "
     << cfg.str("provenance.spacings_mm") << " mm and interpolated with " << cfg.str("provenance.interps") << ". "
     << (fem_dirs.empty() ? std::string("No FE solutions were included (provenance.fem_dirs empty).")
                          : "FE solutions evaluated directly: " + cfg.str("provenance.fem_dirs") + ".")
     << " Table: `provenance.csv`.\n\n";
  md << "## Ideal mount: c4 and peak-to-peak by spacing and mode (deg; exact field: all zero)\n\n";
  std::vector<std::vector<std::string>> t;
  for (const auto& r : rows)
    if (r.case_label == "ideal")
      t.push_back({r.source, r.variant, fmt(r.sampled.c_deg[1], 5), fmt(r.sampled.c_deg[2], 5), fmt(r.sampled.c_deg[3], 5),
                   fmt(r.sampled.c_deg[4], 5), fmt(r.sampled.c_deg[8], 5), fmt(r.sampled.pp_deg, 5)});
  md << md_table({"source", "variant", "c1", "c2", "c3", "c4", "c8", "pp"}, t) << "\n";
  // Observed convergence order of the ideal-mount c4 artefact between the two finest spacings.
  if (spacings.size() >= 2) {
    md << "Observed order of the ideal-mount c4 artefact between h = " << spacings[spacings.size() - 2] << " and "
       << spacings.back() << " mm: ";
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
  md << "## Verdict per harmonic and case\n\n"
     << "Physical = the exact field gives c_n >= " << floor_deg
     << " deg. Artefact = |c_n(sampled) - c_n(exact)| over all grid variants"
     << (fem_dirs.empty() ? "" : " and FE solutions") << ": largest (where) and smallest (where).\n\n";
  std::vector<std::vector<std::string>> v;
  for (const auto& h : harmonic_verdicts(rows, floor_deg))
    v.push_back({h.case_label, "c" + std::to_string(h.n), fmt(h.exact_deg, 5), h.physical ? "physical" : "artefact only",
                 fmt(h.worst_artifact_deg, 5), h.worst_variant, fmt(h.best_artifact_deg, 6), h.best_variant});
  md << md_table({"case", "harmonic", "exact", "verdict", "worst artefact", "worst variant", "best artefact", "best variant"}, v)
     << "\n## Plots\n\n"
     << md_image("artefacts vs grid spacing", "artefacts_vs_h.png") << "\n"
     << md_image("ideal-mount harmonics", "ideal_harmonics.png") << "\n";
  out.write_text("summary.md", md.str());
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy, "harmonic_provenance: physical harmonics vs grid-sampling and FE artefacts", study_keys(),
                   argc, argv, run);
}
