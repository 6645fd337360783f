// The shared text-table reader (src/core/text_table.*): separators, byte-order mark, line ends, quotes and
// decimal commas recognised from the content; numbers; the numeric table; every refusal one line.
#include <catch2/catch.hpp>

#include <filesystem>
#include <functional>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include "core/errors.hpp"
#include "core/text_table.hpp"
#include "support/spreadsheet_text.hpp"

using namespace magenc;
namespace fs = std::filesystem;

namespace {

std::vector<TextRow> rows_of(const std::string& text, TextTableOptions o = {}) {
  TextTableReader r(text, "t.csv", o);
  std::vector<TextRow> rows;
  for (TextRow row; r.next(row);) rows.push_back(row);
  return rows;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("text table: the separator, decimal mark, BOM and line ends come from the content", "[core][contract]") {
  const std::string plain = "# note, with; marks\nx_mm,y_mm,Bz_T\n0.5,-1.25,1e-3\n\n2,3.5,-0.125\n";
  const std::vector<double> want = {0.5, -1.25, 1e-3, 2, 3.5, -0.125};
  for (const auto& [form, sep, text] : std::vector<std::tuple<std::string, char, std::string>>{
           {"plain", ',', plain},
           {"BOM + CRLF", ',', test::with_bom(test::with_crlf(plain))},
           {"CR only", ',', test::with_crlf(plain, true)},
           {"';' + decimal comma", ';', test::european(plain)},
           {"tab + decimal comma", '\t', test::european(plain, '\t')},
           {"blanks", ' ', "x_mm   y_mm   Bz_T\n 0.5 -1.25 1e-3\n2\t3.5   -0.125\n"},
           {"quoted cells", ',', "\"x_mm\",\"y_mm\",\"Bz_T\"\n\"0,5\",-1.25,\"1e-3\"\n2,\"3,5\" , -0.125\n"},
           {"emptied rows", ';', test::european(plain) + ";;\n;;\n"}}) {
    CAPTURE(form);
    TextTableReader r(text, "t.csv");
    TextRow row;
    REQUIRE(r.next(row));
    CHECK(r.separator() == sep);
    CHECK(r.had_bom() == (form == "BOM + CRLF"));
    CHECK(row.cells == std::vector<std::string>{"x_mm", "y_mm", "Bz_T"});
    CHECK(row.line == (form == "blanks" || form == "quoted cells" ? 1 : 2));
    std::vector<double> got;
    while (r.next(row))
      for (const auto& c : row.cells) {
        const CellNumber n = parse_number(c);
        CHECK(n.ok());
        got.push_back(n.value);
      }
    CHECK(got == want);
  }
  // Line numbers count every line end (CRLF once, lone CR once); leading comments are kept with them.
  const auto rows = rows_of("# a\r\n% b\r\rh\r\n1\n", {"#%", 0});
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].line == 4);
  CHECK(rows[1].line == 5);
  TextTableReader r("# a\n% b\nh\n# later\n1\n", "t", {"#%", 0});
  TextRow row;
  while (r.next(row)) {
  }
  REQUIRE(r.leading_comments().size() == 2);
  CHECK(r.leading_comments()[1].text == "% b");
  CHECK(r.leading_comments()[1].line == 2);
  // A forced separator wins over recognition; a quoted cell may hold the separator and "" is a quote.
  CHECK(rows_of("a;b c\n", {"#", ' '})[0].cells == std::vector<std::string>{"a;b", "c"});
  CHECK(rows_of("\"a,\"\"b\"\"\",c\n")[0].cells == std::vector<std::string>{"a,\"b\"", "c"});
  // An empty cell inside a line is kept; a trailing separator (a spreadsheet's used range) is no cell.
  CHECK(rows_of("a,,b,\n")[0].cells == std::vector<std::string>{"a", "", "b"});
}

TEST_CASE("text table: numbers", "[core][contract]") {
  CHECK(parse_number("0,25").value == 0.25);
  CHECK(parse_number("-1,5e-3").value == -1.5e-3);
  CHECK(parse_number("1e-400").ok());  // underflow rounds (to 0)
  CHECK(parse_number("0x10").value == 16.0);  // strtod syntax
  for (const char* bad : {"1,5.0", "1,2,3", "1.5x", "abc", " ", "1 2", "1.2.3", ","})
    CHECK(parse_number(bad).status == CellNumber::NotNumber);
  for (const char* inf : {"inf", "-inf", "nan", "1e999", "-1e400000"}) CHECK(parse_number(inf).status == CellNumber::NotFinite);
  CHECK(parse_number("").status == CellNumber::Empty);
  CHECK(detect_separator("a;b,c\td") == ';');
  CHECK(detect_separator("\"a;b\",c") == ',');
  CHECK(detect_separator("a b") == ' ');
  CHECK(decimal_comma_hint(',', 4, 3).find("decimal comma") != std::string::npos);
  CHECK(decimal_comma_hint(';', 4, 3).empty());
  CHECK(decimal_comma_hint(',', 2, 3).empty());
}

TEST_CASE("text table: bad input is one line naming the input", "[core][bad-input]") {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"\xFF\xFEx\0_\0m\0m\0", "t.csv is UTF-16 text"},
      {"\xFE\xFF\0x", "t.csv is UTF-16 text"},
      {std::string("a,b\n1,2\n3,\0\n", 12), "t.csv line 3 holds a NUL byte"},
      {"a,b\n\"1,2\n", "t.csv line 2: a cell opens a double quote and does not close it"},
  };
  for (const auto& [text, want] : bad) {
    CAPTURE(want);
    const std::string& t = text;  // clang 14 cannot capture a structured binding in a lambda
    const std::string m = error_of([&] { rows_of(t); });
    CHECK(m.find(want) != std::string::npos);
    CHECK(m.find("allowed") != std::string::npos);
    CHECK(m.find('\n') == std::string::npos);
  }
}

TEST_CASE("numeric table: header and rows of finite numbers, every refusal one line", "[core][bad-input]") {
  const NumericTable t =
      parse_numeric_table(test::with_bom(test::european("x_mm,y_mm,z_mm\n0.5,1,2\n-1,0,4.55\n")), "--points p.csv",
                          {"x_mm", "y_mm", "z_mm"});
  REQUIRE(t.rows() == 2);
  CHECK(t.columns == std::vector<std::string>{"x_mm", "y_mm", "z_mm"});
  CHECK(t.column("z_mm") == 2);
  CHECK(t.column("Bz_T") == -1);
  CHECK(t.at(1, 2) == 4.55);
  CHECK(t.line == std::vector<long>{2, 3});
  const std::vector<std::string> allowed = {"x_mm", "y_mm", "z_mm"};
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"", "--points p.csv is empty: expected a header row naming the columns (allowed x_mm, y_mm, z_mm)"},
      {"x_mm,q\n", "line 1: unknown column 'q': allowed columns x_mm, y_mm, z_mm"},
      {"x_mm,x_mm\n", "line 1: column 'x_mm' appears twice"},
      {"x_mm,y_mm\n", "has a header but no data rows"},
      {"x_mm,y_mm\n1,2\n3\n", "line 3: 1 cells, the header has 2 columns"},
      {"x_mm,y_mm\n1,2,5\n", "line 2: 3 cells, the header has 2 columns: allowed one number per column; a decimal comma"},
      {"x_mm,y_mm\n1,abc\n", "line 2: column y_mm = 'abc' is not a number"},
      {"x_mm,y_mm\n1,inf\n", "line 2: column y_mm = 'inf' is not finite"},
      {"x_mm;y_mm\n1;\n", "line 2: column y_mm is empty"},
  };
  for (const auto& [text, want] : bad) {
    CAPTURE(text);
    const std::string& body = text;  // clang 14 cannot capture a structured binding in a lambda
    const std::string m = error_of([&] { parse_numeric_table(body, "--points p.csv", allowed); });
    CHECK(m.find(want) != std::string::npos);
    CHECK(m.find("allowed") != std::string::npos);
    CHECK(m.find('\n') == std::string::npos);
  }
  // Files: missing, a directory, over the size limit; a good file reads.
  const fs::path dir = fs::temp_directory_path() / ("magenc_test_text_table_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  CHECK(error_of([&] { read_numeric_table(dir / "none.csv", "--points"); }).find("does not exist") != std::string::npos);
  CHECK(error_of([&] { read_numeric_table(dir, "--points"); }).find("is a directory, not a file") != std::string::npos);
  // A named pipe is refused without opening it (opening would wait for a writer).
  REQUIRE(::mkfifo((dir / "pipe.csv").c_str(), 0600) == 0);
  CHECK(error_of([&] { read_numeric_table(dir / "pipe.csv", "--points"); }).find("is not a regular file (a named pipe") !=
        std::string::npos);
  std::ofstream(dir / "p.csv") << "x_mm\r\n1,5\r\n";
  CHECK(read_numeric_table(dir / "p.csv", "--points").at(0, 0) == 1.5);  // one column: ',' is the decimal mark
  CHECK(error_of([&] { read_text_file(dir / "p.csv", "p", 4); }).find("bytes: allowed at most 4") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("text table: trailing separators of a spreadsheet's used range are no columns", "[core][contract]") {
  // Excel and LibreOffice write "a;b;" (and "a;b;;") when the used range is wider than the table.
  for (int extra : {1, 2}) {
    CAPTURE(extra);
    const std::string text = test::trailing_separators(test::european("theta_deg,error_deg\n0,0.5\n90,-0.25\n"), ';', extra);
    const NumericTable t = parse_numeric_table(text, "c.csv", {"theta_deg", "error_deg"});
    REQUIRE(t.columns == std::vector<std::string>{"theta_deg", "error_deg"});
    REQUIRE(t.rows() == 2);
    CHECK(t.at(1, 1) == -0.25);
    const NumericTable u = parse_numeric_table(test::trailing_separators("x_mm,y_mm,z_mm\n1,2,3\n", ',', extra), "p.csv");
    CHECK(u.columns.size() == 3);
    CHECK(u.at(0, 2) == 3);
  }
  // A row with trailing separators under a header without them is the same row.
  CHECK(parse_numeric_table("a;b\n1;2;;\n", "t.csv").at(0, 1) == 2);
  // An empty cell inside the header's width is still an empty cell, not a trailing separator.
  const std::string m = error_of([] { parse_numeric_table("a;b;c\n1;2;\n", "t.csv"); });
  CHECK(m.find("line 2: column c is empty") != std::string::npos);
}

TEST_CASE("text table: UTF-16 without a byte-order mark is named as such", "[core][bad-input]") {
  // Excel's "Unicode Text" and other UTF-16 writers: little or big endian, with or without the mark.
  const std::string ascii = "theta_deg,error_deg\n0,0.5\n";
  std::string le, be;
  for (char c : ascii) le += std::string{c, '\0'}, be += std::string{'\0', c};
  for (const std::string& text : {le, be, "\xFF\xFE" + le}) {
    const std::string m = error_of([&] { parse_numeric_table(text, "c.csv"); });
    CAPTURE(m);
    CHECK(m.find("c.csv is UTF-16 text") == 0);
    CHECK(m.find("save as \"CSV UTF-8\"") != std::string::npos);
    CHECK(utf16_hint(text).size() > 0);
  }
  CHECK(utf16_hint(ascii).empty());
  CHECK(utf16_hint(std::string("a,b\n1,2\n3,\0\n", 12)).empty());  // one NUL byte is not UTF-16
}
