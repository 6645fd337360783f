#include "fields/field_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"
#include "fields/magnet.hpp"

namespace magenc {

namespace {

const char* const kAllowedColumns =
    "allowed columns x_mm|x_m, y_mm|y_m, optional z_mm|z_m, Bz_T|Bz_mT, optional Bx_T|Bx_mT with By_T|By_mT";

// Column roles in a table.
enum Col { X = 0, Y, Z, BX, BY, BZ, kCols };
const char* const kColName[kCols] = {"x", "y", "z", "Bx", "By", "Bz"};

// One header cell -> (role, scale to mm or T, unit text); role kCols if unknown.
struct ColumnSpec {
  int role = kCols;
  double scale = 1.0;
  std::string unit;
};
ColumnSpec column_spec(const std::string& name) {
  const auto us = name.find('_');
  if (us == std::string::npos) return {};
  const std::string q = name.substr(0, us), unit = name.substr(us + 1);
  for (int r = 0; r < kCols; ++r) {
    if (q != kColName[r]) continue;
    if (r <= Z) {
      if (unit == "mm") return {r, 1.0, unit};
      if (unit == "m") return {r, 1e3, unit};
    } else {
      if (unit == "T") return {r, 1.0, unit};
      if (unit == "mT") return {r, 1e-3, unit};
    }
  }
  return {};
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n\v\f");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n\v\f");
  return s.substr(b, e - b + 1);
}

// Splits a line on the file's separator (' ' = runs of blanks); trims cells and strips one pair of quotes.
std::vector<std::string> split_cells(const std::string& line, char sep) {
  std::vector<std::string> cells;
  if (sep == ' ') {
    std::istringstream is(line);
    for (std::string c; is >> c;) cells.push_back(c);
  } else {
    std::size_t start = 0;
    while (true) {
      const auto pos = line.find(sep, start);
      cells.push_back(trim(line.substr(start, pos == std::string::npos ? std::string::npos : pos - start)));
      if (pos == std::string::npos) break;
      start = pos + 1;
    }
  }
  for (auto& c : cells)
    if (c.size() >= 2 && c.front() == '"' && c.back() == '"') c = trim(c.substr(1, c.size() - 2));
  return cells;
}

std::string point_text(double x, double y, double z) {
  std::string s = "(";  // not "(" + std::string: GCC 12 -Wrestrict false positive (GCC bug 105651)
  s += num(x) + ", " + num(y) + ", " + num(z) + ") mm";
  return s;
}

// One axis of the lattice: the rows' coordinate levels and their grid indices.
struct Axis {
  std::vector<double> level;        // sorted distinct coordinate levels (mm)
  std::vector<long long> index;     // lattice index of each level (level[0] -> 0)
  std::vector<std::size_t> row_level;  // per row: its level
  double h = 0;                     // fitted spacing (mm); 0 for one level
  double origin = 0;                // fitted position of index 0 (mm)
  long long lo = 0, hi = 0;         // index range of the grid's main block
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

GridData parse_field_table(const std::string& text, const std::string& source, double plane_z_mm,
                           const FieldTableLimits& limits) {
  const std::string where = "table " + source;
  // 1. Lines: comments, header, data rows (one finite number per column).
  std::vector<int> role;            // per column
  std::vector<double> scale;        // per column
  std::vector<std::string> header;  // per column, as written
  char sep = ' ';
  int col_of[kCols];
  std::fill(col_of, col_of + kCols, -1);
  std::vector<std::vector<double>> vals(kCols);  // per role, per row (mm, T)
  std::vector<long> line_of;                     // per row: its line number (1-based)
  {
    // strtod raises FE_OVERFLOW for 1e999 (rejected below as not finite): untrapped (fp_trap.hpp).
    const FpTrapPause parsing_input;
    std::size_t pos = 0;
    long line_no = 0;
    if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) pos = 3;  // UTF-8 byte-order mark
    while (pos < text.size()) {
      const auto nl = text.find('\n', pos);
      const std::string raw = text.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
      pos = nl == std::string::npos ? text.size() : nl + 1;
      ++line_no;
      const std::string line = trim(raw);
      if (line.empty() || line[0] == '#' || line[0] == '%') continue;
      const std::string at = where + " line " + std::to_string(line_no);
      if (header.empty()) {
        // Header: separator, known and distinct columns, consistent units.
        sep = line.find(',') != std::string::npos ? ',' : (line.find('\t') != std::string::npos ? '\t' : ' ');
        header = split_cells(line, sep);
        std::string unit_len, unit_B;
        for (std::size_t c = 0; c < header.size(); ++c) {
          const ColumnSpec s = column_spec(header[c]);
          if (s.role == kCols) {
            char* end = nullptr;
            std::strtod(header[c].c_str(), &end);
            if (!header[c].empty() && end == header[c].c_str() + header[c].size())
              throw InputError(at + ": expected the header row naming the columns, found the number '" + header[c] +
                               "': " + kAllowedColumns);
            throw InputError(at + ": unknown column '" + header[c] + "': " + kAllowedColumns);
          }
          if (col_of[s.role] >= 0)
            throw InputError(at + ": column " + kColName[s.role] + " appears twice ('" + header[col_of[s.role]] +
                             "', '" + header[c] + "'): " + kAllowedColumns);
          std::string& unit = s.role <= Z ? unit_len : unit_B;
          if (!unit.empty() && unit != s.unit)
            throw InputError(at + ": column '" + header[c] + "' mixes units with another " +
                             (s.role <= Z ? "coordinate (" : "field (") + unit + "): allowed one unit for all " +
                             (s.role <= Z ? "coordinates (mm or m)" : "field columns (T or mT)"));
          unit = s.unit;
          col_of[s.role] = int(c);
          role.push_back(s.role);
          scale.push_back(s.scale);
        }
        for (int r : {X, Y, BZ})
          if (col_of[r] < 0)
            throw InputError(at + ": the header has no " + kColName[r] + " column: " + kAllowedColumns);
        if ((col_of[BX] < 0) != (col_of[BY] < 0))
          throw InputError(at + ": the header has " + (col_of[BX] >= 0 ? "Bx but no By" : "By but no Bx") +
                           ": allowed both or neither");
        continue;
      }
      // Data row.
      const auto cells = split_cells(line, sep);
      if (cells.size() != header.size())
        throw InputError(at + ": " + std::to_string(cells.size()) + " values, the header has " +
                         std::to_string(header.size()) + " columns: allowed one number per column");
      if (line_of.size() >= limits.max_nodes)
        throw InputError(at + ": more than " + std::to_string(limits.max_nodes) + " data rows: allowed at most " +
                         std::to_string(limits.max_nodes) + " grid nodes");
      for (std::size_t c = 0; c < cells.size(); ++c) {
        const std::string& t = cells[c];
        char* end = nullptr;
        const double v = t.empty() ? NAN : std::strtod(t.c_str(), &end);
        if (t.empty() || end != t.c_str() + t.size())
          throw InputError(at + ": " + header[c] + " = '" + t + "' is not a number: allowed finite numbers");
        if (!std::isfinite(v) || !std::isfinite(v * scale[c]))
          throw InputError(at + ": " + header[c] + " = '" + t + "' is not finite: allowed finite numbers");
        vals[role[c]].push_back(v * scale[c]);
      }
      line_of.push_back(line_no);
    }
  }
  if (header.empty())
    throw InputError(where + " is empty: expected a header row naming the columns (" + kAllowedColumns + ") and data rows");
  const std::size_t nrows = line_of.size();
  if (nrows == 0) throw InputError(where + " has a header but no data rows: allowed a regular grid of at least 2 x 2 points");

  // 2. Lattice per axis: levels, spacing, index of every row's coordinate.
  const bool has_z = col_of[Z] >= 0;
  const int naxes = has_z ? 3 : 2;
  Axis ax[3];
  std::size_t first_bad_row = nrows;  // first row (in file order) that is off the lattice or apart from the grid
  std::string bad_message;
  auto flag_row = [&](std::size_t r, const std::string& msg) {
    if (r < first_bad_row) {
      first_bad_row = r;
      bad_message = msg;
    }
  };
  auto row_point = [&](std::size_t r) {
    return point_text(vals[X][r], vals[Y][r], has_z ? vals[Z][r] : plane_z_mm);
  };
  for (int d = 0; d < naxes; ++d) {
    Axis& a = ax[d];
    const std::vector<double>& v = vals[d];
    std::vector<double> sorted(v);
    std::sort(sorted.begin(), sorted.end());
    const double scale_mm = std::max({std::abs(sorted.front()), std::abs(sorted.back()), sorted.back() - sorted.front()});
    const double merge_tol = 1e-9 * scale_mm;  // printing noise of the same coordinate
    for (double x : sorted)
      if (a.level.empty() || x - a.level.back() > merge_tol) a.level.push_back(x);
    a.row_level.resize(nrows);
    for (std::size_t r = 0; r < nrows; ++r)
      a.row_level[r] = std::size_t(std::upper_bound(a.level.begin(), a.level.end(), v[r] + merge_tol) - a.level.begin()) - 1;
    const std::size_t nl = a.level.size();
    a.index.assign(nl, 0);
    a.origin = a.level[0];
    if (nl == 1) continue;
    // Spacing: median gap between neighbouring levels; indices relative to level 0.
    std::vector<double> gaps(nl - 1);
    for (std::size_t i = 0; i + 1 < nl; ++i) gaps[i] = a.level[i + 1] - a.level[i];
    const double hm = median(gaps);
    for (std::size_t i = 0; i < nl; ++i) {
      const double t = (a.level[i] - a.level[0]) / hm;
      a.index[i] = t < 9e15 ? std::llround(t) : (1LL << 53);
    }
    // Blocks of contiguous indices; the block with the most rows is the grid, others are extra points
    // when they hold fewer rows than half an average grid line (else they count as the grid with gaps).
    std::vector<std::size_t> rows_per_level(nl, 0);
    for (std::size_t r = 0; r < nrows; ++r) ++rows_per_level[a.row_level[r]];
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
    std::vector<char> extra(nl, 0);
    std::size_t grid_first = blocks[main].first, grid_last = blocks[main].second;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      if (b == main) continue;
      if (double(block_rows(blocks[b])) < 0.5 * per_line) {
        for (std::size_t i = blocks[b].first; i <= blocks[b].second; ++i) extra[i] = 1;
      } else {
        grid_first = std::min(grid_first, blocks[b].first);
        grid_last = std::max(grid_last, blocks[b].second);
      }
    }
    // Line level = origin + h*index: a robust start (median gap, median origin), then least squares over
    // the levels within 0.05 cells of it (so one stray level cannot tilt the line); then each level must
    // lie within kLatticeTol cells of the fitted line.
    std::vector<double> origins;
    for (std::size_t i = grid_first; i <= grid_last; ++i)
      if (!extra[i]) origins.push_back(a.level[i] - hm * double(a.index[i]));
    const double o_med = median(origins);
    double si = 0, sl = 0, sii = 0, sil = 0, n = 0;
    for (std::size_t i = grid_first; i <= grid_last; ++i) {
      const double id = double(a.index[i]);
      if (extra[i] || !(std::abs(a.level[i] - o_med - hm * id) <= 0.05 * hm)) continue;
      si += id, sl += a.level[i], sii += id * id, sil += id * a.level[i], n += 1;
    }
    const double den = n * sii - si * si;
    a.h = den > 0 ? (n * sil - si * sl) / den : hm;
    a.origin = n > 0 ? (sl - a.h * si) / n : o_med;
    a.lo = a.index[grid_first];
    a.hi = a.index[grid_last];
    const std::string c = kColName[d];
    const std::string extent = c + " in [" + num(a.level[grid_first]) + ", " + num(a.level[grid_last]) + "] mm";
    std::vector<char> off(nl, 0);
    bool any_off = false;
    for (std::size_t i = 0; i < nl; ++i) {
      if (extra[i]) continue;
      const double on_grid = a.origin + a.h * double(a.index[i]);
      // Two levels on one index: at least one is off by >= half a cell (both within the tolerance are
      // one coordinate printed two ways: the same node).
      if (!(std::abs(a.level[i] - on_grid) <= kLatticeTol * a.h)) off[i] = 1, any_off = true;
    }
    for (std::size_t r = 0; r < nrows; ++r) {
      const std::size_t i = a.row_level[r];
      if (extra[i])
        flag_row(r, where + " line " + std::to_string(line_of[r]) + ": the point " + row_point(r) +
                        " is an extra point, apart from the grid of the other rows (" + extent +
                        "): allowed only the points of one regular grid");
      else if (any_off && off[i])
        flag_row(r, where + " line " + std::to_string(line_of[r]) + ": " + c + " = " + num(a.level[i]) +
                        " mm is off the regular grid of the other rows (" + c + " = " + num(a.origin) + " + i*" +
                        num(a.h) + " mm, nearest " + num(a.origin + a.h * std::round((a.level[i] - a.origin) / a.h)) +
                        " mm): allowed within " + num(kLatticeTol) + " of a cell");
    }
  }
  if (first_bad_row < nrows) throw InputError(bad_message);
  for (int d = 0; d < 2; ++d)
    if (ax[d].level.size() < 2)
      throw InputError(where + ": all rows have " + kColName[d] + " = " + num(ax[d].level[0]) +
                       " mm: allowed a grid of at least 2 x 2 points (x and y)");

  // 3. Grid size, duplicates, missing points.
  long long n[3] = {1, 1, 1};
  for (int d = 0; d < naxes; ++d) n[d] = ax[d].hi - ax[d].lo + 1;
  const double nodes_d = double(n[0]) * double(n[1]) * double(n[2]);
  if (nodes_d > double(limits.max_nodes))
    throw InputError(where + ": the points span a grid of " + std::to_string(n[0]) + " x " + std::to_string(n[1]) +
                     " x " + std::to_string(n[2]) + " nodes: allowed at most " + std::to_string(limits.max_nodes) +
                     " nodes");
  const std::size_t nodes = std::size_t(nodes_d);
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
    throw InputError(where + " line " + std::to_string(line_of[dup]) + ": the point " + row_point(dup) +
                     " repeats line " + std::to_string(line_of[dup_of]) + ": allowed each grid point once");
  auto node_point = [&](std::size_t id) {
    double p[3] = {0, 0, plane_z_mm};
    for (int d = 0; d < naxes; ++d) {
      p[d] = ax[d].origin + ax[d].h * double(ax[d].lo + (long long)(id % std::size_t(n[d])));
      id /= std::size_t(n[d]);
    }
    return point_text(p[0], p[1], p[2]);
  };
  if (nrows != nodes) {
    std::size_t missing = 0;
    while (missing < nrows && node_of[order[missing]] == missing) ++missing;
    throw InputError(where + ": the grid point " + node_point(missing) + " is missing (" + std::to_string(nrows) +
                     " rows for a grid of " + std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " +
                     std::to_string(n[2]) + " points): allowed only complete regular grids");
  }

  // 4. GridData in node order (i fastest).
  GridData g;
  g.source = source;
  for (int d = 0; d < 3; ++d) g.dims[d] = int(n[d]);
  g.origin_mm = Vec3(ax[X].origin + ax[X].h * double(ax[X].lo), ax[Y].origin + ax[Y].h * double(ax[Y].lo),
                     has_z ? ax[Z].origin + ax[Z].h * double(ax[Z].lo) : plane_z_mm);
  g.spacing_mm = Vec3(ax[X].h, ax[Y].h, (has_z && n[2] > 1) ? ax[Z].h : 1.0);
  const bool has_B = col_of[BX] >= 0;
  g.Bz_T.resize(nodes);
  if (has_B) g.Bx_T.resize(nodes), g.By_T.resize(nodes);
  for (std::size_t r = 0; r < nrows; ++r) {
    g.Bz_T[node_of[r]] = vals[BZ][r];
    if (has_B) g.Bx_T[node_of[r]] = vals[BX][r], g.By_T[node_of[r]] = vals[BY][r];
  }
  g.validate();
  return g;
}

GridData read_field_table(const std::filesystem::path& file, double plane_z_mm, const FieldTableLimits& limits) {
  const std::string name = file.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw InputError("table " + name + " does not exist or is not a file (expected a text table of B on a regular grid)");
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) throw InputError("table " + name + ": cannot read its size: " + ec.message());
  if (bytes > limits.max_bytes)
    throw InputError("table " + name + " has " + std::to_string(bytes) + " bytes: allowed at most " +
                     std::to_string(limits.max_bytes));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("table " + name + " cannot be opened");
  std::string text(static_cast<std::size_t>(bytes), '\0');
  in.read(text.data(), std::streamsize(bytes));
  if (std::uintmax_t(in.gcount()) != bytes) throw InputError("table " + name + " could not be read completely");
  return parse_field_table(text, name, plane_z_mm, limits);
}

std::shared_ptr<GridField> table_field_from_file(const std::filesystem::path& file, const Config& cfg, Interp mode) {
  const double zs = sensing_plane_z_mm(cfg);
  GridData g = read_field_table(file, zs);
  if (g.is_plane() && !(std::abs(g.origin_mm.z() - zs) <= GridField::kPlaneTolerance_mm))
    throw InputError("table " + file.string() + " is one plane at z = " + num(g.origin_mm.z()) +
                     " mm but the sensing plane is z_s = " + num(zs) +
                     " mm (magnet frame): allowed a plane at z_s (or no z column) or several z levels");
  return std::make_shared<GridField>(std::move(g), mode, "table");
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
