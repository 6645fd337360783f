// libFuzzer target: the shared reader of CSV and text tables (core/text_table): lines, separators, quotes,
// byte-order marks and line ends through TextTableReader (recognised and forced separators), every cell
// through parse_number, and the numeric table (header + numbers) that new readers use.
#include <string_view>

#include "core/errors.hpp"
#include "core/text_table.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const char sep : {'\0', ',', ';', '\t', ' '}) {
    try {
      magenc::TextTableReader reader(text, "fuzz", {"#%", sep});
      for (magenc::TextRow row; reader.next(row);)
        for (const auto& cell : row.cells) (void)magenc::parse_number(cell);
      (void)reader.leading_comments();
    } catch (const magenc::InputError&) {
    }
  }
  try {
    (void)magenc::parse_numeric_table(text, "fuzz");
  } catch (const magenc::InputError&) {
  }
  return 0;
}
