#include "fields/field_table.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"
#include "core/text_table.hpp"
#include "fields/magnet.hpp"

namespace magenc {

namespace {

const char* const kAllowedColumns =
    "allowed columns x_mm|x_m, y_mm|y_m, optional z_mm|z_m, Bz_T|Bz_mT, optional Bx_T|Bx_mT with By_T|By_mT";
const char* const kOtherFormats =
    "or a COMSOL export ('%' header lines with '% Length unit:' and the column names) or an Ansys .fld "
    "(Min:, Max:, Grid Size: lines)";

// Column roles in a table.
enum Col { X = 0, Y, Z, BX, BY, BZ, kCols };
const char* const kColName[kCols] = {"x", "y", "z", "Bx", "By", "Bz"};

// One column: its role, the scale of its numbers to mm or T, its unit and its name as written.
struct ColumnSpec {
  int role = kCols;
  double scale = 1.0;
  std::string unit;
  std::string name;
};

// The columns of a table, checked: each role at most once, x, y and Bz present, Bx and By together,
// one unit for all coordinates and one for all field columns. at: "table FILE line N".
void check_columns(const std::vector<ColumnSpec>& cols, const std::string& at, const std::string& allowed) {
  int col_of[kCols];
  std::fill(col_of, col_of + kCols, -1);
  std::string unit_len, unit_B;
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const ColumnSpec& s = cols[c];
    if (col_of[s.role] >= 0)
      throw InputError(at + ": column " + kColName[s.role] + " appears twice ('" + cols[col_of[s.role]].name + "', '" +
                       s.name + "'): " + allowed);
    std::string& unit = s.role <= Z ? unit_len : unit_B;
    if (!unit.empty() && unit != s.unit)
      throw InputError(at + ": column '" + s.name + "' mixes units with another " +
                       (s.role <= Z ? "coordinate (" : "field (") + unit + "): allowed one unit for all " +
                       (s.role <= Z ? "coordinates (mm or m)" : "field columns (T or mT)"));
    unit = s.unit;
    col_of[s.role] = int(c);
  }
  for (int r : {X, Y, BZ})
    if (col_of[r] < 0) throw InputError(at + ": the header has no " + kColName[r] + " column: " + allowed);
  if ((col_of[BX] < 0) != (col_of[BY] < 0))
    throw InputError(at + ": the header has " + (col_of[BX] >= 0 ? "Bx but no By" : "By but no Bx") +
                     ": allowed both or neither");
}

bool starts_with_nocase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[i])) != std::tolower(static_cast<unsigned char>(prefix[i]))) return false;
  return true;
}

bool all_numbers(const std::vector<std::string>& cells) {
  return !cells.empty() && std::all_of(cells.begin(), cells.end(), [](const std::string& c) {
    return parse_number(c).status != CellNumber::NotNumber && !c.empty();
  });
}

// Rows of a table in mm and T, whatever format they came in, with their line numbers.
struct TableRows {
  std::vector<ColumnSpec> cols;
  bool has_z = false, has_B = false;
  std::vector<double> vals[kCols];  // per role, per row (mm, T)
  std::vector<long> line_of;        // per row: its line (1-based)
  // Ansys .fld only: the grid its header declares (mm; size 0 on an axis of one level).
  bool declared = false;
  Vec3 min_mm = Vec3::Zero(), max_mm = Vec3::Zero(), size_mm = Vec3::Zero();
  std::string format = "table";     // "table", "COMSOL export", "Ansys .fld" (for messages)
  std::size_t size() const { return line_of.size(); }
  void set_columns(std::vector<ColumnSpec> c) {
    cols = std::move(c);
    for (const auto& s : cols) has_z |= s.role == Z, has_B |= s.role == BX;
  }
};

// One data row: one finite number per column, scaled to mm and T.
void add_row(TableRows& t, const TextRow& row, char sep, const std::string& where, const FieldTableLimits& limits) {
  const std::string at = where + " line " + std::to_string(row.line);
  const auto& cells = row.cells;
  if (cells.size() != t.cols.size())
    throw InputError(at + ": " + std::to_string(cells.size()) + " values, the header has " + std::to_string(t.cols.size()) +
                     " columns: allowed one number per column" + decimal_comma_hint(sep, cells.size(), t.cols.size()));
  if (t.size() >= limits.max_nodes)
    throw InputError(at + ": more than " + std::to_string(limits.max_nodes) + " data rows: allowed at most " +
                     std::to_string(limits.max_nodes) + " grid nodes");
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const CellNumber n = parse_number(cells[c]);
    const ColumnSpec& s = t.cols[c];
    if (n.status == CellNumber::Empty || n.status == CellNumber::NotNumber)
      throw InputError(at + ": " + s.name + " = '" + cells[c] + "' is not a number: allowed finite numbers");
    const double v = n.value * s.scale;
    if (n.status == CellNumber::NotFinite || !std::isfinite(v))
      throw InputError(at + ": " + s.name + " = '" + cells[c] + "' is not finite: allowed finite numbers");
    t.vals[s.role].push_back(v);
  }
  t.line_of.push_back(row.line);
}

// ---- magenc's own table: one header row naming the columns with their units ----

// One header cell -> its column (role kCols if unknown).
ColumnSpec native_column(const std::string& name) {
  const auto us = name.find('_');
  if (us == std::string::npos) return {kCols, 1.0, "", name};
  const std::string q = name.substr(0, us), unit = name.substr(us + 1);
  for (int r = 0; r < kCols; ++r) {
    if (q != kColName[r]) continue;
    if (r <= Z) {
      if (unit == "mm") return {r, 1.0, unit, name};
      if (unit == "m") return {r, 1e3, unit, name};
    } else {
      if (unit == "T") return {r, 1.0, unit, name};
      if (unit == "mT") return {r, 1e-3, unit, name};
    }
  }
  return {kCols, 1.0, "", name};
}

TableRows read_native(std::string_view text, const std::string& where, const FieldTableLimits& limits) {
  TableRows t;
  TextTableReader reader(text, where, {"#%", 0});
  TextRow row;
  if (!reader.next(row))
    throw InputError(where + " is empty: expected a header row naming the columns (" + kAllowedColumns + ") and data rows");
  const std::string at = where + " line " + std::to_string(row.line);
  std::vector<ColumnSpec> cols;
  for (const auto& cell : row.cells) {
    ColumnSpec s = native_column(cell);
    if (s.role == kCols) {
      if (!cell.empty() && parse_number(cell).status != CellNumber::NotNumber)
        throw InputError(at + ": expected the header row naming the columns, found the number '" + cell + "': " +
                         kAllowedColumns + "; " + kOtherFormats);
      throw InputError(at + ": unknown column '" + cell + "': " + kAllowedColumns);
    }
    cols.push_back(s);
  }
  check_columns(cols, at, kAllowedColumns);
  t.set_columns(std::move(cols));
  while (reader.next(row)) add_row(t, row, reader.separator(), where, limits);
  return t;
}

// ---- COMSOL's spreadsheet export: '%' header lines, the last naming the columns ----

const char* const kComsolColumns =
    "allowed columns x, y, optional z (unit from '% Length unit:'), and mf.Bz (T) or (mT), optionally with "
    "mf.Bx and mf.By (any interface prefix, e.g. mfnc.Bz)";

// The factor from a length unit to mm (0 if unknown).
double length_unit_to_mm(const std::string& u) {
  if (u == "m") return 1e3;
  if (u == "cm") return 10.0;
  if (u == "mm") return 1.0;
  if (u == "um" || u == "\xC2\xB5m" || u == "\xCE\xBCm") return 1e-3;  // um, micro sign m, Greek mu m
  return 0.0;
}

// The column names of COMSOL's last header line: cells on the data's separator (blanks when that leaves
// one cell); with blanks, a token that starts with '(' is the unit of the name before it ("mf.Bz (T)").
std::vector<std::string> comsol_names(const std::string& line, char sep, const std::string& where, long line_no) {
  std::vector<std::string> cells = split_cells(line, sep, where, line_no), names;
  if (sep != ' ' && cells.size() == 1) sep = ' ', cells = split_cells(line, sep, where, line_no);
  for (auto& c : cells) {
    if (sep == ' ' && !names.empty() && !c.empty() && c[0] == '(') names.back() += " " + c;
    else names.push_back(c);
  }
  return names;
}

// One COMSOL column: "x" (any case), "mf.Bz (T)"; length_mm: the '% Length unit:' factor (0 if none).
ColumnSpec comsol_column(const std::string& name, double length_mm, const std::string& length_unit,
                         const std::string& at) {
  const auto open = name.find('(');
  std::string base = name.substr(0, open), unit;
  while (!base.empty() && std::isspace(static_cast<unsigned char>(base.back()))) base.pop_back();
  if (open != std::string::npos) {
    const auto close = name.find(')', open);
    unit = name.substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1);
  }
  if (base.size() == 1 && std::string("xyzXYZ").find(base[0]) != std::string::npos) {
    const int role = std::tolower(static_cast<unsigned char>(base[0])) - 'x';
    const std::string u = unit.empty() ? length_unit : unit;
    const double f = unit.empty() ? length_mm : length_unit_to_mm(unit);
    if (u.empty())
      throw InputError(at + ": the COMSOL export has no '% Length unit:' line: cannot tell the unit of the "
                            "coordinates: allowed '% Length unit: mm' or 'm' among the '%' header lines");
    if (f == 0) throw InputError(at + ": length unit '" + u + "' is unknown: allowed m, cm, mm, um");
    return {role, f, u, name};
  }
  const auto dot = base.rfind('.');
  const std::string q = dot == std::string::npos ? base : base.substr(dot + 1);
  for (int r = BX; r <= BZ; ++r) {
    if (q != kColName[r]) continue;
    if (unit.empty())
      throw InputError(at + ": column '" + name + "' has no unit: allowed '" + base + " (T)' or '" + base + " (mT)'");
    if (unit == "T") return {r, 1.0, unit, name};
    if (unit == "mT") return {r, 1e-3, unit, name};
    throw InputError(at + ": column '" + name + "' is in '" + unit + "': allowed T or mT");
  }
  throw InputError(at + ": unknown column '" + name + "': " + kComsolColumns);
}

TableRows read_comsol(std::string_view text, const std::string& where, const FieldTableLimits& limits) {
  TableRows t;
  t.format = "COMSOL export";
  TextTableReader reader(text, where, {"#%", 0});
  TextRow row;
  reader.next(row);  // the first data row (recognise_format saw it)
  const auto& comments = reader.leading_comments();
  std::string length_unit;
  for (const auto& c : comments) {
    std::string body = c.text.substr(1);
    body.erase(0, body.find_first_not_of(" \t"));
    if (starts_with_nocase(body, "Length unit:")) {
      length_unit = body.substr(12);
      length_unit.erase(0, length_unit.find_first_not_of(" \t"));
      length_unit.erase(length_unit.find_last_not_of(" \t") + 1);
    }
  }
  const TextRow& names_line = comments.back();
  const std::string at = where + " line " + std::to_string(names_line.line);
  std::string names_text = names_line.text.substr(1);
  const auto first = names_text.find_first_not_of(" \t");
  names_text = first == std::string::npos ? "" : names_text.substr(first);
  if (names_line.text[0] != '%' || names_text.find(':') != std::string::npos || names_text.empty())
    throw InputError(at + ": the last '%' header line before the data does not name the columns ('" + names_text +
                     "'): allowed a COMSOL export whose last header line names them, e.g. '% x  y  z  mf.Bz (T)'");
  const double length_mm = length_unit_to_mm(length_unit);
  std::vector<ColumnSpec> cols;
  for (const auto& n : comsol_names(names_text, reader.separator(), where, names_line.line))
    cols.push_back(comsol_column(n, length_mm, length_unit, at));
  check_columns(cols, at, kComsolColumns);
  t.set_columns(std::move(cols));
  do add_row(t, row, reader.separator(), where, limits);
  while (reader.next(row));
  return t;
}

// ---- Ansys Maxwell's grid export (.fld): Min:, Max:, Grid Size: in a header, rows x y z and B in SI ----

// The three numbers after `key` in a header line ("Min: -0.005 -0.005 0", "Min: [-5mm -5mm 4.55mm]"),
// in mm: a number without a unit is in metres (SI), as Maxwell writes the rows. False when the key is absent.
bool ansys_triplet(const std::string& line, const std::string& key, Vec3& out_mm, const std::string& at) {
  const std::size_t k = line.find(key);
  if (k == std::string::npos) return false;
  std::size_t p = k + key.size(), end = line.size();
  for (const char* other : {"Min:", "Max:", "Grid Size:", "Unit:"}) {
    const auto o = line.find(other, p);
    if (o != std::string::npos) end = std::min(end, o);
  }
  std::string body = line.substr(p, end - p);
  for (char& c : body)
    if (c == '[' || c == ']' || c == ',') c = ' ';
  std::istringstream is(body);
  int n = 0;
  bool ok = true;
  for (std::string tok; ok && is >> tok;) {
    std::size_t u = tok.size();
    while (u > 0 && std::isalpha(static_cast<unsigned char>(tok[u - 1]))) --u;
    const std::string unit = tok.substr(u);
    const CellNumber v = parse_number(tok.substr(0, u));
    const double f = unit.empty() ? 1e3 : length_unit_to_mm(unit);
    ok = n < 3 && v.ok() && f != 0 && std::isfinite(v.value * f);
    if (ok) out_mm[n++] = v.value * f;
  }
  if (!ok || n != 3)
    throw InputError(at + ": '" + key + "' is followed by '" + line.substr(p, end - p) +
                     "': allowed three finite lengths (in m, or each with its unit, e.g. 4.55mm)");
  return true;
}

// The quantity line "X,Y,Z,Vector data \"<Bx,By,Bz>\"", "X Y Z Scalar data \"Bz\"", "X Y Z Bz": the number
// of field columns it names (3 for B, 1 for Bz).
int ansys_quantity(const std::string& line, const std::string& at) {
  const auto q1 = line.find('"'), q2 = line.rfind('"');
  std::string q = q1 != std::string::npos && q2 > q1 ? line.substr(q1 + 1, q2 - q1 - 1) : line.substr(1);
  std::string compact;
  for (char c : q)
    if (!std::isspace(static_cast<unsigned char>(c)) && c != ',' && c != '<' && c != '>') compact += c;
  if (q1 == std::string::npos) {  // "X Y Z Bz": drop the coordinate names
    compact.clear();
    for (char c : line)
      if (!std::isspace(static_cast<unsigned char>(c)) && c != ',') compact += c;
    if (starts_with_nocase(compact, "XYZ")) compact = compact.substr(3);
  }
  const bool complex = line.find("Complex") != std::string::npos;
  if (!complex && (compact == "BxByBz" || compact == "B" || compact == "B_Vector")) return 3;
  if (!complex && (compact == "Bz" || compact == "B_z")) return 1;
  throw InputError(at + ": the file holds '" + q + "'" + (complex ? " (complex data)" : "") +
                   ": allowed the real B vector (Vector data \"<Bx,By,Bz>\") or Bz (Scalar data \"Bz\")");
}

TableRows read_ansys(std::string_view text, const std::string& where, const FieldTableLimits& limits) {
  TableRows t;
  t.format = "Ansys .fld";
  TextTableReader reader(text, where, {"#", ' '});
  TextRow row;
  bool have[3] = {false, false, false};
  int field_cols = 0;  // from the quantity line; 0: from the number of columns (4: Bz, 6: Bx By Bz)
  bool data = false;
  while (reader.next(row)) {
    if ((data = all_numbers(row.cells))) break;
    const std::string at = where + " line " + std::to_string(row.line);
    const bool found[3] = {ansys_triplet(row.text, "Min:", t.min_mm, at), ansys_triplet(row.text, "Max:", t.max_mm, at),
                           ansys_triplet(row.text, "Grid Size:", t.size_mm, at)};
    for (int k = 0; k < 3; ++k) have[k] = have[k] || found[k];
    if (found[0] || found[1] || found[2]) continue;
    if (row.text.find(',') != std::string::npos && all_numbers(split_cells(row.text, ',', where, row.line)))
      throw InputError(at + ": '" + row.text + "' separates its values by ',': allowed an Ansys .fld grid export with "
                            "the values of a row separated by blanks (as Ansys writes them)");
    if (!starts_with_nocase(row.text, "X") && row.text.find("data") == std::string::npos)
      throw InputError(at + ": '" + row.text + "' is neither a grid header (Min:, Max:, Grid Size:) nor the "
                            "quantity line (X,Y,Z,...): allowed an Ansys .fld grid export");
    field_cols = ansys_quantity(row.text, at);
  }
  const char* key[3] = {"Min:", "Max:", "Grid Size:"};
  for (int k = 0; k < 3; ++k)
    if (!have[k])
      throw InputError(where + ": the Ansys .fld header has no '" + key[k] +
                       "' line: allowed a grid export with Min:, Max: and Grid Size: lines");
  if (!data)
    throw InputError(where + " has an Ansys .fld header but no data rows: allowed a grid of at least 2 x 2 rows x y z B");
  const std::size_t ncols = row.cells.size();
  if (field_cols == 0) field_cols = ncols == 4 ? 1 : ncols == 6 ? 3 : 0;
  if (field_cols == 0 || ncols != std::size_t(3 + field_cols))
    throw InputError(where + " line " + std::to_string(row.line) + ": " + std::to_string(ncols) +
                     " values: allowed x y z (m) and Bz, or x y z and Bx By Bz (T)");
  std::vector<ColumnSpec> cols = {{X, 1e3, "m", "x"}, {Y, 1e3, "m", "y"}, {Z, 1e3, "m", "z"}};
  if (field_cols == 3) cols.insert(cols.end(), {{BX, 1.0, "T", "Bx"}, {BY, 1.0, "T", "By"}});
  cols.push_back({BZ, 1.0, "T", "Bz"});
  t.set_columns(std::move(cols));
  t.declared = true;
  do add_row(t, row, ' ', where, limits);
  while (reader.next(row));
  return t;
}

// ---- Which format: recognised from the content ----

enum class TableFormat { Native, Comsol, Ansys };

TableFormat recognise_format(std::string_view text, const std::string& where) {
  TextTableReader reader(text, where, {"#%", 0});
  TextRow row;
  if (!reader.next(row)) return TableFormat::Native;  // (empty: the native reader says so)
  if (starts_with_nocase(row.text, "Min:") || starts_with_nocase(row.text, "Grid Output Min:") ||
      starts_with_nocase(row.text, "Max:") || starts_with_nocase(row.text, "Grid Size:"))
    return TableFormat::Ansys;
  const auto& comments = reader.leading_comments();
  if (all_numbers(row.cells) && !comments.empty() && comments.back().text[0] == '%') return TableFormat::Comsol;
  return TableFormat::Native;
}

TableRows read_rows(std::string_view text, const std::string& where, const FieldTableLimits& limits) {
  switch (recognise_format(text, where)) {
    case TableFormat::Comsol: return read_comsol(text, where, limits);
    case TableFormat::Ansys: return read_ansys(text, where, limits);
    default: return read_native(text, where, limits);
  }
}

// ---- The regular grid: per axis the levels, their lattice indices, and the offending rows ----

std::string point_text(double x, double y, double z) {
  std::string s = "(";  // not "(" + std::string: GCC 12 -Wrestrict false positive (GCC bug 105651)
  s += num(x) + ", " + num(y) + ", " + num(z) + ") mm";
  return s;
}

// One axis of the lattice: the rows' coordinate levels and their grid indices.
struct Axis {
  std::vector<double> level;           // sorted distinct coordinate levels (mm)
  std::vector<long long> index;        // lattice index of each level (level[0] -> 0)
  std::vector<std::size_t> row_level;  // per row: its level
  std::vector<char> extra;             // per level: apart from the grid (an extra point)
  std::size_t first = 0, last = 0;     // the grid's first and last level
  double h = 0;                        // fitted spacing (mm); 0 for one level
  double origin = 0;                   // fitted position of index 0 (mm)
  long long lo = 0, hi = 0;            // index range of the grid's main block
};

// The first offending row (in file order) over all axes, with its message.
struct BadRow {
  std::size_t row = std::numeric_limits<std::size_t>::max();
  std::string message;
  void flag(std::size_t r, const std::string& m) {
    if (r < row) row = r, message = m;
  }
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Distinct levels of the coordinates v (merged when they differ by <= 1e-9 of their size or of the median
// |v|, whichever is larger: printing noise) and each row's level. The median, not the range: one far point
// (1e12 mm beside a grid of 0..3 mm) must not merge the grid's own levels into one.
void axis_levels(Axis& a, const std::vector<double>& v) {
  std::vector<double> sorted(v);
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> mag(v.size());
  for (std::size_t r = 0; r < v.size(); ++r) mag[r] = std::abs(v[r]);
  const double bulk_mm = median(mag);
  auto merge_tol = [bulk_mm](double x, double y) { return 1e-9 * std::max({std::abs(x), std::abs(y), bulk_mm}); };
  for (double x : sorted)
    if (a.level.empty() || x - a.level.back() > merge_tol(x, a.level.back())) a.level.push_back(x);
  a.row_level.resize(v.size());
  for (std::size_t r = 0; r < v.size(); ++r)
    a.row_level[r] =
        std::size_t(std::upper_bound(a.level.begin(), a.level.end(), v[r] + merge_tol(v[r], v[r])) - a.level.begin()) - 1;
  a.index.assign(a.level.size(), 0);
  a.extra.assign(a.level.size(), 0);
  a.origin = a.level[0];
}

// Lattice indices from the median gap hm; blocks of contiguous indices: the block with the most rows is
// the grid, others are extra points when they hold fewer rows than half an average grid line (else they
// count as the grid with gaps).
void axis_blocks(Axis& a, double hm) {
  const std::size_t nl = a.level.size();
  for (std::size_t i = 0; i < nl; ++i) {
    const double t = (a.level[i] - a.level[0]) / hm;
    a.index[i] = t < 9e15 ? std::llround(t) : (1LL << 53);
  }
  std::vector<std::size_t> rows_per_level(nl, 0);
  for (std::size_t l : a.row_level) ++rows_per_level[l];
  std::vector<std::pair<std::size_t, std::size_t>> blocks;  // [first, last] level
  for (std::size_t i = 0; i < nl; ++i)
    if (i == 0 || a.index[i] - a.index[i - 1] > 1) blocks.push_back({i, i});
    else blocks.back().second = i;
  auto block_rows = [&](const std::pair<std::size_t, std::size_t>& b) {
    return std::accumulate(rows_per_level.begin() + long(b.first), rows_per_level.begin() + long(b.second) + 1, std::size_t(0));
  };
  std::size_t main = 0;
  for (std::size_t b = 1; b < blocks.size(); ++b)
    if (block_rows(blocks[b]) > block_rows(blocks[main])) main = b;
  const double per_line = double(block_rows(blocks[main])) / double(blocks[main].second - blocks[main].first + 1);
  a.first = blocks[main].first, a.last = blocks[main].second;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (b == main) continue;
    if (double(block_rows(blocks[b])) < 0.5 * per_line) {
      for (std::size_t i = blocks[b].first; i <= blocks[b].second; ++i) a.extra[i] = 1;
    } else {
      a.first = std::min(a.first, blocks[b].first);
      a.last = std::max(a.last, blocks[b].second);
    }
  }
}

// Line level = origin + h*index: a robust start (median gap hm, median origin), then least squares over the
// levels within 0.05 cells of it (so one stray level cannot tilt the line).
void axis_line(Axis& a, double hm) {
  std::vector<double> origins;
  for (std::size_t i = a.first; i <= a.last; ++i)
    if (!a.extra[i]) origins.push_back(a.level[i] - hm * double(a.index[i]));
  const double o_med = median(origins);
  double si = 0, sl = 0, sii = 0, sil = 0, n = 0;
  for (std::size_t i = a.first; i <= a.last; ++i) {
    const double id = double(a.index[i]);
    if (a.extra[i] || !(std::abs(a.level[i] - o_med - hm * id) <= 0.05 * hm)) continue;
    si += id, sl += a.level[i], sii += id * id, sil += id * a.level[i], n += 1;
  }
  const double den = n * sii - si * si;
  a.h = den > 0 ? (n * sil - si * sl) / den : hm;
  a.origin = n > 0 ? (sl - a.h * si) / n : o_med;
  a.lo = a.index[a.first];
  a.hi = a.index[a.last];
}

// Axis d of the rows: levels, spacing, indices; flags the rows that are extra points or off the lattice
// (every level must lie within kLatticeTol cells of the fitted line).
Axis fit_axis(const TableRows& t, int d, const std::string& where, double plane_z_mm, BadRow& bad) {
  Axis a;
  axis_levels(a, t.vals[d]);
  const std::size_t nl = a.level.size();
  if (nl == 1) return a;
  std::vector<double> gaps(nl - 1);
  for (std::size_t i = 0; i + 1 < nl; ++i) gaps[i] = a.level[i + 1] - a.level[i];
  const double hm = median(gaps);
  axis_blocks(a, hm);
  axis_line(a, hm);
  const std::string c = kColName[d];
  const std::string extent = c + " in [" + num(a.level[a.first]) + ", " + num(a.level[a.last]) + "] mm";
  std::vector<char> off(nl, 0);
  bool any_off = false;
  for (std::size_t i = 0; i < nl; ++i) {
    // Two levels on one index: at least one is off by >= half a cell (both within the tolerance are one
    // coordinate printed two ways: the same node).
    if (!a.extra[i] && !(std::abs(a.level[i] - (a.origin + a.h * double(a.index[i]))) <= kLatticeTol * a.h))
      off[i] = 1, any_off = true;
  }
  for (std::size_t r = 0; r < t.size(); ++r) {
    const std::size_t i = a.row_level[r];
    if (!a.extra[i] && !(any_off && off[i])) continue;
    const std::string at = where + " line " + std::to_string(t.line_of[r]) + ": ";
    const double z = t.has_z ? t.vals[Z][r] : plane_z_mm;
    if (a.extra[i])
      bad.flag(r, at + "the point " + point_text(t.vals[X][r], t.vals[Y][r], z) +
                      " is an extra point, apart from the grid of the other rows (" + extent +
                      "): allowed only the points of one regular grid");
    else
      bad.flag(r, at + c + " = " + num(a.level[i]) + " mm is off the regular grid of the other rows (" + c + " = " +
                      num(a.origin) + " + i*" + num(a.h) + " mm, nearest " +
                      num(a.origin + a.h * std::round((a.level[i] - a.origin) / a.h)) + " mm): allowed within " +
                      num(kLatticeTol) + " of a cell");
  }
  return a;
}

// The regular grid of the rows: GridData in node order (i fastest). InputError for the first row off the
// lattice or apart from the grid, a grid beyond the node limit, a repeated point, or a missing point.
GridData rows_to_grid(const TableRows& t, const std::string& source, double plane_z_mm, const FieldTableLimits& limits) {
  const std::string where = "table " + source;
  const int naxes = t.has_z ? 3 : 2;
  Axis ax[3];
  BadRow bad;
  for (int d = 0; d < naxes; ++d) ax[d] = fit_axis(t, d, where, plane_z_mm, bad);
  if (bad.row < t.size()) throw InputError(bad.message);
  for (int d = 0; d < 2; ++d)
    if (ax[d].level.size() < 2)
      throw InputError(where + ": all rows have " + kColName[d] + " = " + num(ax[d].level[0]) +
                       " mm: allowed a grid of at least 2 x 2 points (x and y)");
  long long n[3] = {1, 1, 1};
  for (int d = 0; d < naxes; ++d) n[d] = ax[d].hi - ax[d].lo + 1;
  const double nodes_d = double(n[0]) * double(n[1]) * double(n[2]);
  const std::string dims = std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]);
  if (nodes_d > double(limits.max_nodes))
    throw InputError(where + ": the points span a grid of " + dims + " nodes: allowed at most " +
                     std::to_string(limits.max_nodes) + " nodes");
  const std::size_t nodes = std::size_t(nodes_d), nrows = t.size();
  std::vector<std::size_t> node_of(nrows);
  for (std::size_t r = 0; r < nrows; ++r) {
    std::size_t id = 0, stride = 1;
    for (int d = 0; d < naxes; ++d) {
      id += std::size_t(ax[d].index[ax[d].row_level[r]] - ax[d].lo) * stride;
      stride *= std::size_t(n[d]);
    }
    node_of[r] = id;
  }
  std::vector<std::size_t> order(nrows);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return node_of[a] < node_of[b]; });
  std::size_t dup = nrows, dup_of = nrows;
  for (std::size_t k = 1; k < nrows; ++k)
    if (node_of[order[k]] == node_of[order[k - 1]] && order[k] < dup) dup = order[k], dup_of = order[k - 1];
  if (dup < nrows)
    throw InputError(where + " line " + std::to_string(t.line_of[dup]) + ": the point " +
                     point_text(t.vals[X][dup], t.vals[Y][dup], t.has_z ? t.vals[Z][dup] : plane_z_mm) + " repeats line " +
                     std::to_string(t.line_of[dup_of]) + ": allowed each grid point once");
  if (nrows != nodes) {
    std::size_t id = 0;
    while (id < nrows && node_of[order[id]] == id) ++id;
    double p[3] = {0, 0, plane_z_mm};
    for (int d = 0; d < naxes; ++d) {
      p[d] = ax[d].origin + ax[d].h * double(ax[d].lo + (long long)(id % std::size_t(n[d])));
      id /= std::size_t(n[d]);
    }
    throw InputError(where + ": the grid point " + point_text(p[0], p[1], p[2]) + " is missing (" + std::to_string(nrows) +
                     " rows for a grid of " + dims + " points): allowed only complete regular grids");
  }
  GridData g;
  g.source = source;
  for (int d = 0; d < 3; ++d) g.dims[d] = int(n[d]);
  g.origin_mm = Vec3(ax[X].origin + ax[X].h * double(ax[X].lo), ax[Y].origin + ax[Y].h * double(ax[Y].lo),
                     t.has_z ? ax[Z].origin + ax[Z].h * double(ax[Z].lo) : plane_z_mm);
  g.spacing_mm = Vec3(ax[X].h, ax[Y].h, (t.has_z && n[2] > 1) ? ax[Z].h : 1.0);
  g.Bz_T.resize(nodes);
  if (t.has_B) g.Bx_T.resize(nodes), g.By_T.resize(nodes);
  for (std::size_t r = 0; r < nrows; ++r) {
    g.Bz_T[node_of[r]] = t.vals[BZ][r];
    if (t.has_B) g.Bx_T[node_of[r]] = t.vals[BX][r], g.By_T[node_of[r]] = t.vals[BY][r];
  }
  g.validate();
  return g;
}

// Ansys .fld: the rows, read as metres, must lie on the grid that the header's Min:, Max: and Grid Size:
// declare (in their units); else the unit of the rows cannot be told.
void check_declared_grid(const TableRows& t, const GridData& g, const std::string& where) {
  for (int d = 0; d < 3; ++d) {
    const double lo = g.origin_mm[d], hi = lo + (g.dims[d] > 1 ? (g.dims[d] - 1) * g.spacing_mm[d] : 0.0);
    const double tol = std::max(0.01 * std::abs(t.size_mm[d]),
                                1e-6 * std::max({std::abs(t.min_mm[d]), std::abs(t.max_mm[d]), 1.0}));
    const std::string c = kColName[d];
    if (!(std::abs(lo - t.min_mm[d]) <= tol && std::abs(hi - t.max_mm[d]) <= tol))
      throw InputError(where + ": the rows span " + c + " in [" + num(lo) + ", " + num(hi) +
                       "] mm read as metres, but the header declares Min/Max " + c + " = [" + num(t.min_mm[d]) + ", " +
                       num(t.max_mm[d]) + "] mm: cannot tell the unit of the rows: allowed rows in metres on the "
                       "declared grid");
    if (g.dims[d] > 1 && !(std::abs(g.spacing_mm[d] - t.size_mm[d]) <= tol))
      throw InputError(where + ": the rows' spacing in " + c + " is " + num(g.spacing_mm[d]) +
                       " mm but the header's Grid Size says " + num(t.size_mm[d]) +
                       " mm: allowed rows on the declared grid");
  }
}

// Plausibility of the numbers against the units the header claims (a table in other units than its header
// says would otherwise give a field 1000 times off, or a grid 1000 times too large): the largest |B| of
// the table between kMinFieldMax_T and kMaxField_T, the grid within kMaxExtent_mm, its spacing at least
// kMinSpacing_mm.
void check_plausible(const TableRows& t, const GridData& g, const std::string& where, const FieldTableLimits& limits) {
  int col_max = -1;
  double bmax = 0;
  for (std::size_t c = 0; c < t.cols.size(); ++c) {
    if (t.cols[c].role < BX) continue;
    for (double v : t.vals[t.cols[c].role])
      if (std::abs(v) > bmax || col_max < 0) bmax = std::abs(v), col_max = int(c);
  }
  const ColumnSpec& fc = t.cols[std::size_t(col_max)];
  const std::string field_col = "column '" + fc.name + "'";
  const std::string field_range = largest_field_range_text(limits);
  if (bmax == 0.0) throw InputError(where + ": every field value is zero: allowed a largest |B| above 0");
  if (bmax > limits.largest_field_max_T)
    throw InputError(where + ": " + field_col + " holds |B| = " + num(bmax / fc.scale) + " " + fc.unit + " (" + num(bmax) +
                     " T): " + field_range + (fc.unit == "T" ? " (values in mT under a T header?" : " (") +
                     " a table reaching into a magnet or steel: raise checks.largest_field_max_T)");
  if (bmax < limits.largest_field_min_T)
    throw InputError(where + ": the largest |B| of the table is " + num(bmax / fc.scale) + " " + fc.unit + " (" +
                     field_col + "): " + field_range + (fc.unit == "mT" ? " (values in T under a mT header?" : " (") +
                     " a weak field: lower checks.largest_field_min_mT)");
  const ColumnSpec* xc = nullptr;
  for (const auto& c : t.cols)
    if (c.role == X) xc = &c;
  const std::string len_unit = xc ? xc->unit : "mm";
  for (int d = 0; d < 3; ++d) {
    if (g.dims[d] < 2) continue;
    const double extent = g.spacing_mm[d] * (g.dims[d] - 1);
    if (extent > kFieldTableMaxExtent_mm)
      throw InputError(where + ": the grid spans " + num(extent) + " mm in " + kColName[d] + " (read in " + len_unit +
                       "): allowed at most " + num(kFieldTableMaxExtent_mm) + " mm (coordinates in mm under a " +
                       len_unit + " header or length unit?)");
    if (g.spacing_mm[d] < kFieldTableMinSpacing_mm)
      throw InputError(where + ": the grid spacing in " + kColName[d] + " is " + num(g.spacing_mm[d]) + " mm (read in " +
                       len_unit + "): allowed at least " + num(kFieldTableMinSpacing_mm) +
                       " mm (coordinates in m under a " + len_unit + " header?)");
  }
}

}  // namespace

GridData parse_field_table(const std::string& text, const std::string& source, double plane_z_mm,
                           const FieldTableLimits& limits) {
  const std::string where = "table " + source;
  TableRows t;
  {
    // strtod and unit scaling overflow for 1e999 or 1e308 m (rejected as not finite): untrapped (fp_trap.hpp).
    const FpTrapPause parsing_input;
    t = read_rows(text, where, limits);
  }
  if (t.size() == 0)
    throw InputError(where + " has a header but no data rows: allowed a regular grid of at least 2 x 2 points");
  GridData g = rows_to_grid(t, source, plane_z_mm, limits);
  if (t.declared) check_declared_grid(t, g, where);
  check_plausible(t, g, where, limits);
  return g;
}

GridData read_field_table(const std::filesystem::path& file, double plane_z_mm, const FieldTableLimits& limits) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw InputError("table " + file.string() +
                     " does not exist or is not a file (expected a text table of B on a regular grid)");
  const std::string text = read_text_file(file, "table " + file.string(), limits.max_bytes);
  return parse_field_table(text, file.string(), plane_z_mm, limits);
}

std::shared_ptr<GridField> table_field_from_file(const std::filesystem::path& file, const Config& cfg, Interp mode) {
  const double zs = sensing_plane_z_mm(cfg);
  GridData g = read_field_table(file, zs, field_table_limits(cfg));
  if (g.is_plane() && !(std::abs(g.origin_mm.z() - zs) <= GridField::kPlaneTolerance_mm))
    throw InputError("table " + file.string() + " is one plane at z = " + num(g.origin_mm.z()) +
                     " mm but the sensing plane is z_s = " + num(zs) +
                     " mm (magnet frame): allowed a plane at z_s (or no z column) or several z levels");
  return std::make_shared<GridField>(std::move(g), mode, "table");
}

std::vector<KeySpec> field_check_keys() {
  return {
      real_key("checks.largest_field_min_mT", kFieldTableMinFieldMax_T * 1e3, 0, 1e6, "mT",
               "field tables (table:FILE, table_to_vti) and inspect scans: the least largest |B| a file may hold "
               "(1 mT: a magnet's field at a sensor is 1-500 mT; tesla under a mT header reads 1000 times smaller); "
               "lower it for a weak field",
               true),
      real_key("checks.largest_field_max_T", kFieldTableMaxField_T, 0, 1e3, "T",
               "field tables and inspect scans: the most largest |B| a file may hold (1 T; mT under a T header reads "
               "1000 times larger); raise it for points at a magnet's face or in steel",
               true),
  };
}

FieldTableLimits field_table_limits(const Config& cfg) {
  FieldTableLimits l;
  if (cfg.find("checks.largest_field_min_mT")) l.largest_field_min_T = cfg.real("checks.largest_field_min_mT") * 1e-3;
  if (cfg.find("checks.largest_field_max_T")) l.largest_field_max_T = cfg.real("checks.largest_field_max_T");
  if (!(l.largest_field_min_T < l.largest_field_max_T))
    throw InputError("checks.largest_field_min_mT = " + num(l.largest_field_min_T * 1e3) +
                     " mT is out of range: allowed below checks.largest_field_max_T = " + num(l.largest_field_max_T) + " T");
  return l;
}

std::string largest_field_range_text(const FieldTableLimits& l) {
  return "allowed a largest |B| between " + num(l.largest_field_min_T * 1e3) + " mT and " + num(l.largest_field_max_T) +
         " T";
}

std::string field_table_text(const GridData& g, const FieldTableFormat& f) {
  g.validate();
  const bool with_z = f.with_z || !g.is_plane();
  const bool with_B = f.with_B && g.has_B();
  const std::string L = f.metres ? "_m" : "_mm", U = f.millitesla ? "_mT" : "_T";
  const double ls = f.metres ? 1e-3 : 1.0, bs = f.millitesla ? 1e3 : 1.0;
  std::ostringstream os;
  os << std::setprecision(17);
  if (!f.comment.empty()) {
    std::istringstream cs(f.comment);
    for (std::string l; std::getline(cs, l);) os << "# " << l << '\n';
  }
  const char s = f.separator;
  os << "x" << L << s << "y" << L;
  if (with_z) os << s << "z" << L;
  if (with_B) os << s << "Bx" << U << s << "By" << U;
  os << s << "Bz" << U << '\n';
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::size_t id = std::size_t(i) + std::size_t(g.dims[0]) * (std::size_t(j) + std::size_t(g.dims[1]) * k);
        os << (g.origin_mm.x() + i * g.spacing_mm.x()) * ls << s << (g.origin_mm.y() + j * g.spacing_mm.y()) * ls;
        if (with_z) os << s << (g.origin_mm.z() + (g.is_plane() ? 0.0 : k * g.spacing_mm.z())) * ls;
        if (with_B) os << s << g.Bx_T[id] * bs << s << g.By_T[id] * bs;
        os << s << g.Bz_T[id] * bs << '\n';
      }
  return os.str();
}

}  // namespace magenc
