// libFuzzer target: the .vti grid reader (grid:FILE.vti, GridField::from_file), through the
// interpolating field source so that whatever the reader accepts is also sampled.
#include "core/errors.hpp"
#include "fuzz_common.hpp"
#include "fields/grid_field.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = magenc_fuzz::write_input("grid.vti", data, size);
  try {
    const auto field = magenc::GridField::from_file(path, magenc::Interp::Linear);
    const auto& g = field->grid();
    const magenc::Vec3 centre =
        g.origin_mm + 0.5 * g.spacing_mm.cwiseProduct(magenc::Vec3(g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1));
    (void)field->B_T(centre);
  } catch (const magenc::InputError&) {
  }
  return 0;
}
