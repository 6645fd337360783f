// libFuzzer target: the COMSOL spreadsheet-export reader of `table:` (fields/field_table), through the
// interpolating field source as fuzz_field_table does. The format is recognised from the content ('%'
// header lines, then rows of numbers): an input that does not start with '%' gets a COMSOL header put in
// front, so that most of the mutated bytes reach the COMSOL reader (its column line, units and rows).
#include <string>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "fields/field_table.hpp"
#include "fuzz_common.hpp"
#include "probe/common_keys.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const magenc::Config cfg(magenc::common_keys());
  std::string text(reinterpret_cast<const char*>(data), size);
  if (text.empty() || text[0] != '%') text = "% Length unit: mm\n% x y z mf.Bz (T)\n" + text;
  const auto path = magenc_fuzz::write_input("comsol.txt", reinterpret_cast<const uint8_t*>(text.data()), text.size());
  try {
    const auto field = magenc::table_field_from_file(path, cfg, magenc::Interp::Cubic);
    const auto& g = field->grid();
    (void)field->B_T(magenc::Vec3(g.origin_mm + 0.5 * g.spacing_mm));
  } catch (const magenc::InputError&) {
  }
  return 0;
}
