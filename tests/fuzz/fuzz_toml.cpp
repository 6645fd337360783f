// libFuzzer target: the TOML configuration reader (Config::load_toml_string, --config) and the --set
// parser, with solve_field's full key table (common keys + [fem] + [mesh] ...), the [provenance] keys
// (list keys and the table-list key provenance.fem_variants) and the [nonius] keys; then the readers of
// what a configuration says beyond each key's own range: the magnet (rings, multipole patterns and their
// pole errors), the speed chain, the nonius track and the plausibility window of field files.
#include "studies/harmonic_provenance/provenance.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "core/errors.hpp"
#include "fields/field_table.hpp"
#include "fields/magnet.hpp"
#include "fuzz_common.hpp"
#include "probe/nonius.hpp"
#include "probe/speed.hpp"

namespace {

// Each reader may refuse the configuration only with an InputError.
void read_everything(const magenc::Config& cfg) {
  try {
    (void)magenc::Magnet::from_config(cfg);
  } catch (const magenc::InputError&) {
  }
  try {
    (void)magenc::SpeedChain::from_config(cfg);
  } catch (const magenc::InputError&) {
  }
  try {
    if (magenc::NoniusTrack::present(cfg)) (void)magenc::NoniusTrack::from_config(cfg);
  } catch (const magenc::InputError&) {
  }
  try {
    (void)magenc::field_table_limits(cfg);
  } catch (const magenc::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const auto schema = magenc::merge_schemas(
      magenc::merge_schemas(magenc::fem::solve_field_schema(), magenc::provenance_keys()), magenc::NoniusTrack::keys());
  const std::string text(reinterpret_cast<const char*>(data), size);
  magenc::Config cfg(schema);
  try {
    cfg.load_toml_string(text, "fuzz.toml");
    (void)cfg.to_toml();
    (void)cfg.to_json();
    read_everything(cfg);
  } catch (const magenc::InputError&) {
  }
  magenc::Config cfg2(schema);
  try {
    cfg2.set(text);
    read_everything(cfg2);
  } catch (const magenc::InputError&) {
  }
  return 0;
}
