// libFuzzer target: the correction-file reader (calibrate --correction FILE.csv, analysis/calibration_file).
// A correction that reads is also evaluated over a turn (the table lookup and the ellipse inversion).
#include <cmath>

#include "analysis/calibration_file.hpp"
#include "core/errors.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = magenc_fuzz::write_input("correction.csv", data, size);
  try {
    const magenc::Correction c = magenc::read_correction_csv(path);
    for (int i = 0; i < 16; ++i) {
      (void)c.e_deg(22.5 * i);
      (void)c.ellipse.angle_deg(std::cos(0.4 * i), std::sin(0.4 * i));
    }
  } catch (const magenc::InputError&) {
  }
  return 0;
}
