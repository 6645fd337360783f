// Study exact_field: the one-offset sweeps of linear_model on the exact field
// of the configured (default) magnet, for several probe arrays (default two,
// diff4, ring:8), plus an air-gap sweep dz with a residual dynamic
// eccentricity. The same reference cases are also run on the linear field so
// the summary can say what the linear model misses. Writes
//   spectra.csv  one row per case (extra column `sweep` names the case)
//   fits.csv     cubic fits of the chosen coefficients (study field)
//   eps.png, harmonics.png, coefficients_<offset>.png, summary.md
// The computation is src/analysis/offset_sweeps.*, the outputs src/report/sweep_reports.*.
//   exact_field [--config studies/exact_field/exact_field.toml] [--set sweep.points=51] [--out DIR]
#include "analysis/offset_sweeps.hpp"
#include "report/study_output.hpp"
#include "report/sweep_reports.hpp"

using namespace magenc;

namespace {

const char* kStudy = "exact_field";

std::vector<KeySpec> study_keys() {
  std::vector<KeySpec> k = {study_arrays_key(),
                            string_key("study.field", "analytic", {}, "field source of the study (linear, analytic, ...)")};
  for (auto& s : offset_sweep_keys("the eps(theta) plot, harmonic bars and summary tables")) k.push_back(s);
  for (auto& s : dz_sweep_keys()) k.push_back(s);
  k.push_back(real_key("dz_sweep.residual_dx_mm", 0.05, -100, 100, "mm",
                       "dynamic eccentricity dx present during the air-gap sweep"));
  k.push_back(real_key("summary.floor_deg", 1e-4, 0, 1e3, "deg",
                       "harmonics below this amplitude are not listed as dominant"));
  k.push_back(real_key("summary.relative", 0.01, 0, 1, "",
                       "harmonics below this fraction of the largest are not listed as dominant"));
  return k;
}

void run(const Config& cfg, StudyOutput& out) {
  const ExactFieldResult result = run_exact_field(cfg, kStudy);
  write_exact_field_report(out, result, StudySetup::from_config(cfg));
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy,
                   "exact_field: angle-error spectra of the exact magnet field for one-offset sweeps, "
                   "several probe arrays, and an air-gap sweep",
                   study_keys(), argc, argv, run);
}
