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
// summary.md carries the acceptance check at the reference offset: for `two`
// and `diff4`, c1..c4 of every FEM source within max(2 % of exact, 0.002 deg).
// The computation is src/analysis/fem_field_studies.*, the outputs
// src/report/fem_field_reports.*.
//   real_field [--config studies/real_field/real_field.toml] [--set fem_field.dir=/tmp/field] [--out DIR]
#include "analysis/fem_field_studies.hpp"
#include "field_solver/field_io/solved_field.hpp"
#include "report/fem_field_reports.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

const char* kStudy = "real_field";

std::vector<KeySpec> study_keys() {
  std::vector<KeySpec> k = {study_arrays_key()};
  for (auto& s : offset_sweep_keys("the eps(theta) plot, harmonic bars and the acceptance table")) k.push_back(s);
  for (auto& s : acceptance_keys()) k.push_back(s);
  for (auto& s : fem_field_keys("plane.vti")) k.push_back(s);
  return k;
}

void run(const Config& cfg, StudyOutput& out) {
  const RealFieldResult result = run_real_field(cfg, kStudy, fem_sources_from_config(cfg));
  write_real_field_report(out, result, StudySetup::from_config(cfg));
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy,
                   "real_field: angle-error spectra of the FEM field (fem:DIR / grid:DIR/plane.vti) for one-offset "
                   "sweeps and several arrays, beside the exact field, with the FEM-vs-exact acceptance check",
                   study_keys(), argc, argv, run);
}
