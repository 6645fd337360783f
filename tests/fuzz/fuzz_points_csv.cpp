// libFuzzer target: the points CSV reader (field_at --points FILE.csv).
#include "core/errors.hpp"
#include "fuzz_common.hpp"
#include "io/points_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = magenc_fuzz::write_input("points.csv", data, size);
  try {
    (void)magenc::read_points_csv(path);
  } catch (const magenc::InputError&) {
  }
  return 0;
}
