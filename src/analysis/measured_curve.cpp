#include "analysis/measured_curve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numeric>
#include <sstream>

#include "core/errors.hpp"
#include "core/text_table.hpp"
#include "core/units.hpp"
#include "probe/spectrum.hpp"

namespace magenc {

namespace {

// A finite number filling the whole cell, else InputError naming origin, row and column.
double parse_cell(const std::string& cell, const std::string& origin, int row, const std::string& column) {
  const std::string where = origin + " row " + std::to_string(row) + " column " + column;
  const CellNumber n = parse_number(cell);
  if (n.status == CellNumber::Empty) throw InputError(where + " is empty: allowed a finite number");
  if (n.status == CellNumber::NotNumber)
    throw InputError(where + " = '" + cell + "' is not a number: allowed a finite number");
  if (n.status == CellNumber::NotFinite)
    throw InputError(where + " = '" + cell + "' is not finite: allowed a finite number");
  return n.value;
}

// Column indices of a curve file (-1: absent).
struct CurveColumns {
  int i_theta, i_err, i_phi, i_uc, i_us;
};

// 1. Header: the first non-blank, non-comment line.
CurveColumns read_curve_header(TextTableReader& reader, TextRow& line, const std::string& origin,
                               const CurveReadOptions& opts, MeasuredCurve& c, int& lineno,
                               std::vector<std::string>& header) {
  if (reader.next(line)) {
    lineno = int(line.line);
    header = line.cells;
  }
  const std::string allowed = "allowed headers theta_deg,error_deg | theta_deg,phi_deg | theta_deg,u_cos,u_sin";
  if (header.empty()) throw InputError(origin + " has no header row: " + allowed);
  int i_theta = -1, i_err = -1, i_phi = -1, i_uc = -1, i_us = -1;
  for (int i = 0; i < static_cast<int>(header.size()); ++i) {
    const std::string& h = header[i];
    int* slot = h == "theta_deg" ? &i_theta : h == "error_deg" ? &i_err : h == "phi_deg" ? &i_phi
              : h == "u_cos"     ? &i_uc    : h == "u_sin"     ? &i_us  : nullptr;
    if (!slot) throw InputError(origin + " row " + std::to_string(lineno) + ": unknown column '" + h + "': " + allowed);
    if (*slot >= 0) throw InputError(origin + " row " + std::to_string(lineno) + ": column '" + h + "' appears twice");
    *slot = i;
  }
  if (i_theta < 0) throw InputError(origin + " row " + std::to_string(lineno) + ": no theta_deg column: " + allowed);
  const int formats = (i_err >= 0) + (i_phi >= 0) + ((i_uc >= 0 || i_us >= 0) ? 1 : 0);
  if (formats != 1 || ((i_uc >= 0) != (i_us >= 0)))
    throw InputError(origin + " row " + std::to_string(lineno) + ": columns do not form one curve format: " + allowed);
  c.format = i_err >= 0 ? "error_deg" : i_phi >= 0 ? "phi_deg" : "raw";
  if (opts.error_sign != 1 && opts.error_sign != -1)
    throw InputError("--error-sign " + std::to_string(opts.error_sign) + " is invalid: allowed +1 or -1");
  if (opts.error_sign != 1 && c.format != "error_deg")
    throw InputError("--error-sign -1 applies to theta_deg,error_deg files only; " + origin + " has " + c.format +
                     " columns: allowed --error-sign +1");

  return {i_theta, i_err, i_phi, i_uc, i_us};
}

// 3. Count, coverage, folding, gaps.
void check_curve_coverage(MeasuredCurve& c, const std::string& origin, const CurveReadOptions& opts,
                          const std::vector<double>& theta_raw, const std::vector<double>& err,
                          const std::vector<int>& rows) {
  const int n = static_cast<int>(theta_raw.size());
  if (n < opts.min_points)
    throw InputError(origin + " has " + std::to_string(n) + " distinct data rows: allowed at least " +
                     std::to_string(opts.min_points));
  const auto [mn, mx] = std::minmax_element(theta_raw.begin(), theta_raw.end());
  c.raw_span_deg = *mx - *mn;
  c.turns = c.raw_span_deg / 360.0;
  if (c.raw_span_deg < 360.0 - opts.max_gap_deg)
    throw InputError(origin + " covers only " + num(c.raw_span_deg) + " deg of theta (rows " +
                     std::to_string(rows[mn - theta_raw.begin()]) + " to " + std::to_string(rows[mx - theta_raw.begin()]) +
                     "): allowed at least one turn (360 deg less the largest allowed gap, " + num(opts.max_gap_deg) +
                     " deg)");
  std::vector<double> folded(n);
  for (int i = 0; i < n; ++i) {
    double f = std::fmod(theta_raw[i], 360.0);
    if (f < 0) f += 360.0;
    if (f >= 360.0) f = 0.0;
    folded[i] = f;
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return folded[a] < folded[b]; });
  c.theta_deg.resize(n);
  c.error_deg.resize(n);
  c.row.resize(n);
  for (int i = 0; i < n; ++i) {
    c.theta_deg[i] = folded[order[i]];
    c.error_deg[i] = err[order[i]];
    c.row[i] = rows[order[i]];
  }
  std::vector<double> steps(n);
  for (int i = 0; i < n; ++i)
    steps[i] = (i + 1 < n ? c.theta_deg[i + 1] : c.theta_deg[0] + 360.0) - c.theta_deg[i];
  std::vector<double> sorted_steps = steps;
  std::nth_element(sorted_steps.begin(), sorted_steps.begin() + n / 2, sorted_steps.end());
  c.median_step_deg = sorted_steps[n / 2];
  const double report_above = std::max(5.0 * c.median_step_deg, 2.0);
  int widest = 0;
  for (int i = 0; i < n; ++i) {
    if (steps[i] > steps[widest]) widest = i;
    if (steps[i] > report_above)
      c.gaps.push_back({c.theta_deg[i], i + 1 < n ? c.theta_deg[i + 1] : c.theta_deg[0], steps[i]});
  }
  std::sort(c.gaps.begin(), c.gaps.end(), [](const CurveGap& a, const CurveGap& b) { return a.width_deg > b.width_deg; });
  c.largest_gap_deg = steps[widest];
  if (c.largest_gap_deg > opts.max_gap_deg) {
    const int next = widest + 1 < n ? widest + 1 : 0;
    throw InputError(origin + ": gap of " + num(c.largest_gap_deg) + " deg between theta = " +
                     num(c.theta_deg[widest]) + " (row " + std::to_string(c.row[widest]) + ") and " +
                     num(c.theta_deg[next]) + " deg (row " + std::to_string(c.row[next]) +
                     ") after folding: allowed gaps up to " + num(opts.max_gap_deg) + " deg");
  }
}

}  // namespace

MeasuredCurve parse_measured_curve(const std::string& text, const std::string& origin,
                                   const CurveReadOptions& opts) {
  MeasuredCurve c;
  c.path = origin;
  // Lines, cells and numbers as spreadsheet programs write them (core/text_table.hpp).
  TextTableReader reader(text, origin);
  TextRow line;
  int lineno = 0;
  std::vector<std::string> header;
  const auto [i_theta, i_err, i_phi, i_uc, i_us] = read_curve_header(reader, line, origin, opts, c, lineno, header);

  // 2. Rows.
  std::vector<double> theta_raw, err;
  std::vector<int> rows;
  std::map<double, std::pair<double, int>> seen;  // raw theta -> (error, row)
  std::map<int, std::pair<double, double>> channels_of_row;  // raw format: row -> (u_cos, u_sin)
  while (reader.next(line)) {
    lineno = int(line.line);
    const auto& cells = line.cells;
    if (cells.size() != header.size())
      throw InputError(origin + " row " + std::to_string(lineno) + " has " + std::to_string(cells.size()) +
                       " cells: allowed " + std::to_string(header.size()) + " (as the header)" +
                       decimal_comma_hint(reader.separator(), cells.size(), header.size()));
    const double th = parse_cell(cells[i_theta], origin, lineno, "theta_deg");
    if (std::abs(th) > 1e7)
      throw InputError(origin + " row " + std::to_string(lineno) + " theta_deg = " + num(th) +
                       " is out of range: allowed |theta| <= 1e7 deg");
    double e = 0;
    if (c.format == "error_deg") {
      e = opts.error_sign * parse_cell(cells[i_err], origin, lineno, "error_deg");
    } else if (c.format == "phi_deg") {
      e = parse_cell(cells[i_phi], origin, lineno, "phi_deg") - th;
    } else {
      const double uc = parse_cell(cells[i_uc], origin, lineno, "u_cos");
      const double us = parse_cell(cells[i_us], origin, lineno, "u_sin");
      if (uc == 0 && us == 0)
        throw InputError(origin + " row " + std::to_string(lineno) +
                         ": u_cos = u_sin = 0 gives no angle: allowed channels not both zero");
      e = rad_to_deg(std::atan2(us, uc)) - th;
      channels_of_row[lineno] = {uc, us};
    }
    e = wrap_deg(std::fmod(e, 360.0));
    const auto it = seen.find(th);
    if (it != seen.end()) {
      if (std::abs(wrap_deg(it->second.first - e)) > 1e-9)
        throw InputError(origin + " row " + std::to_string(lineno) + ": theta_deg = " + num(th) +
                         " repeats row " + std::to_string(it->second.second) +
                         " with a different value: allowed each angle once (or repeated with the same value)");
      ++c.duplicates;
      continue;
    }
    seen.emplace(th, std::make_pair(e, lineno));
    theta_raw.push_back(th);
    err.push_back(e);
    rows.push_back(lineno);
  }

  check_curve_coverage(c, origin, opts, theta_raw, err, rows);
  if (c.format == "raw") {
    c.channels.resize(c.theta_deg.size(), 2);
    for (Eigen::Index i = 0; i < c.theta_deg.size(); ++i) {
      const auto& [uc, us] = channels_of_row.at(c.row[i]);
      c.channels(i, 0) = uc;
      c.channels(i, 1) = us;
    }
  }
  return c;
}

MeasuredCurve read_measured_curve(const std::string& path, const CurveReadOptions& opts) {
  // A regular file only (a directory or a named pipe is refused, not read); NUL bytes and UTF-16 are refused
  // by the text-table reader, naming the line.
  const std::string where = "measured curve " + path;
  const std::string text = read_text_file(path, where, std::uintmax_t(1) << 28);
  if (text.find('\0') != std::string::npos) {
    const std::string utf16 = utf16_hint(text);
    throw InputError(where + (utf16.empty() ? " contains NUL bytes: allowed a text CSV file" : utf16));
  }
  return parse_measured_curve(text, path, opts);
}

}  // namespace magenc
