#include "io/tables.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/text_table.hpp"

namespace magenc {

namespace {

// Numbers in tables: 10 significant digits (%.10g), enough for every result.
std::string table_num(double v) { return fmt_sig(v, 10); }

// A text cell, quoted (RFC 4180) when it holds a comma, quote or newline.
std::string cell(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

template <class Row>
void check_same_extras(const std::vector<Row>& rows, const char* table) {
  for (const auto& r : rows) {
    if (r.extra.size() != rows.front().extra.size())
      throw std::invalid_argument(std::string(table) + ": rows carry different extra columns");
    for (std::size_t i = 0; i < r.extra.size(); ++i)
      if (r.extra[i].first != rows.front().extra[i].first)
        throw std::invalid_argument(std::string(table) + ": rows carry different extra columns");
  }
}

}  // namespace

std::string spectra_csv(const std::vector<SpectrumRow>& rows) {
  check_same_extras(rows, "spectra table");
  // A multipole read adds ce1..ce4 after pp (docs/interfaces.md): every row or none.
  const bool electrical = !rows.empty() && rows.front().spectrum.pole_pairs > 0;
  for (const auto& r : rows)
    if ((r.spectrum.pole_pairs > 0) != electrical)
      throw std::invalid_argument("spectra table: rows of multipole and other reads mixed (ce1..ce4 in some only)");
  std::ostringstream os;
  os << "field,array,r0_mm,sx_mm,sy_mm,dx_mm,dy_mm,dz_mm";
  for (const auto& c : spectrum_columns()) os << ',' << c;
  if (electrical)
    for (const auto& c : electrical_columns()) os << ',' << c;
  if (!rows.empty())
    for (const auto& [name, text] : rows.front().extra) os << ',' << cell(name);
  os << '\n';
  for (const auto& r : rows) {
    os << cell(r.field) << ',' << cell(r.array) << ',' << table_num(r.r0_mm) << ',' << table_num(r.mount.sx_mm) << ','
       << table_num(r.mount.sy_mm) << ',' << table_num(r.mount.dx_mm) << ',' << table_num(r.mount.dy_mm) << ','
       << table_num(r.mount.dz_mm);
    for (const auto& c : spectrum_columns()) os << ',' << table_num(r.spectrum.column(c));
    if (electrical)
      for (const double v : r.spectrum.ce_deg) os << ',' << table_num(v);
    for (const auto& [name, text] : r.extra) os << ',' << cell(text);
    os << '\n';
  }
  return os.str();
}

std::string fits_csv(const std::vector<FitRow>& rows) {
  check_same_extras(rows, "fits table");
  std::ostringstream os;
  os << "study,swept,coef,p3,p2,p1,p0";
  if (!rows.empty())
    for (const auto& [name, text] : rows.front().extra) os << ',' << cell(name);
  os << '\n';
  for (const auto& r : rows) {
    os << cell(r.study) << ',' << cell(r.swept) << ',' << cell(r.coef);
    for (double v : r.p) os << ',' << table_num(v);
    for (const auto& [name, text] : r.extra) os << ',' << cell(text);
    os << '\n';
  }
  return os.str();
}

std::vector<Mount> read_cases_csv(const std::filesystem::path& path) {
  const std::string where = "--cases " + path.string();
  const std::string allowed_cols =
      "allowed columns sx_mm, sy_mm, dx_mm, dy_mm, dz_mm, tilt_x_deg, tilt_y_deg, magnet_tilt_deg, "
      "magnet_tilt_azimuth_deg";
  static const char* const known[] = {"sx_mm",      "sy_mm",      "dx_mm",           "dy_mm",
                                      "dz_mm",      "tilt_x_deg", "tilt_y_deg",      "magnet_tilt_deg",
                                      "magnet_tilt_azimuth_deg"};
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(where + ": cannot open file");
  const std::string text = read_text_file(path, where);
  // Lines, cells and numbers as spreadsheet programs write them (core/text_table.hpp).
  TextTableReader reader(text, where);
  std::vector<std::string> header;
  std::vector<Mount> cases;
  TextRow line;
  while (reader.next(line)) {
    const auto& cells = line.cells;
    const std::string at = where + ":" + std::to_string(line.line);
    if (header.empty()) {
      // 1. Header: known, distinct column names.
      for (const auto& name : cells) {
        bool ok = false;
        for (const char* k : known) ok = ok || name == k;
        if (!ok)
          throw InputError(at + ": unknown column '" + name + "': " + allowed_cols);
        for (const auto& h : header)
          if (h == name) throw InputError(at + ": column '" + name + "' appears twice: " + allowed_cols);
        header.push_back(name);
      }
      continue;
    }
    // 2. Data row: one finite number per header column.
    if (cells.size() != header.size())
      throw InputError(at + ": " + std::to_string(cells.size()) + " cells, header has " +
                       std::to_string(header.size()) + ": allowed exactly one number per column" +
                       decimal_comma_hint(reader.separator(), cells.size(), header.size()));
    Mount m;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const CellNumber n = parse_number(cells[i]);
      if (!n.ok())
        throw InputError(at + ": column " + header[i] + " = '" + cells[i] +
                         "' is not a finite number: allowed finite numbers (mm, deg)");
      const double v = n.value;
      if (header[i] == "sx_mm") m.sx_mm = v;
      else if (header[i] == "sy_mm") m.sy_mm = v;
      else if (header[i] == "dx_mm") m.dx_mm = v;
      else if (header[i] == "dy_mm") m.dy_mm = v;
      else if (header[i] == "dz_mm") m.dz_mm = v;
      else if (header[i] == "tilt_x_deg") m.tilt_x_deg = v;
      else if (header[i] == "tilt_y_deg") m.tilt_y_deg = v;
      else if (header[i] == "magnet_tilt_deg") m.magnet_tilt_deg = v;
      else m.magnet_tilt_azimuth_deg = v;
    }
    try {
      m.validate();  // tilt ranges
    } catch (const InputError& e) {
      throw InputError(at + ": " + e.what());
    }
    cases.push_back(m);
  }
  if (header.empty()) throw InputError(where + ": empty file: expected a header row (" + allowed_cols + ")");
  if (cases.empty()) throw InputError(where + ": no data rows: allowed at least one case");
  return cases;
}

}  // namespace magenc
