#include "core/text_table.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"

namespace magenc {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

std::string_view trim_view(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && is_blank(s[b])) ++b;
  while (e > b && is_blank(s[e - 1])) --e;
  return s.substr(b, e - b);
}

const char* const kUtf16Clause =
    " is UTF-16 text (Excel's \"Unicode Text\"): allowed UTF-8 or ASCII text (in Excel: save as \"CSV UTF-8\")";

std::string where_line(const std::string& where, long line_no) { return where + " line " + std::to_string(line_no); }

// One cell starting at s[i] (after blanks), up to the separator or the end; i is left on the separator
// (or at the end). A quoted cell is unquoted ("" -> "); text after its closing quote is kept as written.
std::string next_cell(std::string_view s, std::size_t& i, char sep, const std::string& where, long line_no) {
  while (i < s.size() && s[i] != sep && is_blank(s[i])) ++i;
  std::string cell;
  if (i < s.size() && s[i] == '"') {
    ++i;
    while (true) {
      if (i >= s.size())
        throw InputError(where_line(where, line_no) +
                         ": a cell opens a double quote and does not close it: allowed cells in matching quotes");
      if (s[i] == '"') {
        if (i + 1 < s.size() && s[i + 1] == '"') {
          cell += '"';
          i += 2;
          continue;
        }
        ++i;
        break;
      }
      cell += s[i++];
    }
  }
  const std::size_t start = i;
  while (i < s.size() && s[i] != sep) ++i;
  cell += s.substr(start, i - start);
  return std::string(trim_view(cell));
}

}  // namespace

char detect_separator(std::string_view line) {
  bool quoted = false, semicolon = false, tab = false, comma = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    semicolon |= c == ';';
    tab |= c == '\t';
    comma |= c == ',';
  }
  return semicolon ? ';' : tab ? '\t' : comma ? ',' : ' ';
}

std::vector<std::string> split_cells(std::string_view line, char sep, const std::string& where, long line_no) {
  std::vector<std::string> cells;
  if (sep == ' ') {
    std::size_t i = 0;
    while (true) {
      while (i < line.size() && is_blank(line[i])) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && !is_blank(line[j])) ++j;
      std::string_view tok = line.substr(i, j - i);
      if (tok.size() >= 2 && tok.front() == '"' && tok.back() == '"') tok = trim_view(tok.substr(1, tok.size() - 2));
      cells.emplace_back(tok);
      i = j;
    }
    return cells;
  }
  std::size_t i = 0;
  while (true) {
    cells.push_back(next_cell(line, i, sep, where, line_no));
    if (i >= line.size()) break;
    ++i;  // the separator
  }
  return cells;
}

std::string separator_name(char sep) {
  switch (sep) {
    case ',': return "','";
    case ';': return "';'";
    case '\t': return "tab";
    default: return "blanks";
  }
}

CellNumber parse_number(std::string_view cell) {
  CellNumber r;
  if (cell.empty()) return r;  // Empty
  std::string s(cell);
  const auto comma = s.find(',');
  if (comma != std::string::npos) {
    if (s.find('.') != std::string::npos || s.find(',', comma + 1) != std::string::npos) {
      r.status = CellNumber::NotNumber;
      return r;
    }
    s[comma] = '.';
  }
  char* end = nullptr;
  double v = 0;
  {
    // strtod raises FE_OVERFLOW for 1e999 (reported as not finite): untrapped (fp_trap.hpp).
    const FpTrapPause parsing_input;
    v = std::strtod(s.c_str(), &end);
  }
  if (end == s.c_str() || end != s.c_str() + s.size() || std::isspace(static_cast<unsigned char>(s[0]))) {
    r.status = CellNumber::NotNumber;
    return r;
  }
  r.value = v;
  r.status = std::isfinite(v) ? CellNumber::Ok : CellNumber::NotFinite;
  return r;
}

std::string decimal_comma_hint(char separator, std::size_t cells, std::size_t expected) {
  if (separator != ',' || cells <= expected) return "";
  return "; a decimal comma between ',' separators splits numbers: with decimal commas separate the fields "
         "with ';' (as spreadsheet programs do)";
}

std::string utf16_hint(std::string_view text) {
  // UTF-16 text of ASCII characters has a NUL at every other byte (after the byte-order mark, if any).
  const std::size_t n = std::min<std::size_t>(text.size(), 512);
  std::size_t even = 0, odd = 0;
  for (std::size_t i = 0; i < n; ++i) (i % 2 ? odd : even) += text[i] == '\0';
  const bool utf16 = n >= 4 && (2 * odd >= n / 2 || 2 * even >= n / 2) && std::min(odd, even) * 8 < std::max(odd, even);
  if (!utf16) return "";
  return kUtf16Clause;
}

TextTableReader::TextTableReader(std::string_view text, std::string where, TextTableOptions options)
    : text_(text), where_(std::move(where)), options_(std::move(options)), separator_(options_.separator) {
  if (text_.size() >= 2 && ((text_[0] == '\xFF' && text_[1] == '\xFE') || (text_[0] == '\xFE' && text_[1] == '\xFF')))
    throw InputError(where_ + kUtf16Clause);
  if (text_.substr(0, 3) == "\xEF\xBB\xBF") {
    bom_ = true;
    pos_ = 3;
  }
}

bool TextTableReader::next(TextRow& row) {
  while (pos_ < text_.size()) {
    const std::size_t eol = text_.find_first_of("\r\n", pos_);
    const std::string_view raw = text_.substr(pos_, eol == std::string_view::npos ? std::string_view::npos : eol - pos_);
    if (eol == std::string_view::npos) pos_ = text_.size();
    else pos_ = eol + ((text_[eol] == '\r' && eol + 1 < text_.size() && text_[eol + 1] == '\n') ? 2 : 1);
    ++line_;
    if (raw.find('\0') != std::string_view::npos) {
      const std::string utf16 = utf16_hint(text_);
      if (!utf16.empty()) throw InputError(where_ + utf16);
      throw InputError(where_line(where_, line_) + " holds a NUL byte: allowed a text file (UTF-8 or ASCII)");
    }
    const std::string_view t = trim_view(raw);
    if (t.empty()) continue;
    if (options_.comment_marks.find(t[0]) != std::string::npos) {
      if (!content_seen_) comments_.push_back({line_, std::string(t), {}});
      continue;
    }
    // A line of empty cells (";;;", as spreadsheet programs write emptied rows) is blank too, and does not
    // decide the separator.
    const char sep = separator_ ? separator_ : detect_separator(t);
    row.cells = split_cells(t, sep, where_, line_);
    if (std::all_of(row.cells.begin(), row.cells.end(), [](const std::string& c) { return c.empty(); })) continue;
    // Trailing separators, as spreadsheet programs write a used range wider than the table ("a;b;"): the
    // first content line drops its trailing empty cells, later lines those beyond its count.
    if (sep != ' ') {
      const std::size_t keep = content_seen_ ? first_cells_ : 1;
      while (row.cells.size() > keep && row.cells.back().empty()) row.cells.pop_back();
      if (!content_seen_) first_cells_ = row.cells.size();
    }
    separator_ = sep;
    content_seen_ = true;
    row.line = line_;
    row.text.assign(t);
    return true;
  }
  return false;
}

std::string read_text_file(const std::filesystem::path& file, const std::string& what, std::uintmax_t max_bytes) {
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  if (std::filesystem::is_directory(status))
    throw InputError(what + " is a directory, not a file: allowed a readable text file");
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw InputError(what + " is not a regular file (a named pipe, socket or device is not read): allowed a readable "
                            "text file");
  if (!std::filesystem::is_regular_file(status))
    throw InputError(what + " does not exist or is not a file: allowed a readable text file");
  const std::uintmax_t bytes = std::filesystem::file_size(file, ec);
  if (ec) throw InputError(what + ": cannot read its size: " + ec.message());
  if (bytes > max_bytes)
    throw InputError(what + " has " + std::to_string(bytes) + " bytes: allowed at most " + std::to_string(max_bytes));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(what + " cannot be opened: allowed a readable text file");
  std::string text(static_cast<std::size_t>(bytes), '\0');
  in.read(text.data(), std::streamsize(bytes));
  if (std::uintmax_t(in.gcount()) != bytes) throw InputError(what + " could not be read completely");
  return text;
}

int NumericTable::column(const std::string& name) const {
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (columns[c] == name) return int(c);
  return -1;
}

NumericTable parse_numeric_table(std::string_view text, const std::string& where,
                                 const std::vector<std::string>& allowed, const TextTableOptions& options) {
  NumericTable t;
  t.where = where;
  TextTableReader reader(text, where, options);
  TextRow row;
  auto allowed_text = [&] {
    std::string s;
    for (const auto& a : allowed) s += (s.empty() ? "" : ", ") + a;
    return s;
  };
  if (!reader.next(row))
    throw InputError(where + " is empty: expected a header row naming the columns (allowed " +
                     (allowed.empty() ? std::string("any names") : allowed_text()) + ") and data rows");
  t.header_line = row.line;
  const std::string at_header = where_line(where, row.line);
  for (const auto& name : row.cells) {
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw InputError(at_header + ": unknown column '" + name + "': allowed columns " + allowed_text());
    if (t.column(name) >= 0) throw InputError(at_header + ": column '" + name + "' appears twice: allowed each column once");
    t.columns.push_back(name);
  }
  const std::size_t nc = t.columns.size();
  while (reader.next(row)) {
    const std::string at = where_line(where, row.line);
    if (row.cells.size() != nc)
      throw InputError(at + ": " + std::to_string(row.cells.size()) + " cells, the header has " + std::to_string(nc) +
                       " columns: allowed one number per column" +
                       decimal_comma_hint(reader.separator(), row.cells.size(), nc));
    for (std::size_t c = 0; c < nc; ++c) {
      const CellNumber n = parse_number(row.cells[c]);
      const std::string cell = at + ": column " + t.columns[c];
      if (n.status == CellNumber::Empty) throw InputError(cell + " is empty: allowed finite numbers");
      if (n.status == CellNumber::NotNumber)
        throw InputError(cell + " = '" + row.cells[c] + "' is not a number: allowed finite numbers");
      if (n.status == CellNumber::NotFinite)
        throw InputError(cell + " = '" + row.cells[c] + "' is not finite: allowed finite numbers");
      t.values.push_back(n.value);
    }
    t.line.push_back(row.line);
  }
  if (t.line.empty()) throw InputError(where + " has a header but no data rows: allowed at least one row");
  return t;
}

NumericTable read_numeric_table(const std::filesystem::path& file, const std::string& what,
                                const std::vector<std::string>& allowed, const TextTableOptions& options) {
  const std::string where = what + " " + file.string();
  const std::string text = read_text_file(file, where);
  return parse_numeric_table(text, where, allowed, options);
}

}  // namespace magenc
