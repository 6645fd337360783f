// Study diagnosis: how well diagnose (src/analysis/diagnosis_fit) recovers mounting and signal-chain errors
// from one measured curve, and which combinations of sources reproduce the original study's unexplained
// measurements.
//  1. Round trip: roundtrip.cases seeded random truths per array (the parameters of roundtrip.randomized,
//     default: the free set), synthetic curves with reference-encoder noise and the sensor's quantization,
//     fitted; coverage of the 2-sigma intervals per free parameter (target ~95 %). Exact field always; the FE
//     field too when fem_field.dir names a solved field (roundtrip.fem_cases cases).
//     An all-free fit on a few cases lists what one curve cannot identify.
//  2. Anomalies: constructed target curves (hypotheses) fitted with candidate explanations
//     (analysis/diagnosis_study.hpp, anomaly_experiments()).
// Writes coverage.csv, anomalies.csv, example_fit.png, example_harmonics.png, summary.md.
//   diagnosis [--config studies/diagnosis.toml] [--set roundtrip.cases=20] [--out DIR]
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "analysis/sweep.hpp"
#include "analysis/diagnosis_study.hpp"
#include "core/errors.hpp"
#include "core/omp_wait.hpp"
#include "fem_field_scheme.hpp"
#include "fields/field_factory.hpp"
#include "report/diagnosis_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

const char* kStudy = "diagnosis";

std::vector<KeySpec> study_keys() {
  return {
      string_key("study.arrays", "two,diff4", {}, "comma-separated probe arrays (two, diff4, ring:N)"),
      int_key("roundtrip.cases", 100, 1, 100000, "random cases per array on the exact field"),
      int_key("roundtrip.fem_cases", 20, 0, 100000, "random cases per array on the FE field (fem_field.dir)"),
      int_key("roundtrip.seed", 1, 0, 1000000000, "seed of the random truths, noise and starts"),
      int_key("roundtrip.points", 360, 64, 1000000, "samples per synthetic curve (one turn, jittered)"),
      real_key("roundtrip.noise_deg", 0.005, 0, 10, "deg", "reference-encoder noise RMS (Gaussian)"),
      int_key("roundtrip.quant_positions", 8192, 0, 100000000, "sensor positions per turn (0: no quantization)"),
      string_key("roundtrip.randomized", "", {}, "parameters drawn at random (empty: the free set)"),
      string_key("roundtrip.free", "", {}, "parameters fitted (empty: the default free set of the array)"),
      real_key("roundtrip.range_scale", 2.0, 0, 100, "", "random values in +- range_scale * typical size"),
      real_key("roundtrip.max_zero_deg", 0.5, 0, 180, "deg", "random encoder zero offset in +- this"),
      int_key("roundtrip.starts", 3, 1, 100, "fit starts per case"),
      int_key("roundtrip.all_free_cases", 5, 0, 10000, "cases fitted with every parameter free (identifiability)"),
      bool_key("anomalies.enabled", true, "run the constructed-curve experiments"),
      string_key("fem_field.dir", "", {}, "solved field directory for fem: (empty: exact field only)"),
  };
}

std::vector<std::string> list(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  for (std::string x; std::getline(ss, x, ',');)
    if (!x.empty()) v.push_back(x);
  return v;
}

std::string pct(double f) { return fmt(100.0 * f, 0) + " %"; }

std::string val_sigma(double v, double s) {
  std::ostringstream os;
  os.precision(4);
  os << v << " +- ";
  if (std::isfinite(s)) os << std::setprecision(2) << s; else os << "inf";
  return os.str();
}

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs.
  register_fem_field_scheme();
  const auto arrays = list(cfg.str("study.arrays"));
  if (arrays.empty()) throw InputError("study.arrays is empty: allowed a comma-separated list of arrays");
  struct Src {
    std::string label;
    FieldSourcePtr field;
    int cases;
  };
  std::vector<Src> sources{{"exact", make_field_source("analytic", cfg), static_cast<int>(cfg.integer("roundtrip.cases"))}};
  const std::string fem_dir = cfg.str("fem_field.dir");
  if (!fem_dir.empty() && cfg.integer("roundtrip.fem_cases") > 0)
    sources.push_back({"fem:" + fem_dir, make_field_source("fem:" + fem_dir, cfg), static_cast<int>(cfg.integer("roundtrip.fem_cases"))});
  RoundTripOptions rt;
  rt.seed = static_cast<unsigned>(cfg.integer("roundtrip.seed"));
  rt.synth.points = static_cast<int>(cfg.integer("roundtrip.points"));
  rt.synth.noise_deg = cfg.real("roundtrip.noise_deg");
  rt.synth.quant_positions = static_cast<int>(cfg.integer("roundtrip.quant_positions"));
  rt.free = expand_free_names(list(cfg.str("roundtrip.free")));
  for (const auto& n : rt.free) fit_parameter(n);
  rt.range_scale = cfg.real("roundtrip.range_scale");
  rt.max_zero_deg = cfg.real("roundtrip.max_zero_deg");
  rt.starts = static_cast<int>(cfg.integer("roundtrip.starts"));
  const auto randomized = expand_free_names(list(cfg.str("roundtrip.randomized")));
  for (const auto& n : randomized) fit_parameter(n);

  // 2. Round trips.
  std::vector<RoundTripResult> trips;
  std::vector<std::pair<std::string, std::vector<std::string>>> all_free;  // array/source -> not identifiable counts text
  std::ostringstream csv;
  csv << "source,array,parameter,cases_fitted,within_2sigma,coverage,within_2sigma_any_minimum,cases_with_equal_minima,"
         "not_identifiable,median_abs_err,median_sigma\n";
  bool example_written = false;
  for (const auto& src : sources)
    for (const auto& a : arrays) {
      const ModelState base{Mount::from_config(cfg), probe_setup_from_config(cfg, a, "study.arrays")};
      RoundTripOptions o = rt;
      o.cases = src.cases;
      o.fd_step = src.label == "exact" ? 1e-4 : 1e-2;
      std::string note;
      if (o.free.empty()) {  // the default free set of this array, then randomize it (or the given list)
        std::mt19937 r0(o.seed);
        SyntheticOptions s0 = o.synth;
        s0.noise_deg = 0;
        s0.quant_positions = 0;
        // Chosen on the exact field (the physics; FE artefacts must not make confounded parameters look
        // separable), then fitted on this source.
        const std::vector<CurveInput> nominal{synthetic_curve(*sources.front().field, base, table_values(base, {}), s0, r0)};
        o.free = default_free_set(*sources.front().field, nominal, DiagnosisOptions{}, &note);
      }
      o.randomized = randomized.empty() ? o.free : randomized;
      RoundTripResult r = run_round_trip(*src.field, base, o);
      r.field = src.label;
      if (!note.empty()) r.default_free_note = note;
      for (const auto& p : r.params)
        csv << src.label << "," << a << "," << p.json_name << "," << p.fitted << "," << p.within_2sigma << ","
            << p.coverage() << "," << p.within_2sigma_any << "," << p.ambiguous << "," << p.not_identifiable << "," << p.median_abs_err << "," << p.median_sigma << "\n";
      trips.push_back(r);
      // Every parameter free on a few cases: what one curve cannot identify.
      // (exact field only: thirteen free parameters on an FE field take minutes per fit)
      const int nall = src.label == "exact" ? static_cast<int>(cfg.integer("roundtrip.all_free_cases")) : 0;
      if (nall > 0) {
        RoundTripOptions oa = o;
        oa.cases = nall;
        oa.free.clear();
        for (const auto& p : fit_parameters()) oa.free.push_back(p.name);
        const RoundTripResult ra = run_round_trip(*src.field, base, oa);
        std::vector<std::string> flagged;
        for (const auto& p : ra.params)
          flagged.push_back("`" + p.json_name + "` " + std::to_string(p.not_identifiable) + "/" + std::to_string(ra.cases - ra.failed));
        all_free.push_back({src.label + " `" + a + "`", flagged});
      }
      // One example fit, plotted.
      if (!example_written) {
        std::mt19937 rng(o.seed);
        std::vector<std::pair<std::string, double>> set;
        std::uniform_real_distribution<double> uni(-1.0, 1.0);
        for (const auto& n : o.randomized) set.push_back({n, uni(rng) * o.range_scale * fit_parameter(n).scale});
        SyntheticOptions so = o.synth;
        so.zero_deg = 0.2;
        const std::vector<CurveInput> curves{synthetic_curve(*src.field, base, table_values(base, set), so, rng)};
        DiagnosisOptions d;
        d.free = o.free;
        d.starts = o.starts;
        d.fd_step = o.fd_step;
        const DiagnosisResult dr = diagnose_curves(*src.field, curves, d);
        const auto tmp = out.dir() / "example";
        std::filesystem::create_directories(tmp);
        write_diagnosis_plots(tmp, curves, dr);
        std::filesystem::rename(tmp / "fit.png", out.dir() / "example_fit.png");
        std::filesystem::rename(tmp / "harmonics.png", out.dir() / "example_harmonics.png");
        std::filesystem::remove_all(tmp);
        example_written = true;
      }
    }
  out.write_text("coverage.csv", csv.str());

  // 3. Anomalies.
  std::vector<std::pair<std::string, Experiment>> exps;
  std::ostringstream acsv;
  acsv << "anomaly,array,target,candidate,residual_rms_deg,values,not_identifiable\n";
  if (cfg.flag("anomalies.enabled"))
    for (const auto& a : arrays) {
      const ModelState base{Mount::from_config(cfg), probe_setup_from_config(cfg, a, "study.arrays")};
      for (const auto& spec : anomaly_experiments()) {
        SyntheticOptions so = rt.synth;
        so.zero_deg = spec.zero_deg;
        Experiment ex = run_experiment(*sources.front().field, base, spec.title, spec.target_label, spec.truth,
                                       spec.candidates, so, rt.seed);
        for (const auto& f : ex.fits) {
          std::string vals, unid;
          for (const auto& [n, vs] : f.values) vals += (vals.empty() ? "" : " ") + n + "=" + val_sigma(vs.first, vs.second);
          for (const auto& n : f.not_identifiable) unid += (unid.empty() ? "" : " ") + n;
          acsv << "\"" << ex.title << "\"," << a << ",\"" << ex.target_label << "\",\"" << f.label << "\","
               << f.residual_rms_deg << ",\"" << vals << "\",\"" << unid << "\"\n";
        }
        exps.push_back({a, std::move(ex)});
      }
    }
  out.write_text("anomalies.csv", acsv.str());

  // 4. Summary.
  std::ostringstream md;
  md << "# diagnosis: recovering mounting and signal-chain errors from one measured curve\n\n"
     << "Synthetic curves: " << rt.synth.points << " samples per turn (jittered), reference-encoder noise "
     << fmt(rt.synth.noise_deg, 4) << " deg RMS, sensor quantization "
     << (rt.synth.quant_positions > 0 ? std::to_string(rt.synth.quant_positions) + " positions per turn (step " +
                                            fmt(360.0 / rt.synth.quant_positions, 4) + " deg)"
                                      : std::string("off"))
     << ", a random encoder zero offset within +-" << fmt(rt.max_zero_deg, 2) << " deg (fitted as a free DC); random "
     << "values within +-" << fmt(rt.range_scale, 1) << " typical sizes; seed " << rt.seed << ".\n\n";
  md << "## Round trip: coverage of the 2-sigma intervals\n\n"
     << "Fraction of cases whose recovered value lies within 2 sigma of the truth (Gaussian target 95.4 %). "
        "Free set per array: the default (what one curve identifies at the ideal mount) unless roundtrip.free is set.\n\n";
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& r : trips) {
      std::string rnd;
      for (const auto& n : r.randomized) rnd += (rnd.empty() ? "" : ", ") + n;
      for (const auto& p : r.params)
        t.push_back({r.field, "`" + r.array + "`", "`" + p.json_name + "`",
                     std::to_string(p.within_2sigma) + "/" + std::to_string(p.fitted), pct(p.coverage()),
                     pct(p.coverage_any()), std::to_string(p.ambiguous),
                     std::to_string(p.not_identifiable), fmt_auto(p.median_abs_err, 4), fmt_auto(p.median_sigma, 4)});
      t.push_back({r.field, "`" + r.array + "`", "(all)", std::to_string(r.cases - r.failed) + " fits, " +
                   std::to_string(r.failed) + " failed", "", "", "", "", "residual RMS median " + fmt_auto(r.median_residual_rms_deg, 4) + " deg",
                   "fit " + fmt(r.mean_fit_s, 3) + " s mean, " + fmt(r.max_fit_s, 3) + " s max"});
      (void)rnd;
    }
    md << md_table({"field", "array", "parameter", "within 2 sigma", "coverage", "coverage incl. equal minima",
                    "cases with equal minima", "not identifiable", "median |error|",
                    "median sigma"},
                   t)
       << "\n";
    for (const auto& r : trips)
      if (!r.default_free_note.empty()) md << "- " << r.field << " `" << r.array << "`: " << r.default_free_note << "\n";
    md << "\n";
  }
  if (!all_free.empty()) {
    md << "## Every parameter free: what one curve cannot identify\n\nCases in which each parameter was reported "
          "not identifiable (confounded with others, or sigma above its typical size) when all "
       << fit_parameters().size() << " table parameters and the zero offset are free:\n\n";
    for (const auto& [k, v] : all_free) {
      md << "- " << k << ": ";
      for (std::size_t i = 0; i < v.size(); ++i) md << (i ? ", " : "") << v[i];
      md << "\n";
    }
    md << "\n";
  }
  if (!exps.empty()) {
    md << "## The original study's anomalies: constructed curves (hypotheses)\n\n"
       << "Each target curve is made from one hypothetical combination of sources (exact field, with the noise and "
          "quantization above); the candidates are other explanations, fitted to it. A small residual means the "
          "candidate reproduces the curve as well as the target's own sources: then one curve cannot tell them "
          "apart. None of this is a finding about the real rig; it says which combinations would be consistent.\n\n";
    for (const auto& [a, ex] : exps) {
      const auto& h = ex.target_h;
      md << "### " << ex.title << " (`" << a << "`)\n\nTarget: " << ex.target_label << ": a0 " << fmt_auto(h[0], 4);
      for (int n = 1; n <= 4; ++n) md << ", c" << n << " " << fmt_auto(std::hypot(h[2 * n - 1], h[2 * n]), 4);
      md << " deg.\n\n";
      std::vector<std::vector<std::string>> t;
      for (const auto& f : ex.fits) {
        std::string vals, unid;
        for (const auto& [n, vs] : f.values) vals += (vals.empty() ? "" : "; ") + n + " " + val_sigma(vs.first, vs.second);
        for (const auto& n : f.not_identifiable) unid += (unid.empty() ? "" : ", ") + n;
        t.push_back({f.label, fmt_auto(f.residual_rms_deg, 4), vals, unid.empty() ? "-" : unid});
      }
      md << md_table({"candidate", "residual RMS [deg]", "fitted values (1 sigma)", "not identifiable"}, t) << "\n";
    }
  }
  md << "## Plots\n\n" << md_image("example round-trip fit", "example_fit.png") << "\n"
     << md_image("example harmonics", "example_harmonics.png") << "\n";
  out.write_text("summary.md", md.str());
}

}  // namespace

int main(int argc, char** argv) {
  prefer_passive_omp_wait(argc, argv);  // many small parallel regions (core/omp_wait.hpp)
  return run_study(kStudy,
                   "diagnosis: round trip of diagnose on seeded synthetic curves (coverage of 2-sigma intervals) and "
                   "constructed curves for the original study's anomalies",
                   study_keys(), argc, argv, run);
}
