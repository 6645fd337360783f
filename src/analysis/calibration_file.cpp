#include "analysis/calibration_file.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/text_table.hpp"

namespace magenc {

namespace {

std::string g17(double v) { return fmt_sig(v, 17); }

// A correction's angles (lut_deg, a_deg, b_deg, phase_deg) lie within a turn; the ellipse's offsets and gain
// ratio are ratios of channel amplitudes (1e6 is far beyond any sensor's).
constexpr double kMaxCorrection_deg = 360.0;
constexpr double kMaxEllipseConstant = 1e6;

}  // namespace

std::string correction_csv(const Correction& c) {
  std::ostringstream os;
  os << "# magenc correction: psi' = psi - e(psi) (harmonics, lut), or the channel ellipse inverted (ogp)\n";
  os << "quantity,index,value\n";
  os << "method,0," << c.method.name() << "\n";
  os << "turns,0," << c.turns << "\n";
  switch (c.method.kind) {
    case CalibrationKind::Harmonics:
      for (int n = 0; n <= c.method.order; ++n) os << "a_deg," << n << "," << g17(c.harmonics_deg[n == 0 ? 0 : 2 * n - 1]) << "\n";
      for (int n = 1; n <= c.method.order; ++n) os << "b_deg," << n << "," << g17(c.harmonics_deg[2 * n]) << "\n";
      break;
    case CalibrationKind::Lut:
      for (Eigen::Index k = 0; k < c.lut_deg.size(); ++k) os << "lut_deg," << k << "," << g17(c.lut_deg[k]) << "\n";
      break;
    case CalibrationKind::Ogp:
      os << "offset_cos,0," << g17(c.ellipse.offset_cos) << "\n";
      os << "offset_sin,0," << g17(c.ellipse.offset_sin) << "\n";
      os << "gain_ratio,0," << g17(c.ellipse.gain_ratio) << "\n";
      os << "phase_deg,0," << g17(c.ellipse.phase_deg) << "\n";
      break;
    case CalibrationKind::None:
      break;
  }
  return os.str();
}

std::string correction_json(const Correction& c) {
  std::ostringstream os;
  os << "{\n  \"method\": \"" << c.method.name() << "\",\n  \"turns\": " << c.turns;
  auto list = [&](const char* name, const std::vector<double>& v) {
    os << ",\n  \"" << name << "\": [";
    for (std::size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << g17(v[i]);
    os << "]";
  };
  switch (c.method.kind) {
    case CalibrationKind::Harmonics: {
      std::vector<double> a{c.harmonics_deg[0]}, b{0.0};
      for (int n = 1; n <= c.method.order; ++n) {
        a.push_back(c.harmonics_deg[2 * n - 1]);
        b.push_back(c.harmonics_deg[2 * n]);
      }
      list("a_deg", a);  // a_deg[n], n = 0..N
      list("b_deg", b);  // b_deg[n], n = 0..N (b_deg[0] = 0)
      break;
    }
    case CalibrationKind::Lut: {
      std::vector<double> v(c.lut_deg.data(), c.lut_deg.data() + c.lut_deg.size()), at;
      for (Eigen::Index k = 0; k < c.lut_deg.size(); ++k) at.push_back(360.0 * static_cast<double>(k) / static_cast<double>(c.lut_deg.size()));
      list("lut_psi_deg", at);
      list("lut_deg", v);
      break;
    }
    case CalibrationKind::Ogp:
      os << ",\n  \"offset_cos\": " << g17(c.ellipse.offset_cos) << ",\n  \"offset_sin\": " << g17(c.ellipse.offset_sin)
         << ",\n  \"gain_ratio\": " << g17(c.ellipse.gain_ratio) << ",\n  \"phase_deg\": " << g17(c.ellipse.phase_deg);
      break;
    case CalibrationKind::None:
      break;
  }
  os << "\n}\n";
  return os.str();
}

namespace {

// The rows of a correction table, checked one by one (header, cell count, index, numbers, each quantity
// and index once); which constants a method needs is checked by the caller.
struct CorrectionRows {
  std::string method_text;
  long method_line = 0;
  long turns = 0;
  std::map<std::string, std::map<long, double>> values;  // quantity -> index -> value
};
CorrectionRows read_correction_rows(const std::string& text, const std::string& origin) {
  const std::string allowed_q = "method, turns, lut_deg, a_deg, b_deg, offset_cos, offset_sin, gain_ratio, phase_deg";
  TextTableReader reader(text, "correction " + origin);
  TextRow row;
  if (!reader.next(row)) throw InputError("correction " + origin + " is empty: allowed a header quantity,index,value and rows");
  if (row.cells != std::vector<std::string>{"quantity", "index", "value"})
    throw InputError("correction " + origin + " line " + std::to_string(row.line) +
                     ": header is not quantity,index,value: allowed quantity,index,value");
  CorrectionRows out;
  std::string& method_text = out.method_text;
  long& turns = out.turns;
  auto& values = out.values;
  long& method_line = out.method_line;
  while (reader.next(row)) {
    const std::string at = "correction " + origin + " line " + std::to_string(row.line);
    if (row.cells.size() != 3)
      throw InputError(at + " has " + std::to_string(row.cells.size()) + " cells: allowed 3 (quantity,index,value)");
    const std::string& q = row.cells[0];
    const CellNumber idx = parse_number(row.cells[1]);
    if (!idx.ok() || idx.value != std::floor(idx.value) || idx.value < 0 || idx.value > CalibrationMethod::kMaxLut)
      throw InputError(at + ": index '" + row.cells[1] + "' is not valid: allowed an integer in [0, " +
                       std::to_string(CalibrationMethod::kMaxLut) + "]");
    const long i = static_cast<long>(idx.value);
    if (q == "method") {
      if (!method_text.empty()) throw InputError(at + ": method is given twice: allowed once");
      if (row.cells[2].empty()) throw InputError(at + ": method is empty: allowed none, harmonics:N, lut:K, ogp");
      method_text = row.cells[2];
      method_line = row.line;
      continue;
    }
    const CellNumber v = parse_number(row.cells[2]);
    if (!v.ok()) throw InputError(at + ": " + q + " value '" + row.cells[2] + "' is not a finite number: allowed a number");
    if (q == "turns") {
      if (turns != 0) throw InputError(at + ": turns is given twice: allowed once");
      if (v.value != 1 && v.value != 2) throw InputError(at + ": turns = " + row.cells[2] + ": allowed 1 or 2");
      turns = static_cast<long>(v.value);
      continue;
    }
    if (q != "lut_deg" && q != "a_deg" && q != "b_deg" && q != "offset_cos" && q != "offset_sin" && q != "gain_ratio" &&
        q != "phase_deg")
      throw InputError(at + ": unknown quantity '" + q + "': allowed " + allowed_q);
    if ((q == "lut_deg" || q == "a_deg" || q == "b_deg" || q == "phase_deg") && !(std::abs(v.value) <= kMaxCorrection_deg))
      throw InputError(at + ": " + q + " = " + row.cells[2] + ": allowed an angle in [-" + num(kMaxCorrection_deg) +
                       ", " + num(kMaxCorrection_deg) + "] deg");
    if ((q == "offset_cos" || q == "offset_sin" || q == "gain_ratio") && !(std::abs(v.value) <= kMaxEllipseConstant))
      throw InputError(at + ": " + q + " = " + row.cells[2] + ": allowed |value| <= " + num(kMaxEllipseConstant));
    if (!values[q].emplace(i, v.value).second)
      throw InputError(at + ": " + q + " index " + std::to_string(i) + " is given twice: allowed once");
  }
  return out;
}

}  // namespace

Correction parse_correction_csv(const std::string& text, const std::string& origin) {
  CorrectionRows rows = read_correction_rows(text, origin);
  const std::string& method_text = rows.method_text;
  const long turns = rows.turns;
  auto& values = rows.values;
  const long method_line = rows.method_line;
  const std::string where = "correction " + origin;
  if (method_text.empty()) throw InputError(where + " has no method row: allowed method,0,<none | harmonics:N | lut:K | ogp>");
  Correction c;
  c.method = CalibrationMethod::parse(method_text, where + " line " + std::to_string(method_line) + " method");
  c.turns = turns == 0 ? 1 : static_cast<int>(turns);
  // Exactly the constants of the method, each index once.
  const auto expect = [&](const std::string& q, long first, long count) {
    const auto it = values.find(q);
    const long have = it == values.end() ? 0 : static_cast<long>(it->second.size());
    if (have != count || (count > 0 && (it->second.begin()->first != first || it->second.rbegin()->first != first + count - 1)))
      throw InputError(where + ": " + c.method.name() + " has " + std::to_string(have) + " " + q +
                       " rows or other indices: allowed " + std::to_string(count) + " rows, index " +
                       std::to_string(first) + " to " + std::to_string(first + count - 1));
  };
  std::vector<std::string> used;
  switch (c.method.kind) {
    case CalibrationKind::Harmonics: {
      const int N = c.method.order;
      expect("a_deg", 0, N + 1);
      expect("b_deg", 1, N);
      c.harmonics_deg.resize(2 * N + 1);
      c.harmonics_deg[0] = values["a_deg"][0];
      for (int n = 1; n <= N; ++n) {
        c.harmonics_deg[2 * n - 1] = values["a_deg"][n];
        c.harmonics_deg[2 * n] = values["b_deg"][n];
      }
      used = {"a_deg", "b_deg"};
      break;
    }
    case CalibrationKind::Lut: {
      const int K = c.method.order;
      expect("lut_deg", 0, K);
      c.lut_deg.resize(K);
      for (int k = 0; k < K; ++k) c.lut_deg[k] = values["lut_deg"][k];
      used = {"lut_deg"};
      break;
    }
    case CalibrationKind::Ogp: {
      for (const char* q : {"offset_cos", "offset_sin", "gain_ratio", "phase_deg"}) expect(q, 0, 1);
      c.ellipse.offset_cos = values["offset_cos"][0];
      c.ellipse.offset_sin = values["offset_sin"][0];
      c.ellipse.gain_ratio = values["gain_ratio"][0];
      c.ellipse.phase_deg = values["phase_deg"][0];
      if (!(c.ellipse.gain_ratio > 0))
        throw InputError(where + ": gain_ratio = " + num(c.ellipse.gain_ratio) + ": allowed > 0");
      if (!(std::abs(c.ellipse.phase_deg) < 90))
        throw InputError(where + ": phase_deg = " + num(c.ellipse.phase_deg) + ": allowed |phase| < 90");
      used = {"offset_cos", "offset_sin", "gain_ratio", "phase_deg"};
      break;
    }
    case CalibrationKind::None:
      break;
  }
  for (const auto& [q, m] : values) {
    bool ok = false;
    for (const auto& u : used) ok = ok || u == q;
    if (!ok && !m.empty())
      throw InputError(where + ": " + q + " rows do not belong to method " + c.method.name() + ": allowed only its constants");
  }
  return c;
}

Correction read_correction_csv(const std::string& path) {
  return parse_correction_csv(read_text_file(path, "correction " + path, std::uintmax_t(1) << 26), path);
}

}  // namespace magenc
