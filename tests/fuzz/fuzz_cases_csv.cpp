// libFuzzer target: the mounting-cases CSV reader (error_spectrum --cases FILE.csv).
#include "core/errors.hpp"
#include "fuzz_common.hpp"
#include "io/tables.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = magenc_fuzz::write_input("cases.csv", data, size);
  try {
    (void)magenc::read_cases_csv(path);
  } catch (const magenc::InputError&) {
  }
  return 0;
}
