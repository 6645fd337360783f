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
#include <sstream>

#include "analysis/calibration.hpp"
#include "analysis/calibration_file.hpp"
#include "analysis/measured_curve.hpp"
#include "core/atomic_output.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "fields/field_factory.hpp"
#include "probe/common_keys.hpp"
#include "solved_field.hpp"

namespace {

using magenc::InputError;

struct Flags {
  std::string measured, correction, apply, method;
  std::string field = "analytic";
  std::optional<std::string> array, r0;
  int error_sign = 1;
  std::string interp = "cubic";
};

std::string g10(double v) { return magenc::fmt_sig(v, 10); }

// The residual summary: pp before and after, and the least-squares harmonics 1..8 of the residual.
std::string residual_json(const std::string& source, const std::string& method, const Eigen::VectorXd& theta,
                          const Eigen::VectorXd& eps, const Eigen::VectorXd& res) {
  std::ostringstream os;
  const Eigen::VectorXd h = magenc::harmonics_ls(theta, res, magenc::kHarmonics);
  os << "{\n  \"curve\": \"" << source << "\",\n  \"method\": \"" << method << "\",\n  \"samples\": " << theta.size()
     << ",\n  \"pp_before_deg\": " << g10(eps.maxCoeff() - eps.minCoeff())
     << ",\n  \"pp_after_deg\": " << g10(res.maxCoeff() - res.minCoeff()) << ",\n  \"mean_after_deg\": " << g10(res.mean())
     << ",\n  \"c_after_deg\": [";
  for (int n = 1; n <= magenc::kHarmonics; ++n) os << (n > 1 ? ", " : "") << g10(magenc::harmonic_amplitude(h, n));
  os << "]\n}\n";
  return os.str();
}

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
  if (!f.measured.empty() && !f.correction.empty())
    throw InputError("--measured and --correction both give the correction: allowed one of the two");
  if (f.error_sign != 1 && f.error_sign != -1) throw InputError("--error-sign " + std::to_string(f.error_sign) + ": allowed +1 or -1");

  // 1. Configuration.
  magenc::Config cfg = magenc::load_config(schema, common);
  if (f.array) cfg.set("sensor.array=" + *f.array);
  if (f.r0) cfg.set("sensor.r0_mm=" + *f.r0);
  if (!f.method.empty()) cfg.set("calibration.method=" + f.method);
  const magenc::CalibrationMethod method = magenc::calibration_method(cfg);
  const std::string what = f.array ? "--array" : "sensor.array";
  const magenc::ProbeSetup setup = magenc::sensor_setup_from_config(cfg, cfg.str("sensor.array"), what);
  const int turns = magenc::electrical_turns(setup.principle);
  magenc::CurveReadOptions ro;
  ro.error_sign = f.error_sign;
  magenc::FieldSourcePtr field;
  auto the_field = [&]() -> const magenc::FieldSource& {
    if (!field) {
      magenc::FieldOptions fo;
      fo.interp = magenc::parse_interp(f.interp, "--interp");
      field = magenc::open_field_source(f.field, cfg, fo);
    }
    return *field;
  };

  // 2. The correction.
  magenc::Correction corr;
  std::string source;
  if (!f.correction.empty()) {
    corr = magenc::read_correction_csv(f.correction);
    source = f.correction;
  } else {
    if (method.none())
      throw InputError("calibration.method = none: allowed harmonics:N, lut:K or ogp (--method), or --correction FILE");
    if (!f.measured.empty()) {
      const magenc::MeasuredCurve c = magenc::read_measured_curve(f.measured, ro);
      if (method.kind == magenc::CalibrationKind::Ogp) {
        if (c.format != "raw")
          throw InputError("--method ogp needs the raw channels: " + f.measured + " has " + c.format +
                           ", allowed a curve with header theta_deg,u_cos,u_sin");
        corr = magenc::correct_channels(c.channels, turns);
      } else {
        corr = magenc::correct_pairs(method, c.theta_deg + c.error_deg, c.error_deg, turns);
      }
      source = f.measured;
    } else {
      corr = magenc::correction_from_config(the_field(), cfg, cfg.str("sensor.array"), what);
      source = "simulated calibration.at";
    }
  }

  // 3. The residual of another curve.
  std::optional<std::string> res_csv, res_json;
  if (!f.apply.empty()) {
    Eigen::VectorXd theta, eps, res;
    if (f.apply == "run") {
      magenc::AngleErrorResult r = magenc::angle_error(the_field(), setup, magenc::Mount::from_config(cfg));
      theta = r.theta_deg;
      eps = r.eps_deg;
      res = magenc::residual_deg(corr, r);
    } else {
      const magenc::MeasuredCurve c = magenc::read_measured_curve(f.apply, ro);
      theta = c.theta_deg;
      eps = c.error_deg;
      if (corr.method.kind == magenc::CalibrationKind::Ogp) {
        if (c.format != "raw")
          throw InputError("an ogp correction applies to raw channels: " + f.apply + " has " + c.format +
                           ", allowed a curve with header theta_deg,u_cos,u_sin");
        res.resize(theta.size());
        for (Eigen::Index i = 0; i < theta.size(); ++i)
          res[i] = magenc::wrap_deg(corr.ellipse.angle_deg(c.channels(i, 0), c.channels(i, 1)) - corr.turns * theta[i]) /
                   corr.turns;
      } else {
        res = magenc::residual_of_pairs(corr, theta, eps);
      }
    }
    std::ostringstream os;
    os << "theta_deg,error_deg,residual_deg\n";
    for (Eigen::Index i = 0; i < theta.size(); ++i) os << g10(theta[i]) << "," << g10(eps[i]) << "," << g10(res[i]) << "\n";
    res_csv = os.str();
    res_json = residual_json(f.apply, corr.method.name(), theta, eps, res);
  }

  // 4. Outputs, all or nothing.
  magenc::AtomicDir out(common.out.empty() ? std::string("output/calibrate") : common.out);
  magenc::write_file_atomic(out / "correction.csv", magenc::correction_csv(corr));
  magenc::write_file_atomic(out / "correction.json", magenc::correction_json(corr));
  magenc::write_file_atomic(out / "config.toml", cfg.to_toml());
  if (res_csv) {
    magenc::write_file_atomic(out / "residual.csv", *res_csv);
    magenc::write_file_atomic(out / "residual.json", *res_json);
  }
  out.commit();
  std::cout << "calibrate: " << corr.method.name() << " from " << source;
  if (res_json) std::cout << "; residual of " << f.apply << " in residual.json";
  std::cout << "; results in " << out.final_path().string() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return magenc::run_main("calibrate", [&] { return run(argc, argv); });
}
