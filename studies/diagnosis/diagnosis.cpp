// Study diagnosis: how well diagnose (src/analysis/diagnosis_fit) recovers mounting and signal-chain errors
// from one measured curve, and which combinations of sources reproduce the original study's unexplained
// measurements.
//  1. Round trip: roundtrip.cases seeded random truths per array (the parameters of roundtrip.randomized,
//     default: the free set), synthetic curves with reference-encoder noise and the sensor's quantization,
//     fitted; coverage of the 2-sigma intervals per free parameter (target ~95 %). Exact field always; the FE
//     field too when fem_field.dir names a solved field (roundtrip.fem_cases cases).
//     An all-free fit on a few cases lists what one curve cannot identify.
//  2. Anomalies: constructed target curves (hypotheses) fitted with candidate explanations
//     (studies/diagnosis/diagnosis_study.hpp, anomaly_experiments()).
// The computation lives in studies/diagnosis/diagnosis_study.* (run_diagnosis_study), the outputs in
// src/report/diagnosis_report.* (write_diagnosis_study_report).
// Writes coverage.csv, anomalies.csv, example_fit.png, example_harmonics.png, summary.md.
//   diagnosis [--config studies/diagnosis/diagnosis.toml] [--set roundtrip.cases=20] [--out DIR]
#include "studies/diagnosis/diagnosis_study.hpp"
#include "core/omp_wait.hpp"
#include "studies/diagnosis/diagnosis_study_report.hpp"
#include "report/study_output.hpp"
#include "field_solver/field_io/solved_field.hpp"

using namespace magenc;

namespace {

const char* kStudy = "diagnosis";

std::vector<KeySpec> study_keys() {
  return {
      string_list_key("study.arrays", {"two", "diff4"}, {}, "probe arrays (two, diff4, ring:N)"),
      int_key("roundtrip.cases", 100, 1, 100000, "random cases per array on the exact field"),
      int_key("roundtrip.fem_cases", 20, 0, 100000, "random cases per array on the FE field (fem_field.dir)"),
      int_key("roundtrip.seed", 1, 0, 1000000000, "seed of the random truths, noise and starts"),
      int_key("roundtrip.points", 360, 64, 1000000, "samples per synthetic curve (one turn, jittered)"),
      real_key("roundtrip.noise_deg", 0.005, 0, 10, "deg", "reference-encoder noise RMS (Gaussian)"),
      int_key("roundtrip.quant_positions", 8192, 0, 100000000, "sensor positions per turn (0: no quantization)"),
      string_list_key("roundtrip.randomized", {}, {}, "parameters drawn at random (empty: the free set)", 0),
      string_list_key("roundtrip.free", {}, {}, "parameters fitted (empty: the default free set of the array)", 0),
      real_key("roundtrip.range_scale", 2.0, 0, 100, "", "random values in +- range_scale * typical size"),
      real_key("roundtrip.max_zero_deg", 0.5, 0, 180, "deg", "random encoder zero offset in +- this"),
      int_key("roundtrip.starts", 3, 1, 100, "fit starts per case"),
      int_key("roundtrip.all_free_cases", 5, 0, 10000, "cases fitted with every parameter free (identifiability)"),
      int_key("roundtrip.all_free_starts", 1, 1, 100,
              "fit starts per case with every parameter free (each runs to the iteration cap in the flat valley)"),
      bool_key("roundtrip.exact_tables", true,
               "exact field from (r, z) tables of its parts, within 1e-12 of the quadrature (false: the quadrature at every point)"),
      bool_key("anomalies.enabled", true, "run the constructed-curve experiments"),
      string_key("fem_field.dir", "", {}, "solved field directory for fem: (empty: exact field only)"),
  };
}

void run(const Config& cfg, StudyOutput& out) {
  // The FE field (fem:DIR, served by field_solver/) is opened here; the library makes the exact field.
  FieldSourcePtr fem;
  const std::string fem_dir = cfg.str("fem_field.dir");
  if (!fem_dir.empty() && cfg.integer("roundtrip.fem_cases") > 0) fem = open_field_source("fem:" + fem_dir, cfg);
  const DiagnosisStudyResult result = run_diagnosis_study(cfg, fem);  // analysis/
  write_diagnosis_study_report(out, result);                          // report/
}

}  // namespace

int main(int argc, char** argv) {
  prefer_passive_omp_wait(argc, argv);  // many small parallel regions (core/omp_wait.hpp)
  return run_study(kStudy,
                   "diagnosis: round trip of diagnose on seeded synthetic curves (coverage of 2-sigma intervals) and "
                   "constructed curves for the original study's anomalies",
                   study_keys(), argc, argv, run);
}
