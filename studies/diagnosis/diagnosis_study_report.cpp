#include "studies/diagnosis/diagnosis_study_report.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "core/format.hpp"
#include "report/diagnosis_report.hpp"
#include "report/study_plots.hpp"

namespace magenc {

namespace {

std::string pct(double f) { return fmt(100.0 * f, 0) + " %"; }

std::string val_sigma(double v, double s) {
  std::ostringstream os;
  os.precision(4);
  os << v << " +- ";
  if (std::isfinite(s)) os << std::setprecision(2) << s; else os << "inf";
  return os.str();
}

std::string coverage_csv(const DiagnosisStudyResult& res) {
  std::ostringstream csv;
  csv << "source,array,parameter,cases_fitted,within_2sigma,coverage,within_2sigma_any_minimum,cases_with_equal_minima,"
         "not_identifiable,median_abs_err,median_sigma\n";
  for (const auto& r : res.trips)
    for (const auto& p : r.params)
      csv << r.field << "," << r.array << "," << p.json_name << "," << p.fitted << "," << p.within_2sigma << ","
          << p.coverage() << "," << p.within_2sigma_any << "," << p.ambiguous << "," << p.not_identifiable << ","
          << p.median_abs_err << "," << p.median_sigma << "\n";
  return csv.str();
}

std::string anomalies_csv(const DiagnosisStudyResult& res) {
  std::ostringstream acsv;
  acsv << "anomaly,array,target,candidate,residual_rms_deg,values,not_identifiable,equal_minima\n";
  for (const auto& [a, ex] : res.anomalies)
    for (const auto& f : ex.fits) {
      std::string vals, unid, alts;
      for (const auto& [n, vs] : f.values) vals += (vals.empty() ? "" : " ") + n + "=" + val_sigma(vs.first, vs.second);
      for (const auto& n : f.not_identifiable) unid += (unid.empty() ? "" : " ") + n;
      for (const auto& alt : f.alternatives) alts += (alts.empty() ? "" : "; ") + alt;
      acsv << "\"" << ex.title << "\"," << a << ",\"" << ex.target_label << "\",\"" << f.label << "\","
           << f.residual_rms_deg << ",\"" << vals << "\",\"" << unid << "\",\"" << alts << "\"\n";
    }
  return acsv.str();
}

std::string diagnosis_study_summary(const DiagnosisStudyResult& res) {
  const SyntheticOptions& synth = res.synth;
  std::ostringstream md;
  md << "# diagnosis: recovering mounting and signal-chain errors from one measured curve\n\n"
     << "Synthetic curves: " << synth.points << " samples per turn (jittered), reference-encoder noise "
     << fmt(synth.noise_deg, 4) << " deg RMS, sensor quantization "
     << (synth.quant_positions > 0 ? std::to_string(synth.quant_positions) + " positions per turn (step " +
                                         fmt(360.0 / synth.quant_positions, 4) + " deg)"
                                   : std::string("off"))
     << ", a random encoder zero offset within +-" << fmt(res.max_zero_deg, 2) << " deg (fitted as a free DC); random "
     << "values within +-" << fmt(res.range_scale, 1) << " typical sizes; seed " << res.seed << ".\n\n";
  md << "## Round trip: coverage of the 2-sigma intervals\n\n"
     << "Fraction of cases whose recovered value lies within 2 sigma of the truth (Gaussian target 95.4 %). "
        "Free set per array: the default (what one curve identifies at the ideal mount) unless roundtrip.free is set.\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& r : res.trips) {
      for (const auto& p : r.params)
        t.push_back({r.field, "`" + r.array + "`", "`" + p.json_name + "`",
                     std::to_string(p.within_2sigma) + "/" + std::to_string(p.fitted), pct(p.coverage()),
                     pct(p.coverage_any()), std::to_string(p.ambiguous),
                     std::to_string(p.not_identifiable), fmt_auto(p.median_abs_err, 4), fmt_auto(p.median_sigma, 4)});
      t.push_back({r.field, "`" + r.array + "`", "(all)", std::to_string(r.cases - r.failed) + " fits, " +
                   std::to_string(r.failed) + " failed", "", "", "", "", "residual RMS median " + fmt_auto(r.median_residual_rms_deg, 4) + " deg",
                   "fit " + fmt(r.mean_fit_s, 3) + " s mean, " + fmt(r.max_fit_s, 3) + " s max"});
    }
    md << md_table({"field", "array", "parameter", "within 2 sigma", "coverage", "coverage incl. equal minima",
                    "cases with equal minima", "not identifiable", "median |error|",
                    "median sigma"},
                   t)
       << "\n";
    for (const auto& r : res.trips)
      if (!r.default_free_note.empty()) md << "- " << r.field << " `" << r.array << "`: " << r.default_free_note << "\n";
    md << "\n";
  }
  if (!res.all_free.empty()) {
    md << "## Every parameter free: what one curve cannot identify\n\nCases in which each parameter was reported "
          "not identifiable (confounded with others, or sigma above its typical size) when all "
       << fit_parameters().size() << " table parameters and the zero offset are free (" << res.all_free_starts
       << " fit start" << (res.all_free_starts == 1 ? "" : "s")
       << " per case, `roundtrip.all_free_starts`; such a fit stops at its iteration cap in a flat valley, so a "
          "count below n/n moves by a case or two with the starts or the round-off):\n\n";
    for (const auto& [k, v] : res.all_free) {
      md << "- " << k << ": ";
      for (std::size_t i = 0; i < v.size(); ++i) md << (i ? ", " : "") << v[i];
      md << "\n";
    }
    md << "\n";
  }
  if (!res.anomalies.empty()) {
    md << "## The original study's anomalies: constructed curves (hypotheses)\n\n"
       << "Each target curve is made from one hypothetical combination of sources (exact field, with the noise and "
          "quantization above); the candidates are other explanations, fitted to it. A small residual means the "
          "candidate reproduces the curve as well as the target's own sources: then one curve cannot tell them "
          "apart. None of this is a finding about the real rig; it says which combinations would be consistent.\n\n";
    for (const auto& [a, ex] : res.anomalies) {
      const auto& h = ex.target_h;
      md << "### " << ex.title << " (`" << a << "`)\n\nTarget: " << ex.target_label << ": a0 " << fmt_auto(h[0], 4);
      for (int n = 1; n <= 4; ++n) md << ", c" << n << " " << fmt_auto(harmonic_amplitude(h, n), 4);
      md << " deg.\n\n";
      std::vector<std::vector<std::string>> t;
      for (const auto& f : ex.fits) {
        std::string vals, unid, alts;
        for (const auto& [n, vs] : f.values) vals += (vals.empty() ? "" : "; ") + n + " " + val_sigma(vs.first, vs.second);
        for (const auto& n : f.not_identifiable) unid += (unid.empty() ? "" : ", ") + n;
        for (const auto& alt : f.alternatives) alts += (alts.empty() ? "" : "; ") + alt;
        t.push_back({f.label, fmt_auto(f.residual_rms_deg, 4), vals, unid.empty() ? "-" : unid, alts.empty() ? "-" : alts});
      }
      md << md_table({"candidate", "residual RMS [deg]", "fitted values (1 sigma)", "not identifiable",
                      "equally good minima elsewhere"},
                     t)
         << "\n";
    }
  }
  md << "## Plots\n\n" << md_image("example round-trip fit", "example_fit.png") << "\n"
     << md_image("example harmonics", "example_harmonics.png") << "\n";
  return md.str();
}

}  // namespace

void write_diagnosis_study_report(StudyOutput& out, const DiagnosisStudyResult& res) {
  // The example fit's plots: written by write_diagnosis_plots into a scratch folder, renamed into the study folder.
  if (!res.example_curves.empty()) {
    const auto tmp = out.dir() / "example";
    std::filesystem::create_directories(tmp);
    write_diagnosis_plots(tmp, res.example_curves, res.example_fit);
    std::filesystem::rename(tmp / "fit.png", out.dir() / "example_fit.png");
    std::filesystem::rename(tmp / "harmonics.png", out.dir() / "example_harmonics.png");
    std::filesystem::remove_all(tmp);
  }
  out.write_text("coverage.csv", coverage_csv(res));
  out.write_text("anomalies.csv", anomalies_csv(res));
  out.write_text("summary.md", diagnosis_study_summary(res));
}

}  // namespace magenc
