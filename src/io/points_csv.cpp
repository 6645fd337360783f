#include "io/points_csv.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/fp_trap.hpp"

namespace magenc {

namespace {

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : line) {
    if (ch == ',') {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += ch;
    }
  }
  out.push_back(trim(cur));
  return out;
}

// A CSV of numbers with a header naming columns among `known`: '#' comments and blank lines ignored,
// CR LF accepted. Returns one vector per known column (empty when the column is absent); `allowed` is
// the text after "allowed" in errors; `unit` names the units of the numbers.
std::vector<std::vector<double>> parse_columns(const std::string& text, const std::string& where,
                                               const std::vector<std::string>& known, const std::string& allowed,
                                               const std::string& unit) {
  std::istringstream in(text);
  std::vector<int> column_of_cell;  // header cell i -> index in known
  std::vector<std::vector<double>> cols(known.size());
  std::string line;
  int line_no = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    const auto cells = split_commas(t);
    const std::string at = where + ":" + std::to_string(line_no);
    if (!header) {
      header = true;
      std::vector<bool> seen(known.size(), false);
      for (const auto& name : cells) {
        int c = -1;
        for (std::size_t k = 0; k < known.size(); ++k)
          if (name == known[k]) c = static_cast<int>(k);
        if (c < 0) throw InputError(at + ": unknown column '" + name + "': allowed columns " + allowed);
        if (seen[c]) throw InputError(at + ": column '" + name + "' appears twice: allowed columns " + allowed);
        seen[c] = true;
        column_of_cell.push_back(c);
      }
      continue;
    }
    if (cells.size() != column_of_cell.size())
      throw InputError(at + ": " + std::to_string(cells.size()) + " cells, header has " +
                       std::to_string(column_of_cell.size()) + ": allowed exactly one number per column");
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::string& cell = cells[i];
      char* end = nullptr;
      double v = NAN;
      if (!cell.empty()) {
        const FpTrapPause parsing_input;  // strtod raises FE_OVERFLOW for 1e999 (refused below)
        v = std::strtod(cell.c_str(), &end);
      }
      if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v))
        throw InputError(at + ": column " + known[column_of_cell[i]] + " = '" + cell +
                         "' is not a finite number: allowed finite numbers (" + unit + ")");
      cols[column_of_cell[i]].push_back(v);
    }
  }
  if (!header) throw InputError(where + ": no header row: allowed a header naming the columns " + allowed);
  std::size_t rows = 0;
  for (const auto& c : cols) rows = std::max(rows, c.size());
  if (rows == 0) throw InputError(where + ": no rows: allowed one or more rows after the header");
  return cols;
}

void require_column(const std::vector<std::vector<double>>& cols, std::size_t k, const std::string& name,
                    const std::string& where, const std::string& allowed) {
  if (cols[k].empty()) throw InputError(where + ": missing column '" + name + "': allowed columns " + allowed);
}

}  // namespace

Eigen::Matrix3Xd parse_points_csv(const std::string& text, const std::string& where) {
  const std::vector<std::string> known{"x_mm", "y_mm", "z_mm"};
  const std::string allowed = "x_mm, y_mm, z_mm (mm, magnet frame)";
  const auto cols = parse_columns(text, where, known, allowed, "mm");
  for (std::size_t k = 0; k < 3; ++k) require_column(cols, k, known[k], where, allowed);
  Eigen::Matrix3Xd pts(3, static_cast<Eigen::Index>(cols[0].size()));
  for (int k = 0; k < 3; ++k)
    for (std::size_t j = 0; j < cols[0].size(); ++j) pts(k, static_cast<Eigen::Index>(j)) = cols[k][j];
  return pts;
}

ScanTable parse_scan_csv(const std::string& text, const std::string& where) {
  const std::vector<std::string> known{"x_mm", "y_mm", "z_mm", "Bx_mT", "By_mT", "Bz_mT", "Bx_T", "By_T", "Bz_T"};
  const std::string allowed = "x_mm, y_mm, z_mm and Bx_mT, By_mT, Bz_mT or Bx_T, By_T, Bz_T";
  const auto cols = parse_columns(text, where, known, allowed, "mm, mT or T");
  for (std::size_t k = 0; k < 3; ++k) require_column(cols, k, known[k], where, allowed);
  const bool mT = !cols[3].empty() || !cols[4].empty() || !cols[5].empty();
  const bool T = !cols[6].empty() || !cols[7].empty() || !cols[8].empty();
  if (mT && T) throw InputError(where + ": field columns in both mT and T: allowed columns " + allowed);
  const std::size_t b0 = T ? 6 : 3;
  for (std::size_t k = b0; k < b0 + 3; ++k) require_column(cols, k, known[k], where, allowed);
  ScanTable s;
  const auto n = static_cast<Eigen::Index>(cols[0].size());
  s.p_mm.resize(3, n);
  s.B_T.resize(3, n);
  for (int k = 0; k < 3; ++k)
    for (Eigen::Index j = 0; j < n; ++j) {
      s.p_mm(k, j) = cols[k][j];
      s.B_T(k, j) = cols[b0 + k][j] * (T ? 1.0 : 1e-3);
    }
  s.unit = T ? "T" : "mT";
  return s;
}

namespace {
std::string slurp_file(const std::filesystem::path& path, const std::string& where) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(where + ": cannot open file: allowed a readable CSV file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

ScanTable read_scan_csv(const std::filesystem::path& path) {
  const std::string where = "--scan " + path.string();
  return parse_scan_csv(slurp_file(path, where), where);
}

Eigen::Matrix3Xd read_points_csv(const std::filesystem::path& path) {
  const std::string where = "--points " + path.string();
  return parse_points_csv(slurp_file(path, where), where);
}

std::string points_field_csv(const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& B) {
  std::string out = "x_mm,y_mm,z_mm,Bx_T,By_T,Bz_T\n";
  for (Eigen::Index j = 0; j < p.cols(); ++j) {
    for (int k = 0; k < 3; ++k) out += fmt_sig(p(k, j), 17) + ",";
    out += fmt_sig(B(0, j), 17) + "," + fmt_sig(B(1, j), 17) + "," + fmt_sig(B(2, j), 17) + "\n";
  }
  return out;
}

}  // namespace magenc
