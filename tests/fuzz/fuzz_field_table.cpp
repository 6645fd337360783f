// libFuzzer target: the field-table reader (--field table:FILE, table_field_from_file), through the
// interpolating field source so that whatever the reader accepts is also sampled (linear and cubic).
#include "core/config.hpp"
#include "core/errors.hpp"
#include "fields/field_table.hpp"
#include "fuzz_common.hpp"
#include "probe/common_keys.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const magenc::Config cfg(magenc::common_keys());
  const auto path = magenc_fuzz::write_input("table.csv", data, size);
  for (const auto mode : {magenc::Interp::Linear, magenc::Interp::Cubic}) {
    try {
      const auto field = magenc::table_field_from_file(path, cfg, mode);
      const auto& g = field->grid();
      const magenc::Vec3 centre =
          g.origin_mm + 0.5 * g.spacing_mm.cwiseProduct(magenc::Vec3(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1));
      (void)field->B_T(centre);
      (void)field->B_T(g.origin_mm);
    } catch (const magenc::InputError&) {
      return 0;  // rejected: the same file is rejected in every mode
    }
  }
  return 0;
}
