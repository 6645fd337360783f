// Study steel_parts: what a magnet holder, a shaft and an end shield of steel
// (or brass) do to the field on the sensing plane, the field window and the
// harmonics c1..c4, linear (a constant mu_r) and with saturation (a B-H curve,
// Newton). Every solve and the spectra: studies/steel_parts/steel_parts_run.* (results in
// studies/steel_parts/steel_parts_result.hpp); the outputs: studies/steel_parts/steel_parts_report.*.
//   steel_parts [--config studies/steel_parts/steel_parts.toml] [--out DIR]
#include "studies/steel_parts/steel_parts_report.hpp"
#include "report/study_output.hpp"
#include "studies/steel_parts/steel_parts_run.hpp"

using namespace magenc;

namespace {

void run(const Config& cfg, StudyOutput& out) {
  // field_solver/; the steel cup's field files for ParaView into the output's steel_cup/
  const SteelPartsResult result = fem::run_steel_parts(cfg, {".", MAGENC_SOURCE_DIR}, out.dir() / "steel_cup");
  write_steel_parts_report(out, result);                                                  // report/
}

}  // namespace

int main(int argc, char** argv) {
  return run_study("steel_parts",
                   "steel_parts: magnet alone, in a steel or brass cup, on a steel shaft, above an end shield; linear "
                   "and saturating steel; field window and c1..c4 under the mounting offsets",
                   fem::steel_parts_keys(), argc, argv, run);
}
