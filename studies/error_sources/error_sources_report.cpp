#include "studies/error_sources/error_sources_report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "report/setup_text.hpp"
#include "io/plot.hpp"
#include "io/tables.hpp"
#include "report/study_plots.hpp"

namespace magenc {

const std::vector<SourceReference>& physics_md_source_references() {
  static const std::vector<SourceReference> r = {
      {"tilt_x_deg", 1.0, "a0_deg", -0.403},       {"tilt_x_deg", 1.0, "c2_deg", 0.754},
      {"magnet_tilt_deg", 1.0, "c1_deg", 2.476},   {"magnet_tilt_deg", 1.0, "c3_deg", 0.259},
      {"magnetization_elevation_deg", 5.0, "c1_deg", 7.70},
      {"offset_cos_mT", 0.5, "c1_deg", 0.627},     {"gain_mismatch", 0.01, "c2_deg", 0.285},
      {"phase_error_deg", 1.0, "a0_deg", 0.500},   {"phase_error_deg", 1.0, "c2_deg", 0.500},
  };
  return r;
}

namespace {

std::string g_text(double v, int prec = 6) {
  std::ostringstream os;
  os << std::setprecision(prec) << v;
  return os.str();
}

std::string value_text(const ErrorSource& src, double v) {
  return g_text(v, 4) + (src.unit.empty() ? "" : " " + src.unit);
}

std::vector<HarmonicSignature> signatures(const ErrorSourcesRun& run) {
  std::vector<HarmonicSignature> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& per_array : run.sweeps)
    for (const auto& sw : per_array) {
      if (!sw.rows.empty()) {
        out.push_back(harmonic_signature(sw, nan));
        continue;
      }
      HarmonicSignature none;  // the source does not apply to this sensor (e.g. an mT offset on xmr)
      none.swept = sw.spec.swept;
      none.array = sensor_label(sw.setup);
      none.value = nan;
      none.c_deg.fill(nan);
      none.pp_deg = nan;
      out.push_back(none);
    }
  return out;
}

}  // namespace

std::string signature_text(const HarmonicSignature& h, double floor_deg, double rel, int max_count) {
  if (std::isnan(h.pp_deg)) return "n/a";
  const double largest = *std::max_element(h.c_deg.begin(), h.c_deg.end());
  const double thr = std::max(floor_deg, rel * largest);
  std::vector<int> n;
  for (int k = 0; k <= 8; ++k)
    if (h.c_deg[k] >= thr && h.c_deg[k] >= kRoundingZeroDeg) n.push_back(k);
  std::stable_sort(n.begin(), n.end(), [&](int a, int b) { return h.c_deg[a] > h.c_deg[b]; });
  if (n.size() > std::size_t(max_count)) n.resize(std::size_t(max_count));
  if (n.empty()) return "none";
  std::string t;
  for (int k : n) t += (t.empty() ? "" : ", ") + (k == 0 ? std::string("|a0|") : "c" + std::to_string(k)) + " " + fmt_auto(h.c_deg[k], 3);
  return t;
}

std::string harmonics_csv(const ErrorSourcesRun& run, double floor_deg, double rel) {
  std::ostringstream os;
  os << "source,array,value,unit";
  for (int n = 0; n <= 8; ++n) os << ",c" << n << "_deg";
  os << ",pp_deg,dominant\n";
  os << std::setprecision(10);
  for (const auto& h : signatures(run)) {
    if (std::isnan(h.pp_deg)) continue;  // the source does not apply to this sensor
    const ErrorSource& src = find_error_source(h.swept);
    os << h.swept << "," << h.array << "," << h.value << "," << src.unit;
    for (double c : h.c_deg) os << "," << c;
    os << "," << h.pp_deg << ",\"" << signature_text(h, floor_deg, rel) << "\"\n";
  }
  return os.str();
}

namespace {

// harmonics_heatmap: one row per (source, array), columns |a0|, c1..c8 at the source's largest value.
void write_source_heatmap(StudyOutput& out, const ErrorSourcesRun& run, const std::vector<HarmonicSignature>& sig) {
  HeatmapSpec hm;
  hm.title = "Harmonics of each error source alone, at its largest swept value (" + run.field + " field, r_0 = " +
             fmt(run.setups.front().r0_mm, 2) + " mm)";
  hm.xlabel = "harmonic of the angle error (c_0 = |a_0|)";
  hm.ylabel = "";
  for (int n = 0; n <= 8; ++n) hm.column_labels.push_back(n == 0 ? "|a_0|" : "c_" + std::to_string(n));
  hm.cblabel = "amplitude [deg] (log scale; below 10^{-4} deg: lowest colour)";
  hm.log_floor = 1e-4;
  std::size_t k = 0;
  for (std::size_t s = 0; s < run.sources.size(); ++s) {
    if (s > 0) hm.row_separators.push_back(int(k));
    for (std::size_t a = 0; a < run.setups.size(); ++a, ++k) {
      const HarmonicSignature& h = sig[k];
      hm.row_labels.push_back(run.sources[s]->symbol + " = " +
                              (std::isnan(h.value) ? std::string("n/a") : plot_literal(value_text(*run.sources[s], h.value))) +
                              ", " + plot_literal(h.array));
      std::vector<double> v(h.c_deg.begin(), h.c_deg.end());
      std::vector<std::string> t;
      for (double c : v)
        t.push_back(std::isnan(c) ? "n/a" : c < kRoundingZeroDeg ? "0" : (c < 1e-4 ? "<1e-4" : g_text(c, 2)));
      // A source that does not apply: NaN, a blank cell with the text n/a.
      hm.values.push_back(v);
      hm.cell_text.push_back(t);
    }
  }
  hm.width_px = 1200;
  hm.height_px = 160 + 26 * int(hm.row_labels.size());
  write_heatmap(out.dir(), "harmonics_heatmap", hm);
}

// coefficients_<source>: the coefficients against each source, all arrays in one figure per source;
// returns the PNG names.
std::vector<std::string> write_source_coefficient_plots(StudyOutput& out, const ErrorSourcesRun& run) {
  std::vector<std::string> coef_pngs;
  const std::string what = run.field + " field, r_0 = " + fmt(run.setups.front().r0_mm, 2) + " mm";
  for (std::size_t s = 0; s < run.sources.size(); ++s) {
    std::vector<SweepCase> sc;
    for (const auto& sw : run.sweeps[s])
      if (!sw.rows.empty()) sc.push_back({plot_literal(sensor_label(sw.setup)), &sw});
    const std::string name = "coefficients_" + run.sources[s]->swept;
    write_plot(out.dir(), name,
               coefficient_figure(run.sources[s]->description + " alone (" + what + ")",
                                  source_axis_label(*run.sources[s]), sc, run.fits, run.coefs));
    coef_pngs.push_back(name + ".png");
  }
  return coef_pngs;
}

// summary.md: the field, the arrays and the swept sources.
void error_sources_intro(std::ostringstream& md, const ErrorSourcesRun& run, const StudySetup& setup) {
  md << "# error_sources: the error sources beyond the five offsets, one at a time\n\n"
     << "Field `" << run.field << "` (magnet " << magnet_text(setup) << "; sensing plane " << fmt(setup.plane_height_mm, 2) << " mm above the top face), r0 = "
     << fmt(run.setups.front().r0_mm, 3) << " mm, " << run.setups.front().steps << " samples per turn, arrays ";
  for (std::size_t a = 0; a < run.setups.size(); ++a) md << (a ? ", " : "") << "`" << sensor_label(run.setups[a]) << "`";
  md << ". Each source is swept alone from 0 (every other key as configured: an ideal mount by default) in "
     << run.sweep_points << " values:\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (std::size_t s = 0; s < run.sources.size(); ++s) {
      double top = std::numeric_limits<double>::quiet_NaN();
      for (const auto& sw : run.sweeps[s])
        if (!sw.spec.values_mm.empty()) top = sw.spec.values_mm.back();
      t.push_back({"`" + run.sources[s]->swept + "`", run.sources[s]->description, "`" + run.sources[s]->key + "`",
                   std::isnan(top) ? std::string("n/a") : "0 .. " + value_text(*run.sources[s], top)});
    }
    md << md_table({"source (fits `swept`)", "what", "configuration key", "swept"}, t) << "\n";
  }
  md << "Tables: `spectra.csv` (spectra table; extra columns `sweep`, `swept`, `value`), `fits.csv` (cubic fits "
        "p3 x^3 + p2 x^2 + p1 x + p0 of "
     << run.coefs.size() << " coefficients against the source's value in its unit; `swept` names the source), "
     << "`harmonics.csv` (the matrix below).\n\n";
}

// summary.md: which source makes which harmonic, per array (signatures and all amplitudes).
void error_sources_matrix(std::ostringstream& md, const ErrorSourcesRun& run, const std::vector<HarmonicSignature>& sig,
                          double floor_deg, double rel) {
  md << "## Which source makes which harmonic, per array\n\n"
     << "Each source alone at its largest swept value; the harmonics with amplitude >= max(" << floor_deg << " deg, "
     << rel << " x the largest), largest first (|a0| is the constant part). Amplitudes in deg.\n\n";
  {
    std::vector<std::string> header = {"source", "value"};
    for (const auto& s : run.setups) header.push_back("`" + sensor_label(s) + "`");
    std::vector<std::vector<std::string>> t;
    std::size_t i = 0;
    for (const auto* src : run.sources) {
      double v = std::numeric_limits<double>::quiet_NaN();
      for (std::size_t a = 0; a < run.setups.size(); ++a)
        if (!std::isnan(sig[i + a].value)) v = sig[i + a].value;
      std::vector<std::string> r = {src->description, std::isnan(v) ? std::string("n/a") : value_text(*src, v)};
      for (std::size_t a = 0; a < run.setups.size(); ++a, ++i) {
        std::string text = signature_text(sig[i], floor_deg, rel);
        for (std::size_t p = text.find('|'); p != std::string::npos; p = text.find('|', p + 2)) text.insert(p, 1, '\\');
        r.push_back(text);  // "|a0|" escaped for the Markdown table
      }
      t.push_back(r);
    }
    md << md_table(header, t) << "\n";
  }
  md << md_image("heat map of |a0|, c1..c8 per source and array", "harmonics_heatmap.png") << "\n\n";
  md << "All amplitudes (deg) of the same cases:\n\n";
  {
    std::vector<std::string> header = {"source", "array"};
    for (int n = 0; n <= 8; ++n) header.push_back(n == 0 ? "\\|a0\\|" : "c" + std::to_string(n));
    header.push_back("pp");
    std::vector<std::vector<std::string>> t;
    std::size_t i = 0;
    for (const auto* src : run.sources)
      for (std::size_t a = 0; a < run.setups.size(); ++a, ++i) {
        std::vector<std::string> r = {"`" + src->swept + "`", "`" + sig[i].array + "`"};
        for (double c : sig[i].c_deg) r.push_back(std::isnan(c) ? std::string("n/a") : fmt_auto(c, 4, kRoundingZeroDeg));
        r.push_back(std::isnan(sig[i].pp_deg) ? std::string("n/a") : fmt_auto(sig[i].pp_deg, 4, kRoundingZeroDeg));
        t.push_back(r);
      }
    md << md_table(header, t) << "\n";
  }
}

// summary.md: the sweeps' values at docs/physics.md's reference cases.
void error_sources_references(std::ostringstream& md, const ErrorSourcesRun& run) {
  md << "## Against the reference values of docs/physics.md\n\n"
     << "docs/physics.md gives these for the exact field of the default magnet, r0 = 2.4 mm, `two`; listed when the "
        "sweep holds that value and array.\n\n";
  std::vector<std::vector<std::string>> t;
  for (const auto& ref : physics_md_source_references())
    for (std::size_t s = 0; s < run.sources.size(); ++s) {
      if (run.sources[s]->swept != ref.swept) continue;
      for (const auto& sw : run.sweeps[s]) {
        if (sw.setup.array.name != "two") continue;
        for (std::size_t v = 0; v < sw.rows.size(); ++v)
          if (std::abs(sw.spec.values_mm[v] - ref.value) < 1e-9) {
            const double got = sw.rows[v].spectrum.column(ref.coef);
            t.push_back({"`" + ref.swept + "` = " + g_text(ref.value), ref.coef, fmt(got, 3), fmt(ref.expected_deg, 3),
                         fmt(got - ref.expected_deg, 4)});
          }
      }
    }
  if (t.empty())
    md << "(none of the reference cases is in these sweeps)\n\n";
  else
    md << md_table({"case (`two`)", "column", "computed [deg]", "docs/physics.md [deg]", "difference [deg]"}, t) << "\n";
}

}  // namespace

void write_error_sources_report(const ErrorSourcesRun& run, const StudySetup& setup, StudyOutput& out) {
  const double floor_deg = run.floor_deg, rel = run.relative;
  // 1. Tables.
  std::vector<SpectrumRow> rows;
  for (const auto& per_array : run.sweeps)
    for (const auto& sw : per_array) rows.insert(rows.end(), sw.rows.begin(), sw.rows.end());
  out.write_text("spectra.csv", spectra_csv(rows));
  out.write_text("fits.csv", fits_csv(run.fits));
  out.write_text("harmonics.csv", harmonics_csv(run, floor_deg, rel));
  const auto sig = signatures(run);

  // 2. Heat map.
  write_source_heatmap(out, run, sig);
  // 3. Coefficients against each source.
  const std::vector<std::string> coef_pngs = write_source_coefficient_plots(out, run);

  // 4. summary.md.
  std::ostringstream md;
  error_sources_intro(md, run, setup);
  error_sources_matrix(md, run, sig, floor_deg, rel);
  error_sources_references(md, run);
  md << "## Coefficients against each source (cubic fits)\n\n";
  for (std::size_t s = 0; s < coef_pngs.size(); ++s)
    md << md_image(run.sources[s]->description + ": coefficients vs value, per array", coef_pngs[s]) << "\n";
  out.write_text("summary.md", md.str());
}

}  // namespace magenc
