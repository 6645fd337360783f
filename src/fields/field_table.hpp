// Field tables from other tools (docs/interfaces.md, "Field tables from other
// tools" and "Field files as other tools write them"): a text table of B on a
// regular grid, as exported by COMSOL, Ansys Maxwell, FEMM or a magnet maker,
// read into the GridData of grid_field.hpp so that GridField (and its
// nearest/linear/cubic interpolation) serves it. Lines, cells and numbers are
// read by core/text_table.hpp (a UTF-8 byte-order mark, CRLF or CR line ends,
// ';' between fields with decimal commas, tab, ',' or blanks, quoted cells).
//
// Three formats, recognised from the content:
//   - magenc's table: '#'/'%' comment lines, then one header row naming the
//     columns (any order, each at most once):
//       x_mm | x_m,  y_mm | y_m,  [z_mm | z_m]          coordinates, magnet frame
//       Bz_T | Bz_mT, [Bx_T | Bx_mT, By_T | By_mT]     field (Bx and By together)
//     All coordinates in one unit, all field columns in one unit.
//   - COMSOL's spreadsheet export: '%' header lines, then rows of numbers. The
//     coordinate unit is the '% Length unit:' line's (m, cm, mm, um), or a
//     "(mm)" after a coordinate's name; the last '%' line names the columns:
//     x, y, [z] (any case) and <interface>.Bz (T|mT) [with .Bx, .By], e.g.
//     "% x  y  z  mf.Bz (T)". Missing length unit or field unit: refused.
//   - Ansys Maxwell's grid export (.fld): header lines with Min:, Max: and
//     Grid Size: (three lengths each, in m, or each with a unit: "[-5mm ...]";
//     one line "Grid Output Min: [..] Max: [..] Grid Size: [..]" or three),
//     an optional quantity line (X,Y,Z,Vector data "<Bx,By,Bz>" or
//     X,Y,Z,Scalar data "Bz"), then rows x y z (m) and Bz, or x y z Bx By Bz
//     (T): 4 columns are Bz, 6 are B. The rows must lie on the declared grid
//     (else their unit cannot be told: refused).
//   - Every data row has one finite number per column.
//   - Rows in any order; the points must fill a regular grid exactly once.
//
// Regular grid (per axis): the distinct coordinate values, merged when they
// differ by <= 1e-9 of their size or of the axis's median |coordinate| (printing
// noise; a far extra point does not widen it), are the levels; the
// spacing h is the median gap between neighbouring levels; every level must
// lie within kLatticeTol (1e-3) of a cell of level_0 + i*h. The lattice
// indices of the rows then must cover the box of indices exactly once.
// Errors (InputError, one line "table FILE line N: ...") name the first
// offending row: an unreadable cell, a non-finite value, a coordinate off the
// lattice, a point that repeats an earlier one, a point separated from the
// rest of the grid by empty grid lines (an extra point); or, when the rows
// are consistent but incomplete, the first missing point (x, y, z).
//
// Geometry: coordinates are in the magnet frame of docs/physics.md (origin at the
// magnet's centre). A table without a z column is the plane z = plane_z_mm
// (the configured z_s; it serves dz = 0 only). A table with a z column and
// one z level is the plane at that z; with several levels it is a 3-D box.
#pragma once
#include <filesystem>
#include <istream>
#include <memory>
#include <string>

#include "core/config.hpp"
#include "fields/grid_field.hpp"

namespace magenc {

// Plausibility of a table's numbers against the units its header claims (InputError naming the column or
// axis and the range otherwise). The largest |B| of the table between 1 mT and 1 T by default: a magnet's
// field at an encoder's sensor is 1 to 500 mT, so tesla under a mT header (read 1 uT to 0.5 mT) falls below,
// mT under a T header (1 to 500 T) above, and so do all zeros and a 1e300 node. A legitimate table outside
// it (a weak stray field; points at a magnet's face or in steel, above 1 T) sets the keys
// checks.largest_field_min_mT and checks.largest_field_max_T (field_check_keys). The grid at most 1000 mm
// across on every axis (mm numbers under an m header or a COMSOL '% Length unit: m' make it 1000 times
// larger) and its spacing at least 1e-3 mm (m numbers under an mm header).
constexpr double kFieldTableMinFieldMax_T = 1e-3;
constexpr double kFieldTableMaxField_T = 1.0;
constexpr double kFieldTableMaxExtent_mm = 1000.0;
constexpr double kFieldTableMinSpacing_mm = 1e-3;

// Limits on what a table may declare (file size, nodes) and the window of its largest |B|.
struct FieldTableLimits {
  std::uintmax_t max_bytes = std::uintmax_t(1) << 30;  // 1 GiB of text
  std::size_t max_nodes = std::size_t(1) << 24;        // 16.8 M grid nodes (~0.8 GB as doubles)
  double largest_field_min_T = kFieldTableMinFieldMax_T;
  double largest_field_max_T = kFieldTableMaxField_T;
};

// The keys checks.largest_field_min_mT and checks.largest_field_max_T (field tables and scans).
std::vector<KeySpec> field_check_keys();
// The limits with the window of cfg's checks.* keys (the defaults where cfg does not declare them);
// InputError when the window is empty.
FieldTableLimits field_table_limits(const Config& cfg);
// "allowed a largest |B| between 1 mT and 1 T" for messages.
std::string largest_field_range_text(const FieldTableLimits& limits);

// Tolerance, in cells, for coordinates off the regular lattice.
constexpr double kLatticeTol = 1e-3;


// Parses a table's text; `source` names it in messages ("table FILE").
// plane_z_mm: height of a table without a z column (magnet frame, mm).
GridData parse_field_table(const std::string& text, const std::string& source, double plane_z_mm,
                           const FieldTableLimits& limits = {});

// Reads and parses a table file (InputError when missing, unreadable, larger
// than limits.max_bytes, or malformed).
GridData read_field_table(const std::filesystem::path& file, double plane_z_mm,
                          const FieldTableLimits& limits = {});

// A GridField named "table" serving the file, z of a 2-D table = the
// configured sensing plane (sensing_plane_z_mm(cfg)). A table that is a single
// plane at a height other than z_s is refused (it could serve no probe).
std::shared_ptr<GridField> table_field_from_file(const std::filesystem::path& file, const Config& cfg, Interp mode);

// Writing tables (for tests, examples and users who want a reference table).
struct FieldTableFormat {
  char separator = ',';          // ',', '\t' or ' '
  bool metres = false;           // coordinates in m (x_m) instead of mm
  bool millitesla = false;       // field in mT (Bz_mT) instead of T
  bool with_z = true;            // z column (always for 3-D grids)
  bool with_B = true;            // Bx, By columns (when the grid has them)
  std::string comment;           // written as '# ' lines before the header (may be empty)
};
// The grid's nodes as a table, one row per node in node order (i fastest),
// values with 17 significant digits.
std::string field_table_text(const GridData& grid, const FieldTableFormat& format = {});

}  // namespace magenc
