// libFuzzer target: the TOML configuration reader (Config::load_toml_string, --config) and the --set
// parser, with solve_field's full key table (common keys + [fem] + [mesh] ...) and the [provenance] keys
// (list keys and the table-list key provenance.fem_variants).
#include "studies/harmonic_provenance/provenance.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "core/errors.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const auto schema = magenc::merge_schemas(magenc::fem::solve_field_schema(), magenc::provenance_keys());
  const std::string text(reinterpret_cast<const char*>(data), size);
  magenc::Config cfg(schema);
  try {
    cfg.load_toml_string(text, "fuzz.toml");
    (void)cfg.to_toml();
    (void)cfg.to_json();
  } catch (const magenc::InputError&) {
  }
  magenc::Config cfg2(schema);
  try {
    cfg2.set(text);
  } catch (const magenc::InputError&) {
  }
  return 0;
}
