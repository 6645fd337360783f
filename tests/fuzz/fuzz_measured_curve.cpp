// libFuzzer target: the measured-curve reader of diagnose (--measured FILE.csv, read_measured_curve)
// with diagnose's defaults and with the loosest options (--error-sign -1, one point, gaps up to 180 deg),
// and the least-squares harmonics the fit starts from on whatever the reader accepts.
#include "analysis/measured_curve.hpp"
#include "core/errors.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = magenc_fuzz::write_input("curve.csv", data, size);
  magenc::CurveReadOptions loose;
  loose.error_sign = -1;
  loose.min_points = 1;
  loose.max_gap_deg = 180.0;
  for (const auto& opts : {magenc::CurveReadOptions{}, loose}) {
    try {
      const auto c = magenc::read_measured_curve(path.string(), opts);
      (void)magenc::harmonics_ls(c.theta_deg, c.error_deg);
    } catch (const magenc::InputError&) {
    }
  }
  return 0;
}
