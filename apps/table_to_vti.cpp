// table_to_vti: converts a field table from another tool (docs/interfaces.md,
// "Field tables from other tools": COMSOL, Ansys Maxwell, FEMM or a magnet
// maker's text table of B on a regular grid) into VTK image data (.vti) for
// ParaView, with the point arrays of solve_field's grids: `Bz` (T) and, when
// the table has Bx and By, `B` (T, 3 components); coordinates in mm, magnet
// frame. The table is read and checked exactly as `--field table:FILE` reads
// it (src/fields/field_table.hpp); a table without a z column is placed at the
// configured sensing plane z_s (--config/--set magnet.height_mm,
// sensor.plane_height_mm).
//
//   table_to_vti --table FILE [--out FILE.vti] [--config F.toml] [--set key=value]...
//
// --out defaults to the table's path with the extension .vti. The output is
// written atomically (temporary name, then rename); a bad table is one line on
// stderr, exit code 2, and no output file.
// Example: table_to_vti --table maker_Bz.csv --out output/maker_Bz.vti
#include <CLI/CLI.hpp>
#include <iostream>

#include "core/cli.hpp"
#include "core/errors.hpp"
#include "fields/field_table.hpp"
#include "fields/magnet.hpp"
#include "probe/common_keys.hpp"

namespace {

int run(int argc, char** argv) {
  // 1. Options.
  CLI::App app{"Converts a field table (text, regular grid of B; docs/interfaces.md) to a .vti for ParaView"};
  magenc::CommonOptions common;
  std::string table;
  const auto schema = magenc::common_keys();
  magenc::add_common_options(app, common, schema);
  app.add_option("--table", table, "field table: x_mm|x_m, y_*, [z_*], Bz_T|Bz_mT, [Bx_*, By_*] columns")->required();
  magenc::parse_cli(app, argc, argv);
  const magenc::Config cfg = magenc::load_config(schema, common);

  // 2. Read and check the table (z of a 2-D table: the configured sensing plane).
  const magenc::GridData grid = magenc::read_field_table(table, magenc::sensing_plane_z_mm(cfg), magenc::field_table_limits(cfg));

  // 3. Write the .vti atomically.
  std::filesystem::path out = common.out;
  if (out.empty()) out = std::filesystem::path(table).replace_extension(".vti");
  if (out == std::filesystem::path(table))
    throw magenc::InputError("--out " + out.string() + " is the table itself: allowed another file name");
  magenc::write_grid_vti(out, grid, {.compress = true, .base64 = true, .with_bz = true});  // zlib, base64
  std::cout << out.string() << ": " << grid.dims[0] << " x " << grid.dims[1] << " x " << grid.dims[2] << " nodes, "
            << (grid.has_B() ? "B and Bz" : "Bz only") << ", origin (" << grid.origin_mm.x() << ", "
            << grid.origin_mm.y() << ", " << grid.origin_mm.z() << ") mm, spacing (" << grid.spacing_mm.x() << ", "
            << grid.spacing_mm.y() << ", " << (grid.is_plane() ? 0.0 : grid.spacing_mm.z()) << ") mm\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return magenc::run_main("table_to_vti", [&] { return run(argc, argv); });
}
