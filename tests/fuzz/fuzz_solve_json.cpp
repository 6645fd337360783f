// libFuzzer target: the solve.json readers of a solve_field output directory (fem:DIR facts,
// the studies' magnet/plane consistency check, the summaries' description and mu_r).
#include "report/comparison_run.hpp"
#include "core/errors.hpp"
#include "analysis/fem_comparison.hpp"
#include "fem_variant.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const magenc::Config cfg(magenc::common_keys());
  magenc_fuzz::write_input("solve.json", data, size);
  const auto& dir = magenc_fuzz::work_dir();
  try {
    (void)magenc::fem::solve_json_facts(dir);
  } catch (const magenc::InputError&) {
  }
  try {
    (void)magenc::solve_mismatch(dir, cfg);
  } catch (const magenc::InputError&) {
  }
  try {
    (void)magenc::solve_mu_r(dir);
  } catch (const magenc::InputError&) {
  }
  (void)magenc::solve_description(dir);  // documented: "" when unreadable, never throws
  return 0;
}
