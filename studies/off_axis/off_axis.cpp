// Study off_axis: a ring magnet read from the side (a point sensor beside the ring: raw, with the gain
// trim, with each calibration) and by Bz arrays around the bore, on one tolerance box (docs/physics.md
// "Ring magnets and sensors off the axis"; docs/studies/off_axis.md). Computation in off_axis_engine.*,
// outputs in off_axis_report.* (this folder).
//   off_axis [--config studies/off_axis/off_axis.toml] [--set off_axis.samples=50] [--out DIR]
#include "off_axis_engine.hpp"
#include "off_axis_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

void run(const Config& cfg, StudyOutput& out) {
  const OffAxisOptions opt = OffAxisOptions::from_config(cfg);
  const OffAxisResult result = run_off_axis(cfg, opt);
  write_off_axis_report(result, opt, out);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study("off_axis", "off_axis: a ring magnet read side-shaft and by bore arrays on one tolerance box",
                   OffAxisOptions::keys(), argc, argv, run);
}
