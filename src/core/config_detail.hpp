// What the three files of the configuration (config_keys.cpp, config.cpp, config_text.cpp) share: the
// text helpers of config_text.cpp that the engine and the declarations use. Not for use outside src/core/config*.
#pragma once
#include <cstddef>
#include <string>

#include "core/config.hpp"

namespace magenc::config_detail {

bool is_list(KeySpec::Type t);
// A list key of a fixed number of elements (real_array_field): a TOML array only.
bool fixed_length(const KeySpec& s);
// The scalar type of a list key's elements.
KeySpec::Type element_type(KeySpec::Type t);
// A scalar value as a ConfigScalar (lists and tables: 0.0; callers pass scalars).
ConfigScalar as_scalar(const ConfigValue& v);
std::string scalar_text(const ConfigScalar& v);
// Text of a scalar or list value (lists: comma-separated); not for tables.
std::string value_text(const ConfigValue& v);
// The field `name` of table-list key s, or nullptr.
const KeySpec* field_spec(const KeySpec& s, const std::string& name);
// The one-line error of element i (0-based) of n of a table-list key.
[[noreturn]] void table_fail(const KeySpec& s, const std::string& where, std::size_t i, std::size_t n,
                             const std::string& why);
// Parse textual value per spec type (for defaults and --set).
ConfigValue parse_text(const KeySpec& s, const std::string& raw, const std::string& origin);

}  // namespace magenc::config_detail
