// Study linear_model: the study's first field model, Bz = k*x, reproduced.
// An ideal mount, then each mounting offset alone (default sx, sy, dx, dy)
// swept over 0..sweep.max_mm for the configured array at r0. Writes
//   spectra.csv  one row per case (extra column `sweep`: "ideal" or the offset)
//   fits.csv     cubic fits of the chosen coefficients against each offset
//   eps.png, harmonics.png, coefficients.png, summary.md
// and compares the reference offset (default 0.1 mm) with the sanity values
// of docs/physics.md when the configuration matches theirs. The computation is
// src/analysis/offset_sweeps.*, the outputs src/report/sweep_reports.*.
//   linear_model [--config studies/linear_model/linear_model.toml] [--set sweep.points=51] [--out DIR]
#include "analysis/offset_sweeps.hpp"
#include "report/study_output.hpp"
#include "report/sweep_reports.hpp"

using namespace magenc;

namespace {

const char* kStudy = "linear_model";

void run(const Config& cfg, StudyOutput& out) {
  const LinearModelResult result = run_linear_model(cfg, kStudy);
  write_linear_model_report(out, result);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy, "linear_model: angle-error spectra of the linear field Bz = k*x for one-offset sweeps",
                   offset_sweep_keys("the eps(theta) plot, harmonic bars and summary table"), argc, argv, run);
}
