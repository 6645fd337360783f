// Study speed: the angle error of a turning encoder (docs/studies/speed.md; docs/physics.md "Speed: the
// error of a turning encoder"): error against rpm for chip timings with and without prediction, motor
// commutation, the channel filter's attenuation of the static harmonics, a calibration taken at one speed
// and run at another. Computation in speed_engine.*, outputs in speed_report.* (this folder).
//   speed [--config studies/speed/speed.toml] [--set study.rpm_max=10000] [--out DIR]
#include "report/study_output.hpp"
#include "speed_engine.hpp"
#include "speed_report.hpp"

using namespace magenc;

namespace {

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs (all checked before any work); 2. the sweeps; 3. tables, plots, summary.
  const SpeedStudyOptions opt = SpeedStudyOptions::from_config(cfg);
  const StudyCase in = StudyCase::from_config(cfg);
  const SpeedStudyResult result = run_speed_study(*in.field, in.base, in.mount, opt);
  write_speed_report(out, result);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study("speed", "speed: the angle error of a turning encoder (delay, filter, hold, prediction)",
                   SpeedStudyOptions::keys(), argc, argv, run);
}
