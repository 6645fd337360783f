// Common command-line options of every magenc executable (docs/interfaces.md):
// --config FILE.toml, --set key=value (repeatable), --out PATH.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "core/config.hpp"

namespace magenc {

struct CommonOptions {
  std::string config_file;          // --config (empty: embedded defaults)
  std::vector<std::string> sets;    // --set key=value, applied in order
  std::string out;                  // --out (empty: the executable's default)
};

// Adds --config/--set/--out to app, appends the schema's key list to --help, and adds
// --keys-json (prints keys_json(schema) and exits 0; scripts/gen_keys.py writes docs/keys.md from it).
void add_common_options(CLI::App& app, CommonOptions& opts, const std::vector<KeySpec>& schema);

// The declared keys as a JSON array, one object per key: key, type, default, range (allowed_range),
// unit, help; min/max/min_exclusive/max_exclusive for numbers, choices for strings, fields of a
// table-list key, required for a required field.
std::string keys_json(const std::vector<KeySpec>& schema);

// Builds the Config: defaults, then --config, then each --set.
Config load_config(const std::vector<KeySpec>& schema, const CommonOptions& opts);

// Parses argv with CLI11; on --help prints and exits 0, on a parse error
// prints one line naming the flag and exits 2 (via InputError in run_main).
void parse_cli(CLI::App& app, int argc, char** argv);

}  // namespace magenc
