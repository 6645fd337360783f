// Study sensor_principles: Hall arrays reading Bz on a circle (two, diff4,
// ring:8) beside the one-spot principles (in-plane Hall, saturated GMR/TMR,
// AMR; docs/physics.md "Sensor principles") on the same magnet, field and
// tolerance box: the spectrum of each mounting error alone, the Monte Carlo
// p99 of pp over the box, the field against each sensor's window, and which
// principle tolerates which error and why. Computation in
// src/analysis/sensor_principles.*, outputs in studies/sensor_principles/sensor_principles_report.*.
//   sensor_principles [--config studies/sensor_principles/sensor_principles.toml] [--set study.samples=100] [--out DIR]
#include "analysis/sensor_principles.hpp"
#include "fields/field_factory.hpp"
#include "studies/sensor_principles/sensor_principles_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

const char* kStudy = "sensor_principles";

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs: options, the bz base setup (r0, plane, steps), the field (all checked before any work).
  const SensorPrinciplesOptions opt = SensorPrinciplesOptions::from_config(cfg);
  const ProbeSetup base = probe_setup_from_config(cfg, "two");
  const FieldSourcePtr field = make_field_source(cfg.str("study.field"), cfg);
  // 2. The comparison; 3. tables, plots, summary.
  const SensorPrinciplesResult result = run_sensor_principles(*field, base, opt);
  write_sensor_principles_report(result, opt, StudySetup::from_config(cfg), out);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy,
                   "sensor_principles: Hall arrays, in-plane Hall, xMR and AMR on the same magnet and tolerance box",
                   SensorPrinciplesOptions::keys(), argc, argv, run);
}
