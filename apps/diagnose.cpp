// diagnose: from measured angle-error curves back to their causes (docs/interfaces.md, "Measured error curves
// and diagnose"). Reads one or more measured curves, fits the chosen model parameters (mounting offsets,
// tilts, signal-chain errors) plus a free zero offset per curve by nonlinear least squares (Ceres), and
// reports values with 1-sigma uncertainties, correlations, what the data cannot separate, and the residual.
//
//   diagnose --measured FILE.csv [--measured FILE2.csv]... --field F --array A --r0 MM
//            [--free sx,sy,...] [--curve-set N:key=value | N:key+=value]... [--fixed-zero]
//            [--error-sign +1|-1] [--max-gap DEG] [--starts K] [--seed S] [--cond-limit C]
//            [--interp nearest|linear|cubic] [--config F] [--set k=v]... --out DIR
//
// Writes DIR/fit.json, fit.csv, summary.md, fit.png, harmonics.png, config.toml (src/report/diagnosis_report.hpp),
// all or nothing (AtomicDir). Example:
//   diagnose --measured curve.csv --field analytic --array two --r0 2.4 --out output/diagnose
#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>
#include <optional>
#include <sstream>

#include "analysis/diagnose_run.hpp"
#include "core/atomic_output.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/omp_wait.hpp"
#include "probe/common_keys.hpp"
#include "report/diagnosis_report.hpp"
#include "report/study_output.hpp"

namespace {

using magenc::InputError;

// The command line's own shorthands; everything else goes straight into the diagnose request.
struct Shorthands {
  std::optional<std::string> array, r0;  // sensor.array, sensor.r0_mm
  std::string free;                      // --free list (empty: default set)
};

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  for (std::string x; std::getline(ss, x, ',');)
    if (!x.empty()) v.push_back(x);
  return v;
}

std::string help_footer() {
  std::ostringstream os;
  os << "\nFit parameters (--free names; --curve-set keys):\n";
  for (const auto& p : magenc::fit_parameters())
    os << "  " << p.name << "  (" << p.key << ", " << (p.unit.empty() ? "-" : p.unit) << ", bounds [" << p.lower
       << ", " << p.upper << "], typical " << p.scale << "): " << p.what << "\n";
  os << "  magnet_tilt = magnet_tilt_x,magnet_tilt_y (fit.json also gives magnet_tilt_deg and its azimuth).\n"
        "  Not fitted: magnet.magnetization_elevation_deg (a property of the field; for `two` it acts like\n"
        "  offset_cos = offset_sin, for diff4/ring:N it has no effect).\n"
        "  plus a free zero offset (DC) between the two encoders per curve, unless --fixed-zero.\n"
        "Measured curve CSV (header row): theta_deg,error_deg | theta_deg,phi_deg | theta_deg,u_cos,u_sin;\n"
        "  >= 64 rows, one full turn or more (folded mod 360), largest gap <= --max-gap deg; '#' comments.\n"
        "  error_deg = sensor - reference; --error-sign -1 when the file has reference - sensor.\n"
        "Several curves: one joint fit, shared parameters, one zero offset each. Per-curve known values:\n"
        "  --curve-set 2:mount.dz_mm+=0.5   curve 2 was measured with the air gap 0.5 mm larger (shift)\n"
        "  --curve-set 2:mount.sx_mm=0.2    curve 2 has sx = 0.2 mm exactly (known, not fitted there)\n";
  return os.str();
}

int run(int argc, char** argv) {
  const auto t0 = std::chrono::steady_clock::now();
  // 1. Options.
  CLI::App app{"diagnose: fit mounting and signal-chain errors to measured angle-error curves (docs/interfaces.md)"};
  magenc::CommonOptions common;
  Shorthands f;
  magenc::DiagnoseRequest req;  // its defaults are the flags'
  const auto schema = magenc::common_keys();
  magenc::add_common_options(app, common, schema);
  app.footer(app.get_footer() + help_footer());
  app.add_option("--measured", req.measured, "measured curve CSV (repeatable: joint fit)")->required();
  app.add_option("--field", req.field, "field source, as for error_spectrum: analytic, linear, grid:FILE.vti, fem:DIR (default analytic)");
  app.add_option("--array", f.array, "probe array: two, diff4, ring:N (sensor.array)");
  app.add_option("--r0", f.r0, "probe radius r0 in mm (sensor.r0_mm)");
  app.add_option("--free", f.free, "comma-separated parameters to fit (default: what the curves can identify)");
  app.add_option("--curve-set", req.curve_sets, "per-curve known value: N:key=value or N:key+=value (repeatable)");
  app.add_flag("--fixed-zero", req.fixed_zero, "no free zero offset between the encoders (default: free DC)");
  app.add_option("--error-sign", req.error_sign, "+1: error_deg = sensor - reference (default); -1: the opposite");
  app.add_option("--max-gap", req.max_gap_deg, "largest allowed gap between samples in deg (default 30)");
  app.add_option("--starts", req.starts, "start points of the fit (default 6; 1 = configured values only)");
  app.add_option("--seed", req.seed, "seed of the random starts (default 1)");
  app.add_option("--cond-limit", req.cond_limit, "condition number above which directions count as not identifiable (default 1e4)");
  app.add_option("--fd-step", req.fd_step, "central-difference step in typical sizes (default 1e-4 exact field, 1e-2 fem:/grid:)");
  app.add_option("--interp", req.interp, "grid interpolation: nearest, linear, cubic (grid:/table: only; default cubic)")
      ->check(CLI::IsMember({"nearest", "linear", "cubic"}));
  magenc::parse_cli(app, argc, argv);

  // 2. Configuration, curves and field (all read and checked before any output exists), then the fit.
  magenc::Config cfg = magenc::load_config(schema, common);
  if (f.array) cfg.set("sensor.array=" + *f.array);
  if (f.r0) cfg.set("sensor.r0_mm=" + *f.r0);
  req.free = split_commas(f.free);
  req.array_name = f.array ? "--array" : "sensor.array";
  const magenc::DiagnoseRun run = magenc::run_diagnose(req, cfg);
  const auto& curves = run.curves;
  const magenc::DiagnosisResult& res = run.result;

  // 3. Outputs, all or nothing.
  magenc::DiagnosisRunInfo info;
  for (int i = 0; i < argc; ++i) info.command_line += (i ? " " : "") + std::string(argv[i]);
  info.field_spec = req.field;
  info.config_json = cfg.to_json();
  info.config_toml = cfg.to_toml();
  info.curve_sets = req.curve_sets;
  info.options = run.options;
  info.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  magenc::AtomicDir out(common.out.empty() ? std::string("output/diagnose") : common.out);
  magenc::write_diagnosis_outputs(out.path(), curves, res, info);
  out.commit();
  if (!res.converged)
    std::cerr << "diagnose: warning: the best start stopped at its iteration cap before converging (" << res.termination
              << "): fit.json has \"converged\": false; its values may not be the minimum\n";
  std::cout << "diagnose: residual RMS " << res.residual_rms_deg << " deg; results in " << out.final_path().string()
            << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  magenc::prefer_passive_omp_wait(argc, argv);  // many small parallel regions (core/omp_wait.hpp)
  return magenc::run_main("diagnose", [&] { return run(argc, argv); });
}
