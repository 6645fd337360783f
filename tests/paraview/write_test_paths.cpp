// Test helper for the ParaView state test (tests/paraview/check_states.py):
// writes the probe paths of one mounting case as a .vtp through the library
// call the studies use (magenc::write_probe_paths_vtp), with Bz from any
// field source error_spectrum accepts.
//
//   magenc_write_test_paths [--field analytic|grid:FILE.vti|...] [--config F]
//                           [--set key=value]... --out FILE.vtp
// The mounting case, probe array, r0 and steps come from the config keys
// (mount.*, sensor.*), e.g. --set mount.sx_mm=0.3 --set mount.dx_mm=0.2.
#include <CLI/CLI.hpp>

#include "probe/angle_error.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "fields/field_factory.hpp"
#include "fields/magnet.hpp"
#include "io/probe_paths_vtk.hpp"
#include "probe/common_keys.hpp"

namespace {

int run(int argc, char** argv) {
  // 1. Options and configuration.
  CLI::App app{"Writes probe paths (.vtp) of one mounting case for the ParaView state test"};
  magenc::CommonOptions common;
  std::string field_spec = "analytic";
  const auto schema = magenc::common_keys();
  magenc::add_common_options(app, common, schema);
  app.add_option("--field", field_spec, "field source (as error_spectrum --field), default analytic");
  magenc::parse_cli(app, argc, argv);
  if (common.out.empty()) throw magenc::InputError("--out FILE.vtp is required");
  const magenc::Config cfg = magenc::load_config(schema, common);

  // 2. Probe setup, mount and field, as error_spectrum builds them.
  magenc::ProbeSetup setup;
  setup.array = magenc::ProbeArray::parse(cfg.str("sensor.array"));
  setup.r0_mm = cfg.real("sensor.r0_mm");
  setup.steps = static_cast<int>(cfg.integer("sensor.steps"));
  setup.plane_z_mm = magenc::sensing_plane_z_mm(cfg);
  setup.chain = magenc::SignalChain::from_config(cfg);
  setup.magnet_height_mm = cfg.real("magnet.height_mm");
  const magenc::Mount mount = magenc::Mount::from_config(cfg);
  const magenc::FieldSourcePtr field = magenc::make_field_source(field_spec, cfg);

  // 3. Paths and readings, written through the library call error_spectrum --paths uses.
  const magenc::AngleErrorResult res = magenc::angle_error(*field, setup, mount);
  magenc::write_case_probe_paths_vtp(common.out, setup, mount, res);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return magenc::run_main("magenc_write_test_paths", [&] { return run(argc, argv); });
}
