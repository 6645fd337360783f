// Study error_sources: the error sources of an encoder's tolerance sheet beyond
// the five offsets (docs/physics.md, "Beyond the five offsets"): sensor tilt about
// x and y, magnet tilt, magnetization elevation, channel offsets, gain
// mismatch and phase error, each swept alone from 0 on the exact field for
// several sensors (default the bz arrays two, diff4, ring:8 and the one-spot
// principles inplane, xmr, amr), with cubic fits, one
// coefficient figure per source, and which source makes which harmonic per
// array (harmonics.csv, harmonics_heatmap.png, summary.md). The sweeps live in
// studies/error_sources/error_sources_engine.*, the outputs in studies/error_sources/error_sources_report.*.
//   error_sources [--config studies/error_sources/error_sources.toml] [--set sweep.points=21] [--out DIR]
#include "studies/error_sources/error_sources_engine.hpp"
#include "analysis/sensor_principles.hpp"
#include "studies/error_sources/error_sources_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

const char* kStudy = "error_sources";

std::vector<KeySpec> study_keys() {
  std::vector<KeySpec> k = {
      string_list_key("study.arrays", {"two", "diff4", "ring:8", "inplane", "xmr", "amr"}, {},
                      "sensors: bz probe arrays (two, diff4, ring:N) and one-spot principles (inplane, xmr, amr)"),
      string_key("study.field", "analytic", {}, "field source (analytic; others cannot follow the magnetization elevation)"),
      string_list_key("study.sources",
                 {"tilt_x_deg", "tilt_y_deg", "magnet_tilt_deg", "magnetization_elevation_deg", "offset_cos_mT", "offset_sin_mT",
                  "offset_cos_rel", "offset_sin_rel", "gain_mismatch", "phase_error_deg"}, {},
                 "error sources, each swept alone from 0 (a source that does not apply to a sensor is left out: n/a)"),
      string_list_key("sweep.coefs", {"a0_deg", "c1_deg", "c2_deg", "c3_deg", "c4_deg"}, {}, "spectra columns fitted with a cubic"),
      real_key("summary.floor_deg", 1e-4, 0, 1e3, "deg", "harmonics below this amplitude are not listed as dominant"),
      real_key("summary.relative", 0.01, 0, 1, "", "harmonics below this fraction of the largest are not listed"),
  };
  return merge_schemas(k, error_source_sweep_keys());
}

void run(const Config& cfg, StudyOutput& out) {
  // 1. Probe setups, one per sensor (sensor.array is not used: study.arrays lists them; a principle
  //    name stands for the one-spot point array of that principle).
  std::vector<ProbeSetup> setups;
  const ProbeSetup base = probe_setup_from_config(cfg, "two");
  for (const auto& a : cfg.strings("study.arrays"))
    setups.push_back(principle_sensor(a, base, "study.arrays").setup);
  // 2. Every source alone on every array, cubic fits.
  const ErrorSourcesRun result = run_error_sources(cfg, setups, kStudy);
  // 3. Tables, plots, summary.
  write_error_sources_report(result, StudySetup::from_config(cfg), out);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy,
                   "error_sources: angle-error spectra of tilts, magnetization elevation and signal-chain errors, "
                   "each alone, for several probe arrays",
                   study_keys(), argc, argv, run);
}
