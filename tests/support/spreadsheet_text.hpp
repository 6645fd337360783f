// Test helper: a plain CSV text (',' between fields, '.' decimals, LF line ends) rewritten the way
// spreadsheet programs save it: Excel's "CSV UTF-8" (a byte-order mark), Windows line ends, the
// European form (';' between fields, decimal comma), tab-separated text with a decimal comma, trailing
// separators.
#pragma once
#include <string>

namespace magenc::test {

inline std::string with_bom(const std::string& text) { return "\xEF\xBB\xBF" + text; }

// Every LF becomes CR LF (Windows), or CR alone (classic Mac OS) with cr_only.
inline std::string with_crlf(const std::string& text, bool cr_only = false) {
  std::string out;
  for (char c : text) out += c == '\n' ? std::string(cr_only ? "\r" : "\r\n") : std::string(1, c);
  return out;
}

// Lines that are not comments ('#', '%'): ',' -> sep, then '.' -> ',' (decimal comma).
inline std::string european(const std::string& text, char sep = ';') {
  std::string out, line;
  auto flush = [&] {
    const bool comment = !line.empty() && (line[0] == '#' || line[0] == '%');
    if (!comment)
      for (char& c : line) c = c == ',' ? sep : c == '.' ? ',' : c;
    out += line;
    line.clear();
  };
  for (char c : text) {
    if (c == '\n') {
      flush();
      out += '\n';
    } else {
      line += c;
    }
  }
  flush();
  return out;
}

// One more separator (`extra` of them) at the end of every line that is not a comment, as spreadsheet
// programs write a used range wider than the table ("theta_deg;error_deg;").
inline std::string trailing_separators(const std::string& text, char sep = ';', int extra = 1) {
  std::string out, line;
  auto flush = [&] {
    const bool comment = line.empty() || line[0] == '#' || line[0] == '%';
    out += line + (comment ? std::string() : std::string(std::size_t(extra), sep));
    line.clear();
  };
  for (char c : text) {
    if (c == '\n') {
      flush();
      out += '\n';
    } else {
      line += c;
    }
  }
  if (!line.empty()) flush();
  return out;
}

}  // namespace magenc::test
