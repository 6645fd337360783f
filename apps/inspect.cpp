// inspect: a magnet's polarization and a sensor's pose from a measured 3-axis field scan (docs/interfaces.md
// "inspect"): fits offset, rotation, polarization magnitude and/or direction (analysis/inspect_fit.hpp) with
// 1-sigma uncertainties and what the scan cannot separate; writes DIR/fit.json, fit.csv, summary.md,
// components.png, config.toml, all or nothing (AtomicDir).
//
//   inspect --scan FILE.csv [--free offset,rotation,polarization,direction] [--cond-limit C]
//           [--config F] [--set k=v]... --out DIR
//
// Scan CSV: x_mm,y_mm,z_mm (nominal positions, magnet frame) and Bx_mT,By_mT,Bz_mT (or _T), the readings in
// the sensor's axes. The magnet's size and nominal polarization are the [magnet] keys.
// Example: inspect --scan scan.csv --free offset,rotation,polarization,direction --out output/inspect
#include <CLI/CLI.hpp>
#include <iostream>

#include "analysis/inspect_run.hpp"
#include "core/atomic_output.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "probe/common_keys.hpp"
#include "report/inspect_report.hpp"

namespace {

int run(int argc, char** argv) {
  CLI::App app{"inspect: magnet polarization and sensor pose from a 3-axis field scan (docs/interfaces.md)"};
  magenc::CommonOptions common;
  std::string scan_file, free = "offset,rotation,polarization";
  double cond_limit = 1e6;
  const auto schema = magenc::common_keys();
  magenc::add_common_options(app, common, schema);
  app.add_option("--scan", scan_file, "scan CSV: x_mm,y_mm,z_mm,Bx_mT,By_mT,Bz_mT (or _T)")->required();
  app.add_option("--free", free, "free groups: offset, rotation, polarization, direction (default the first three)");
  app.add_option("--cond-limit", cond_limit, "condition number above which directions count as not identifiable (default 1e6)");
  magenc::parse_cli(app, argc, argv);

  const magenc::Config cfg = magenc::load_config(schema, common);
  const magenc::InspectRun run = magenc::run_inspect({scan_file, free, cond_limit, "--free", "--cond-limit"}, cfg);
  const magenc::FieldScan& scan = run.scan;
  const magenc::InspectResult& res = run.result;

  magenc::InspectRunInfo info;
  for (int i = 0; i < argc; ++i) info.command_line += (i ? " " : "") + std::string(argv[i]);
  info.scan_file = scan_file;
  info.unit = run.unit;
  info.config_json = cfg.to_json();
  info.config_toml = cfg.to_toml();
  magenc::AtomicDir out(common.out.empty() ? std::string("output/inspect") : common.out);
  magenc::write_inspect_outputs(out.path(), scan, res, info);
  out.commit();
  std::cout << "inspect: residual RMS " << res.residual_rms_mT << " mT; results in " << out.final_path().string()
            << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return magenc::run_main("inspect", [&] { return run(argc, argv); }); }
