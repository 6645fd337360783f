// Study multipole: a multipole code ring read by Bz arrays with electrical spacing (docs/multipole.md;
// docs/physics.md "Multipole rings and nonius"): interpolation error against read gap and array,
// eccentricity against the e/r law, a Monte Carlo of pole errors, and a nonius track's synchronisation
// margin over a tolerance box with the slipping mounts named. Computation in multipole_engine.*, outputs in
// multipole_report.* (this folder).
//   multipole [--config studies/multipole/multipole.toml] [--set study.box_samples=50] [--out DIR]
#include "multipole_engine.hpp"
#include "multipole_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs (all checked before any work); 2. the parts; 3. tables, plots, summary.
  const MultipoleStudyOptions opt = MultipoleStudyOptions::from_config(cfg);
  const MultipoleStudyResult result = run_multipole_study(cfg, opt);
  write_multipole_report(out, result);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study("multipole", "multipole: a multipole code ring, electrical read heads and a nonius track",
                   MultipoleStudyOptions::keys(), argc, argv, run);
}
