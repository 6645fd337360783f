// calibrate: the factory correction of an encoder as a table a firmware can use, and what is left of it
// after a change (docs/interfaces.md "calibrate", docs/physics.md "Calibration").
//
//   calibrate [--measured FILE.csv | --correction FILE.csv] [--method none|harmonics:N|lut:K|ogp]
//             [--apply FILE.csv | --apply run] [--field F] [--array A] [--r0 MM] [--config F] [--set k=v]... --out DIR
//
// The correction comes from a measured curve (the formats diagnose reads; ogp needs theta_deg,u_cos,u_sin),
// from a correction file written before, or (neither given) from the simulated calibration state
// calibration.at over the configuration. Writes DIR/correction.csv and DIR/correction.json
// (analysis/calibration_file.hpp) and, with --apply, DIR/residual.csv (theta_deg,error_deg,residual_deg) and
// DIR/residual.json of another measured curve or of the configured run state (`--apply run`: the mount
// keys of the configuration, e.g. a simulated re-mount) after the correction. All or nothing (AtomicDir).
#include <CLI/CLI.hpp>
#include <iostream>
#include <optional>

#include "analysis/calibrate_run.hpp"
#include "analysis/calibration_file.hpp"
#include "core/atomic_output.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "fields/field_factory.hpp"
#include "probe/common_keys.hpp"
#include "field_solver/field_io/solved_field.hpp"

namespace {


struct Flags {
  std::string measured, correction, apply, method;
  std::string field = "analytic";
  std::optional<std::string> array, r0;
  int error_sign = 1;
  std::string interp = "cubic";
};

int run(int argc, char** argv) {
  CLI::App app{"calibrate: the factory correction as a firmware table, and the residual after a change (docs/interfaces.md)"};
  magenc::CommonOptions common;
  Flags f;
  const auto schema = magenc::merge_schemas(magenc::common_keys(), magenc::calibration_keys());
  magenc::add_common_options(app, common, schema);
  app.add_option("--measured", f.measured, "calibration curve CSV: theta_deg,error_deg | theta_deg,phi_deg | theta_deg,u_cos,u_sin");
  app.add_option("--correction", f.correction, "a correction.csv written before (instead of calibrating)");
  app.add_option("--method", f.method, "none, harmonics:N, lut:K, ogp (calibration.method)");
  app.add_option("--apply", f.apply, "a curve CSV to correct, or 'run': the configured mount after the correction");
  app.add_option("--field", f.field, "field source of the simulated states: analytic, linear, grid:FILE.vti, table:FILE, fem:DIR");
  app.add_option("--array", f.array, "probe array (sensor.array)");
  app.add_option("--r0", f.r0, "probe radius r0 in mm (sensor.r0_mm)");
  app.add_option("--error-sign", f.error_sign, "+1: error_deg = sensor - reference (default); -1: the opposite");
  app.add_option("--interp", f.interp, "grid interpolation: nearest, linear, cubic (grid:/table: only; default cubic)")
      ->check(CLI::IsMember({"nearest", "linear", "cubic"}));
  magenc::parse_cli(app, argc, argv);
  const magenc::CalibrateRequest req{f.measured, f.correction, f.apply, f.error_sign};

  // 1. Configuration.
  magenc::Config cfg = magenc::load_config(schema, common);
  if (f.array) cfg.set("sensor.array=" + *f.array);
  if (f.r0) cfg.set("sensor.r0_mm=" + *f.r0);
  if (!f.method.empty()) cfg.set("calibration.method=" + f.method);
  const std::string what = f.array ? "--array" : "sensor.array";
  const magenc::ProbeSetup setup = magenc::sensor_setup_from_config(cfg, cfg.str("sensor.array"), what);
  magenc::FieldSourcePtr field;
  const magenc::FieldGetter the_field = [&]() -> const magenc::FieldSource& {
    if (!field) {
      magenc::FieldOptions fo;
      fo.interp = magenc::parse_interp(f.interp, "--interp");
      field = magenc::open_field_source(f.field, cfg, fo);
    }
    return *field;
  };

  // 2. The correction.
  const magenc::CalibrationSource cs = magenc::calibrate_correction(req, cfg, what, the_field);
  const magenc::Correction& corr = cs.correction;

  // 3. The residual of another curve.
  std::optional<magenc::CalibrationResidual> residual;
  if (!f.apply.empty()) residual = magenc::calibrate_residual(req, corr, cfg, setup, the_field);

  // 4. Outputs, all or nothing.
  magenc::AtomicDir out(common.out.empty() ? std::string("output/calibrate") : common.out);
  magenc::write_file_atomic(out / "correction.csv", magenc::correction_csv(corr));
  magenc::write_file_atomic(out / "correction.json", magenc::correction_json(corr));
  magenc::write_file_atomic(out / "config.toml", cfg.to_toml());
  if (residual) {
    magenc::write_file_atomic(out / "residual.csv", residual->csv());
    magenc::write_file_atomic(out / "residual.json", residual->json());
  }
  out.commit();
  std::cout << "calibrate: " << corr.method.name() << " from " << cs.source;
  if (residual) std::cout << "; residual of " << f.apply << " in residual.json";
  std::cout << "; results in " << out.final_path().string() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return magenc::run_main("calibrate", [&] { return run(argc, argv); });
}
