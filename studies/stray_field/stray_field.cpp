// Study stray_field: the worst angle error of each sensor (bz arrays two, diff4, ring:8; inplane, xmr, amr)
// in a homogeneous stray field over all directions, at ISO 11452-8-style levels and as a curve of the
// magnitude, the field tolerated for given errors, direction maps, and beside a straight conductor
// (docs/physics.md "Environment: stray fields and temperature"). Computation in studies/stray_field/stray_field_engine.*,
// outputs in studies/stray_field/stray_field_report.*.
//   stray_field [--config studies/stray_field/stray_field.toml] [--set study.levels_kA_per_m=[1,4]] [--out DIR]
#include "studies/stray_field/stray_field_engine.hpp"
#include "studies/stray_field/stray_field_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

const char* kStudy = "stray_field";

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs: options, the base setup, the mount, the field (all checked before any work).
  const StrayFieldOptions opt = StrayFieldOptions::from_config(cfg);
  const StudyCase in = StudyCase::from_config(cfg);
  // 2. The computation; 3. tables, plots, summary.
  const StrayFieldResult result = run_stray_field(*in.field, in.base, in.mount, opt);
  write_stray_field_report(result, opt, StudySetup::from_config(cfg), out);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy, "stray_field: angle error in homogeneous stray fields and beside a conductor",
                   StrayFieldOptions::keys(), argc, argv, run);
}
