// The configuration's text helpers, shared by its engine (config.cpp) and its text members
// (config_text.cpp), defined in config_detail.cpp: values as text, TOML nodes as values, TOML and JSON
// writers, the bounds of TOML input. Not for use outside src/core/config*.
#pragma once
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <toml++/toml.h>

#include "core/config_keys.hpp"

namespace magenc::config_detail {

// A scalar value as a ConfigScalar (lists and tables: 0.0; callers pass scalars).
ConfigScalar as_scalar(const ConfigValue& v);
std::string scalar_text(const ConfigScalar& v);
// Text of a scalar or list value (lists: comma-separated); not for tables.
std::string value_text(const ConfigValue& v);
// A string as a TOML basic string or JSON string (the escapes both share).
std::string quoted(const std::string& text);
// A real as TOML (and JSON) writes it: 12 significant digits, always with a '.', 'e' or "nan"/"inf".
std::string real_text(double d);
// Tables as one TOML inline array; `sep` between tables.
std::string tables_toml(const ConfigTables& tables, const std::string& open, const std::string& sep,
                        const std::string& close);
// Tables as a JSON array of objects.
std::string tables_json(const ConfigTables& tables);
// A Settings value as a JSON object of its dotted keys / as TOML ({} when empty).
std::string settings_json(const ConfigTables& t);
std::string settings_toml(const ConfigTables& t);
// A TOML node as a configuration scalar; nullopt for arrays and tables.
std::optional<ConfigScalar> toml_scalar(const toml::node& node);
// The elements of a TOML array of a list key: scalars only.
ConfigList toml_list(const KeySpec& s, const toml::array& a, const std::string& origin);
// A TOML array of tables as the tables of table-list key s; a Settings key's table.
ConfigTables toml_tables(const KeySpec& s, const toml::node& node, const std::string& where);
ConfigTables settings_tables(const KeySpec& s, const toml::node& node, const std::string& where);
// Calls leaf(dotted key, node) for every node of tbl that is not a table, and for the tables
// stop(dotted key) names.
void walk_table(const toml::table& tbl, const std::string& prefix,
                const std::function<void(const std::string&, const toml::node&)>& leaf,
                const std::function<bool(const std::string&)>& stop = {});
// The largest TOML input read (a --config file or a string): 1 MiB.
inline constexpr std::size_t kMaxTomlBytes = std::size_t(1) << 20;
// Bounds of TOML text before toml++ parses it (size, dotted-key depth, nesting): InputError naming origin.
void check_toml_bounds(const std::string& text, const std::string& origin);
// The field `name` of table-list key s, or nullptr.
const KeySpec* field_spec(const KeySpec& s, const std::string& name);
// The one-line error of element i (0-based) of n of a table-list key.
[[noreturn]] void table_fail(const KeySpec& s, const std::string& where, std::size_t i, std::size_t n,
                             const std::string& why);
// Parse textual value per spec type (for defaults and --set).
ConfigValue parse_text(const KeySpec& s, const std::string& raw, const std::string& origin);

}  // namespace magenc::config_detail
