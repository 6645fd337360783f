// libFuzzer target: the solve.json reader of a solve_field output directory
// (field_solver/field_io/solved_field.hpp: the facts, the magnet/plane consistency check,
// the summaries' description and mu_r).
#include "core/errors.hpp"
#include "fuzz_common.hpp"
#include "probe/common_keys.hpp"
#include "field_solver/field_io/solved_field.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const magenc::Config cfg(magenc::common_keys());
  magenc_fuzz::write_input("solve.json", data, size);
  const magenc::SolvedFieldDir solved(magenc_fuzz::work_dir());
  try {
    (void)solved.facts();
  } catch (const magenc::InputError&) {
  }
  try {
    (void)solved.mismatch(cfg);
  } catch (const magenc::InputError&) {
  }
  try {
    (void)solved.mu_r();
  } catch (const magenc::InputError&) {
  }
  (void)solved.description();  // documented: "" when unreadable, never throws
  return 0;
}
