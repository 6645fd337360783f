// Study temperature: error spectra and the field against the chip's window from -40 to 150 C, for the
// configured mount and the tolerance box's p99 sample, per sensor (docs/physics.md "Environment: stray
// fields and temperature"). Computation in studies/temperature/temperature_sweep.*, outputs in
// studies/temperature/temperature_report.*.
//   temperature [--config studies/temperature/temperature.toml] [--set magnet.material=smco] [--out DIR]
#include "studies/temperature/temperature_sweep.hpp"
#include "report/study_output.hpp"
#include "studies/temperature/temperature_report.hpp"

using namespace magenc;

namespace {

const char* kStudy = "temperature";

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs: options, the base setup, the mount, the field (all checked before any work).
  const TemperatureOptions opt = TemperatureOptions::from_config(cfg);
  const StudyCase in = StudyCase::from_config(cfg);
  // 2. The sweep; 3. tables, plots, summary.
  const TemperatureResult result = run_temperature_sweep(*in.field, in.base, in.mount, opt);
  write_temperature_report(result, opt, StudySetup::from_config(cfg), out);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy, "temperature: error spectra and field margin from -40 to 150 C",
                   TemperatureOptions::keys(), argc, argv, run);
}
