#include "io/points_csv.hpp"

#include <algorithm>
#include <vector>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/text_table.hpp"
#include "fields/field_table.hpp"

namespace magenc {

namespace {

// A table of numbers under a header naming columns among `known`, through the one text-table reader
// (core/text_table.hpp: byte-order mark, CRLF, ';' with decimal commas, '#' comments). Returns one vector
// per known column (empty when the column is absent).
std::vector<std::vector<double>> parse_columns(const std::string& text, const std::string& where,
                                               const std::vector<std::string>& known) {
  const NumericTable t = parse_numeric_table(text, where, known);
  std::vector<std::vector<double>> cols(known.size());
  for (std::size_t k = 0; k < known.size(); ++k) {
    const int c = t.column(known[k]);
    if (c < 0) continue;
    cols[k].reserve(t.rows());
    for (std::size_t r = 0; r < t.rows(); ++r) cols[k].push_back(t.at(r, static_cast<std::size_t>(c)));
  }
  return cols;
}

void require_column(const std::vector<std::vector<double>>& cols, std::size_t k, const std::string& name,
                    const std::string& where, const std::string& allowed) {
  if (cols[k].empty()) throw InputError(where + ": missing column '" + name + "': allowed columns " + allowed);
}

// The readings against the unit the header claims: the largest |B| between 0.1 mT and 10 T, as a field
// table's (fields/field_table.hpp): all zeros, tesla under mT columns or mT under T columns fall outside.
void check_scan_magnitude(const ScanTable& s, const std::string& where, const FieldTableLimits& limits) {
  Eigen::Index row = 0, comp = 0;
  const double bmax = s.B_T.cols() > 0 ? s.B_T.cwiseAbs().maxCoeff(&comp, &row) : 0.0;
  const std::string range = largest_field_range_text(limits);
  const double in_unit = bmax * (s.unit == "T" ? 1.0 : 1e3);
  if (bmax == 0.0) throw InputError(where + ": every reading is zero: allowed a largest |B| above 0");
  if (bmax > limits.largest_field_max_T)
    throw InputError(where + ": column B" + std::string(1, char('x' + comp)) + "_" + s.unit + " holds " + num(in_unit) +
                     " " + s.unit + " (row " + std::to_string(row + 1) + "): " + range +
                     (s.unit == "T" ? " (readings in mT under a T header?" : " (") +
                     " readings at a magnet's face: raise checks.largest_field_max_T)");
  if (bmax < limits.largest_field_min_T)
    throw InputError(where + ": the largest reading is " + num(in_unit) + " " + s.unit + ": " + range +
                     (s.unit == "mT" ? " (readings in T under a mT header?" : " (") +
                     " a weak field: lower checks.largest_field_min_mT)");
}

}  // namespace

Eigen::Matrix3Xd parse_points_csv(const std::string& text, const std::string& where) {
  const std::vector<std::string> known{"x_mm", "y_mm", "z_mm"};
  const std::string allowed = "x_mm, y_mm, z_mm (mm, magnet frame)";
  const auto cols = parse_columns(text, where, known);
  for (std::size_t k = 0; k < 3; ++k) require_column(cols, k, known[k], where, allowed);
  Eigen::Matrix3Xd pts(3, static_cast<Eigen::Index>(cols[0].size()));
  for (int k = 0; k < 3; ++k)
    for (std::size_t j = 0; j < cols[0].size(); ++j) pts(k, static_cast<Eigen::Index>(j)) = cols[k][j];
  return pts;
}

ScanTable parse_scan_csv(const std::string& text, const std::string& where, const FieldTableLimits& limits) {
  const std::vector<std::string> known{"x_mm", "y_mm", "z_mm", "Bx_mT", "By_mT", "Bz_mT", "Bx_T", "By_T", "Bz_T"};
  const std::string allowed = "x_mm, y_mm, z_mm and Bx_mT, By_mT, Bz_mT or Bx_T, By_T, Bz_T";
  const auto cols = parse_columns(text, where, known);
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
  check_scan_magnitude(s, where, limits);
  return s;
}


ScanTable read_scan_csv(const std::filesystem::path& path, const FieldTableLimits& limits) {
  const std::string where = "--scan " + path.string();
  return parse_scan_csv(read_text_file(path, where), where, limits);
}

Eigen::Matrix3Xd read_points_csv(const std::filesystem::path& path) {
  const std::string where = "--points " + path.string();
  return parse_points_csv(read_text_file(path, where), where);
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
