// Study radius: which probe radius r0 to choose for the configured magnet, and
// what a mounting tolerance costs there (docs/studies/radius.md). For every field in radius.fields (plus the FEM field when
// radius.fem_dir holds a solved field), every array in radius.arrays and every
// r0 in radius.r0_min_mm..r0_max_mm: the spectra of six mounting cases, the
// worst case over the tolerance box corners, a seeded Monte Carlo over the box
// (mean, 95th, 99th percentile of the peak-to-peak error), the sensor-noise
// contribution, the recommended r0 and the error budget there (each group of
// the tolerance box alone: offsets, air gap, sensor tilt, magnet tilt, and when
// enabled the signal chain and the magnetization elevation). The physics and the fast surrogate
// live in src/analysis/radius_scan.*, the outputs in studies/radius/radius_report.*.
//   radius [--config studies/radius/radius.toml] [--set radius.samples=20000] [--out DIR]
#include <chrono>
#include <iostream>

#include "studies/radius/radius_report.hpp"
#include "analysis/radius_scan.hpp"
#include "report/study_output.hpp"
#include "field_solver/field_io/solved_field.hpp"

using namespace magenc;

namespace {

void run(const Config& cfg, StudyOutput& out) {
  const auto t0 = std::chrono::steady_clock::now();
  // 1. Inputs: scan options, then the field sources (fails before any work).
  const RadiusScanOptions opt = RadiusScanOptions::from_config(cfg);
  std::vector<std::string> notes;
  const auto specs =
      radius_field_specs(cfg, notes, [&](const std::string& dir) { return SolvedFieldDir(dir).mismatch(cfg); });
  std::vector<std::pair<std::string, FieldSourcePtr>> fields;
  for (const auto& s : specs) fields.emplace_back(s, open_field_source(s, cfg));
  check_distinct_field_kinds(fields);
  for (const auto& [spec, field] : fields) check_field_serves_box(*field, spec, opt);  // e.g. an elevation axis

  // 2. The scan, one field after another.
  RadiusScanResult result;
  for (const auto& [spec, field] : fields) {
    std::cout << "radius: scanning field " << spec << " (" << opt.r0_mm.size() << " radii, " << opt.samples
              << " MC samples each)\n";
    run_radius_scan(*field, spec, opt, result);
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // 3. Tables, plots, summary.
  out.write_text("radius.csv", radius_csv(result, opt.window.active()));
  out.write_text("radius_spectra.csv", spectra_csv(result.spectra));
  out.write_text("radius_recommendation.csv", recommendation_csv(result));
  out.write_text("radius_validation.csv", validation_csv(result));
  out.write_text("radius_budget.csv", budget_csv(result));
  write_radius_plots(result, opt, out.dir());
  write_budget_plot(result, out.dir());
  out.write_text("summary.md", radius_summary_md(result, opt, StudySetup::from_config(cfg), notes, wall_s));
}

}  // namespace

int main(int argc, char** argv) {
  return run_study("radius", "Probe radius choice: error spectra across r0, tolerance analysis, sensor noise",
                   RadiusScanOptions::keys(), argc, argv, run);
}
