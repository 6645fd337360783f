// Text tables as spreadsheet programs and other tools write them: the one reader of lines, cells and
// numbers behind every CSV and text-table reader of magenc (measured curves, mounting cases, field
// tables, and any new reader of points or scans).
//
// Recognised from the content, in one code path (no option to choose a dialect):
//   - a UTF-8 byte-order mark at the start is skipped (Excel's "CSV UTF-8");
//   - line ends LF, CR LF (Windows) or CR alone (classic Mac OS);
//   - lines that are blank, hold only empty cells (";;;": emptied spreadsheet rows), or whose first
//     non-blank character is one of the comment marks are skipped (the comment lines before the first
//     content line are kept: some formats carry units there);
//   - the separator, from the first content line (outside double quotes): ';' if it has one (the form
//     spreadsheet programs write where the decimal mark is a comma), else a tab, else ',', else runs of
//     blanks (spaces and tabs);
//   - cells are trimmed of blanks; a cell may be wrapped in double quotes, and may then hold the
//     separator ("" inside quotes is one quote);
//   - trailing separators (spreadsheet programs write "a;b;" for a used range wider than the table): the
//     first content line drops its trailing empty cells, every later line its trailing empty cells beyond
//     the first line's count (so "1;;" under a 3-column header still has an empty third cell);
//   - numbers (parse_number): the syntax of strtod in the C locale, with '.' or ',' as the decimal mark
//     ("0,25" = 0.25: a comma can only be inside a cell when ',' is not the separator, or in quotes).
// Refused (InputError, one line "WHERE ...: ... allowed ..."): UTF-16 text (a byte-order mark FF FE or
// FE FF: Excel's "Unicode Text", or without one a NUL at every other byte), a NUL byte, a quoted cell
// without its closing quote.
//
// Use: a TextTableReader and its rows, each reader keeping its own messages for cells and columns;
// or, for a plain table of numbers under a header row, parse_numeric_table / read_numeric_table.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace magenc {

// One line of a table: its 1-based line number in the file, its text (trimmed), its cells.
struct TextRow {
  long line = 0;
  std::string text;
  std::vector<std::string> cells;  // trimmed, quotes removed; empty for comment lines
};

struct TextTableOptions {
  std::string comment_marks = "#";  // a line whose first non-blank character is one of these is a comment
  char separator = 0;               // 0: recognised from the first content line; else ',', ';', '\t' or ' '
};

// One pass over the lines of a table held in memory (text must outlive the reader).
class TextTableReader {
 public:
  // where: how messages name the input ("table FILE", "--cases FILE", "--points FILE").
  // Throws InputError for UTF-16 text.
  TextTableReader(std::string_view text, std::string where, TextTableOptions options = {});

  // The next content line (neither blank nor a comment), split into cells; false after the last one.
  // Throws InputError for a NUL byte or an unterminated quote (naming the line).
  bool next(TextRow& row);

  // The comment lines before the first content line, in file order (text trimmed, mark kept).
  const std::vector<TextRow>& leading_comments() const { return comments_; }
  // The separator in use (0 before the first content line): ',', ';', '\t' or ' ' (runs of blanks).
  char separator() const { return separator_; }
  bool had_bom() const { return bom_; }
  const std::string& where() const { return where_; }

 private:
  std::string_view text_;
  std::string where_;
  TextTableOptions options_;
  std::size_t pos_ = 0;
  long line_ = 0;
  char separator_ = 0;
  bool bom_ = false, content_seen_ = false;
  std::size_t first_cells_ = 0;  // cells of the first content line, trailing empty cells dropped
  std::vector<TextRow> comments_;
};

// When text looks like UTF-16 (a NUL at every other byte of its start): the clause for a message naming it
// (" is UTF-16 text ...: allowed UTF-8 or ASCII text (in Excel: save as "CSV UTF-8")"); else "".
std::string utf16_hint(std::string_view text);

// The separator recognised from a content line (see above): ';', '\t', ',' or ' '.
char detect_separator(std::string_view line);

// Splits one line into trimmed, unquoted cells on `separator` (' ' = runs of blanks). Throws
// InputError "WHERE line N: ..." for a quoted cell without its closing quote.
std::vector<std::string> split_cells(std::string_view line, char separator, const std::string& where, long line_no);

// The separator as words for messages: "','", "';'", "tab", "blanks".
std::string separator_name(char separator);

// A number cell: '.' or ',' as the decimal mark (not both, at most one), else strtod syntax filling the
// whole cell. Overflow (1e999), inf and nan are NotFinite; underflow gives the rounded value.
struct CellNumber {
  enum Status { Ok, Empty, NotNumber, NotFinite } status = Empty;
  double value = 0;
  bool ok() const { return status == Ok; }
};
CellNumber parse_number(std::string_view cell);

// For a data row with `cells` cells where the header has `expected`: when the separator is ',' and the
// row has more cells, the likely cause (a decimal comma between comma separators), as a clause to
// append to the row's message ("; ..."); else "".
std::string decimal_comma_hint(char separator, std::size_t cells, std::size_t expected);

// The whole file as text, for the readers above. what names it in messages ("measured curve F",
// "--cases F"). InputError when it is missing, not a regular file, larger than max_bytes, or unreadable.
std::string read_text_file(const std::filesystem::path& file, const std::string& what,
                           std::uintmax_t max_bytes = std::uintmax_t(1) << 30);

// A table of numbers under one header row naming its columns (the simple case of a new reader:
// points x_mm,y_mm,z_mm, field scans). Rows in file order.
struct NumericTable {
  std::string where;
  std::vector<std::string> columns;  // as written in the header
  long header_line = 0;
  std::vector<long> line;            // per row: its line number
  std::vector<double> values;        // row-major: rows() x columns.size()
  std::size_t rows() const { return line.size(); }
  double at(std::size_t row, std::size_t col) const { return values[row * columns.size() + col]; }
  int column(const std::string& name) const;  // index, -1 if absent
};
// Reads the header and the rows: every column name distinct (and in `allowed` when it is not empty),
// every row one finite number per column, at least one row. Errors (InputError) are one line:
// "WHERE line N: unknown column 'q': allowed columns a, b, c", "WHERE line N: column 'x_mm' appears
// twice", "WHERE line N: 2 cells, the header has 3 columns: allowed one number per column",
// "WHERE line N: column x_mm = 'abc' is not a number: allowed finite numbers" (or "is not finite",
// "is empty"), "WHERE is empty: expected a header row naming the columns (allowed ...)", "WHERE has a header but no data
// rows: allowed at least one row".
NumericTable parse_numeric_table(std::string_view text, const std::string& where,
                                 const std::vector<std::string>& allowed = {}, const TextTableOptions& options = {});
// The same on a file (read_text_file; messages name it as "WHAT FILE", e.g. what = "--points").
NumericTable read_numeric_table(const std::filesystem::path& file, const std::string& what,
                                const std::vector<std::string>& allowed = {}, const TextTableOptions& options = {});

}  // namespace magenc
