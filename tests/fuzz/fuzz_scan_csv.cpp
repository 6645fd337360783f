// libFuzzer target: the field-scan CSV reader (inspect --scan FILE.csv).
#include "core/errors.hpp"
#include "fuzz_common.hpp"
#include "io/points_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = magenc_fuzz::write_input("scan.csv", data, size);
  try {
    (void)magenc::read_scan_csv(path);
  } catch (const magenc::InputError&) {
  }
  return 0;
}
