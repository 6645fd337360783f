// libFuzzer target: the Ansys Maxwell grid-export (.fld) reader of `table:` (fields/field_table), through
// the interpolating field source as fuzz_field_table does. The format is recognised from the content
// (Min:, Max:, Grid Size: header): an input that does not start with "Min:" or "Grid" gets a Maxwell header
// put in front, so that most of the mutated bytes reach the .fld reader (its header, quantity line, rows).
#include <string>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "fields/field_table.hpp"
#include "fuzz_common.hpp"
#include "probe/common_keys.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const magenc::Config cfg(magenc::common_keys());
  std::string text(reinterpret_cast<const char*>(data), size);
  if (text.rfind("Min:", 0) != 0 && text.rfind("Grid", 0) != 0)
    text = "Min: 0 0 0.00455\nMax: 0.001 0.001 0.00455\nGrid Size: 0.001 0.001 0\n" + text;
  const auto path = magenc_fuzz::write_input("grid.fld", reinterpret_cast<const uint8_t*>(text.data()), text.size());
  try {
    const auto field = magenc::table_field_from_file(path, cfg, magenc::Interp::Linear);
    const auto& g = field->grid();
    (void)field->B_T(magenc::Vec3(g.origin_mm + 0.5 * g.spacing_mm));
  } catch (const magenc::InputError&) {
  }
  return 0;
}
