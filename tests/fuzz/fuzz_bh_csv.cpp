// libFuzzer target: the B-H curve reader (bh_curve.hpp), and the curve it returns evaluated.
#include "field_solver/mesh/bh_curve.hpp"
#include "core/errors.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = magenc_fuzz::write_input("bh.csv", data, size);
  try {
    const magenc::fem::BhCurve c = magenc::fem::read_bh_csv(path);
    for (double H : {0.0, 1.0, c.H().back() * 0.5, c.H().back(), c.H().back() * 2.0, -3.0})
      if (!(c.B_T(H) == c.B_T(H)) || !(c.dB_dH(H) >= 0)) __builtin_trap();  // NaN or a negative slope
  } catch (const magenc::InputError&) {
  }
  return 0;
}
