// error_spectrum: angle-error spectra of a magnetic encoder for one mounting
// case (flags) or many (--cases FILE.csv), docs/interfaces.md.
//
//   error_spectrum --field linear|analytic|grid:FILE.vti|table:FILE|fem:DIR
//                  --array two|diff4|ring:N|point  --r0 MM  [--principle bz|inplane|xmr|amr]
//                  [--sx MM] [--sy MM] [--dx MM] [--dy MM] [--dz MM]
//                  [--cases FILE.csv] [--steps M] [--interp nearest|linear|cubic]
//                  [--config F.toml] [--set key=value]... [--out FILE.csv]
//                  [--paths FILE.vtp]
//
// Flags are shorthands for config keys (--r0 -> sensor.r0_mm, --array ->
// sensor.array, --principle -> sensor.principle, --steps -> sensor.steps,
// --sx.. --dz -> mount.*) applied after
// --config and --set, so the config's range checks apply to them. With
// --cases, each row is a complete mount (missing columns = 0) and the mount
// flags/keys are not used; combining --cases with --sx..--dz is an error.
// --field defaults to analytic; --interp (default cubic) applies to grid: fields.
// Tilts, magnetization elevation and the signal chain (docs/physics.md "Beyond the
// five offsets") come through --config/--set (mount.tilt_x_deg, ...,
// magnet.magnetization_elevation_deg, sensor.offset_cos_mT, ...) or, for the
// tilts, as --cases columns; when any case is tilted the table gains the
// columns tilt_x_deg,tilt_y_deg,magnet_tilt_deg,magnet_tilt_azimuth_deg.
// Every table then ends with the field-window columns principle,
// field_min_mT,field_max_mT,in_window (docs/physics.md "Sensor principles": the
// extremes of the magnitude the principle uses; in_window 1 or 0 against
// sensor.field_min_mT/field_max_mT, always 1 when no window is set).
// The in-plane principles (inplane, xmr, amr) use the array point (the
// default array two stands for it; an explicit --array two is refused).
// Writes the spectra table to --out atomically, or to stdout. --paths (one
// case only) also writes the probe paths of that case as .vtp polylines with
// Bz and theta_deg (src/io/probe_paths_vtk.hpp; ParaView's probe_paths.pvsm).
// Example: error_spectrum --field analytic --array two --r0 2.4 --dx 0.1
#include <CLI/CLI.hpp>
#include <iostream>
#include <optional>

#include "analysis/calibration.hpp"
#include "probe/angle_error.hpp"
#include "core/atomic_output.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "probe/common_keys.hpp"
#include "field_solver/field_io/solved_field.hpp"
#include "fields/field_factory.hpp"
#include "fields/magnet.hpp"
#include "io/probe_paths_vtk.hpp"
#include "io/tables.hpp"
#include "probe/nonius.hpp"

namespace {

using magenc::Config;
using magenc::InputError;

// Command-line flags (all text, parsed by the config or the probe-array parser).
struct Flags {
  std::string field = "analytic";          // --field
  std::optional<std::string> array, principle, r0, steps, sx, sy, dx, dy, dz;  // config shorthands
  std::string cases;                        // --cases FILE.csv (empty: one case)
  std::string interp = "cubic";            // --interp (grid: fields only)
  std::string paths;                        // --paths FILE.vtp (one case only; empty: none)
};

// Applies one flag as "key=text"; an invalid value is reported under the flag's name.
void apply_flag(Config& cfg, const std::string& flag, const std::string& key,
                const std::optional<std::string>& text) {
  if (!text) return;
  try {
    cfg.set(key + "=" + *text);
  } catch (const InputError&) {
    if (const magenc::KeySpec* s = cfg.find(key))
      throw InputError(flag + " " + *text + " (" + key + ") is invalid: allowed " + magenc::allowed_range(*s));
    throw;
  }
}

// A [nonius] track (docs/physics.md "Multipole rings and nonius"): the absolute reading on both rings' fields
// replaces the row's spectrum (a slip shows in it; ce1..ce4 stay the master track's incremental reading's)
// and adds nonius_margin_deg.
void add_nonius(const magenc::FieldSource& both, const magenc::ProbeSetup& setup, const magenc::NoniusTrack& track,
                const magenc::Mount& mount, magenc::SpectrumRow& row) {
  const magenc::NoniusResult n = magenc::nonius_reading(both, setup, magenc::nonius_setup(setup, track), mount);
  const magenc::Spectrum master = row.spectrum;
  row.spectrum = n.spectrum;
  row.spectrum.pole_pairs = master.pole_pairs;
  row.spectrum.ce_deg = master.ce_deg;
  row.extra.push_back({"nonius_margin_deg", magenc::fmt_sig(n.margin_deg, 10)});
}

void apply_flags(Config& cfg, const Flags& f) {
  apply_flag(cfg, "--array", "sensor.array", f.array);
  apply_flag(cfg, "--principle", "sensor.principle", f.principle);
  apply_flag(cfg, "--r0", "sensor.r0_mm", f.r0);
  apply_flag(cfg, "--steps", "sensor.steps", f.steps);
  apply_flag(cfg, "--sx", "mount.sx_mm", f.sx);
  apply_flag(cfg, "--sy", "mount.sy_mm", f.sy);
  apply_flag(cfg, "--dx", "mount.dx_mm", f.dx);
  apply_flag(cfg, "--dy", "mount.dy_mm", f.dy);
  apply_flag(cfg, "--dz", "mount.dz_mm", f.dz);
}

// The common and calibration keys, and [nonius]: it exists only where a second track is read (here and the
// multipole study); elsewhere its keys are unknown.
std::vector<magenc::KeySpec> error_spectrum_keys() {
  return magenc::merge_schemas(magenc::merge_schemas(magenc::common_keys(), magenc::calibration_keys()),
                               magenc::NoniusTrack::keys());
}

int run(int argc, char** argv) {
  // 1. Options.
  CLI::App app{"Angle-error spectra of a magnetic rotary encoder under mounting errors (docs/interfaces.md)"};
  magenc::CommonOptions common;
  Flags f;
  const auto schema = error_spectrum_keys();
  magenc::add_common_options(app, common, schema);
  app.add_option("--field", f.field, "field source: linear, analytic, grid:FILE.vti, table:FILE, fem:DIR (default analytic)");
  app.add_option("--array", f.array, "probe array: two, diff4, ring:N (principle bz); point (inplane, xmr, amr) (sensor.array)");
  app.add_option("--principle", f.principle, "sensing principle: bz, inplane, xmr, amr (sensor.principle)");
  app.add_option("--r0", f.r0, "probe radius r0 in mm (sensor.r0_mm)");
  app.add_option("--sx", f.sx, "static eccentricity x in mm (mount.sx_mm)");
  app.add_option("--sy", f.sy, "static eccentricity y in mm (mount.sy_mm)");
  app.add_option("--dx", f.dx, "dynamic eccentricity x in mm (mount.dx_mm)");
  app.add_option("--dy", f.dy, "dynamic eccentricity y in mm (mount.dy_mm)");
  app.add_option("--dz", f.dz, "air-gap offset in mm, + = farther (mount.dz_mm)");
  app.add_option("--cases", f.cases,
                 "CSV of mounting cases: columns sx_mm,sy_mm,dx_mm,dy_mm,dz_mm and optionally tilt_x_deg,tilt_y_deg,"
                 "magnet_tilt_deg,magnet_tilt_azimuth_deg (missing = 0)");
  app.add_option("--steps", f.steps, "samples M of theta per turn (sensor.steps, >= 16)");
  app.add_option("--interp", f.interp, "grid interpolation: nearest, linear, cubic (grid: and table: fields; default cubic)")
      ->check(CLI::IsMember({"nearest", "linear", "cubic"}));
  app.add_option("--paths", f.paths, "also write the probe paths of the (single) case as FILE.vtp (ParaView)");
  magenc::parse_cli(app, argc, argv);

  // 2. Configuration: defaults, --config, --set, then the flags.
  Config cfg = magenc::load_config(schema, common);
  apply_flags(cfg, f);
  const bool mount_flags = f.sx || f.sy || f.dx || f.dy || f.dz;
  if (!f.cases.empty() && mount_flags)
    throw InputError("--cases cannot be combined with --sx/--sy/--dx/--dy/--dz: allowed one of the two");
  if (!f.cases.empty() && !f.paths.empty())
    throw InputError("--paths writes one mounting case: it cannot be combined with --cases");

  // 3. Setup, mounting cases and field.
  const magenc::ProbeSetup setup =
      magenc::sensor_setup_from_config(cfg, cfg.str("sensor.array"), f.array ? "--array" : "sensor.array");
  if (!f.paths.empty() && magenc::reads_in_plane(setup.principle))
    throw InputError("--paths writes the Bz probe paths of a Hall array: allowed with sensor.principle = bz, not " +
                     magenc::principle_name(setup.principle));
  const std::vector<magenc::Mount> cases =
      f.cases.empty() ? std::vector<magenc::Mount>{magenc::Mount::from_config(cfg)}
                      : magenc::read_cases_csv(f.cases);
  magenc::FieldOptions field_opts;
  field_opts.interp = magenc::parse_interp(f.interp, "--interp");
  std::optional<magenc::NoniusTrack> track;
  if (magenc::NoniusTrack::present(cfg)) track = magenc::NoniusTrack::from_config(cfg);
  magenc::FieldSourcePtr field = magenc::open_field_source(f.field, cfg, field_opts);
  if (track) field = magenc::with_nonius(field, *track);  // both rings' fields at every probe
  // calibration.method: the correction taken at calibration.at; the table then describes the residual.
  const magenc::Correction correction = magenc::correction_from_config(
      *field, cfg, cfg.str("sensor.array"), f.array ? "--array" : "sensor.array");
  if (track && !correction.method.none())
    throw InputError("calibration.method = " + correction.method.name() +
                     " with a [nonius] track: the absolute reading is not corrected: allowed calibration.method = none");

  // 4. One spectrum per case (all computed before anything is written).
  std::vector<magenc::SpectrumRow> rows;
  std::optional<magenc::AngleErrorResult> single;  // the one case's full result, for --paths
  bool any_tilt = false;
  for (const auto& mount : cases) any_tilt = any_tilt || mount.tilted();
  for (const auto& mount : cases) {
    magenc::SpectrumRow row;
    row.field = field->name();
    row.array = setup.array.name;
    row.r0_mm = setup.array.is_point() ? 0.0 : setup.r0_mm;  // the point array has no radius
    row.mount = mount;
    if (any_tilt) {  // the tilts of each case, as extra columns after the standard ones
      auto g10 = [](double v) { return magenc::fmt_sig(v, 10); };
      row.extra = {{"tilt_x_deg", g10(mount.tilt_x_deg)},
                   {"tilt_y_deg", g10(mount.tilt_y_deg)},
                   {"magnet_tilt_deg", g10(mount.magnet_tilt_deg)},
                   {"magnet_tilt_azimuth_deg", g10(mount.magnet_tilt_azimuth_deg)}};
    }
    magenc::AngleErrorResult res = magenc::corrected(correction, magenc::angle_error(*field, setup, mount));
    row.spectrum = res.spectrum;
    auto g10 = [](double v) { return magenc::fmt_sig(v, 10); };
    if (!correction.method.none()) row.extra.push_back({"calibration", correction.method.name()});
    row.extra.push_back({"principle", magenc::principle_name(setup.principle)});
    row.extra.push_back({"field_min_mT", g10(res.field_min_mT)});
    row.extra.push_back({"field_max_mT", g10(res.field_max_mT)});
    row.extra.push_back({"in_window", res.in_window ? "1" : "0"});
    if (setup.speed.moving()) row.extra.push_back({"rpm", g10(setup.speed.rpm)});  // a run at speed
    if (track) add_nonius(*field, setup, *track, mount, row);
    if (!f.paths.empty()) single = std::move(res);
    rows.push_back(std::move(row));
  }

  // 5. Output: atomically to --out (or stdout) and --paths.
  if (single) magenc::write_case_probe_paths_vtp(f.paths, setup, cases.front(), *single);
  const std::string table = magenc::spectra_csv(rows);
  if (common.out.empty()) {
    std::cout << table;
  } else {
    magenc::write_file_atomic(common.out, table);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return magenc::run_main("error_spectrum", [&] { return run(argc, argv); });
}
