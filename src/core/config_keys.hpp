// The declarations of the configuration (core/config.hpp): what a key is (KeySpec, its type, default,
// range, unit, help), the helpers that declare keys tersely, the value types, the allowed range of a key as
// text and merging schemas. Defined in config_keys.cpp.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace magenc {

struct KeySpec {
  enum class Type { Real, Int, String, Bool, RealList, IntList, StringList, TableList, Settings };
  std::string key;        // dotted "section.name", e.g. "magnet.radius_mm"
  Type type = Type::Real;
  std::string default_value;  // textual default, parsed like a --set value
  double min = -1e300;        // numeric range (Real/Int); see *_exclusive
  double max = 1e300;
  bool min_exclusive = false;  // true: value must be > min (e.g. sizes > 0)
  bool max_exclusive = false;
  std::vector<std::string> choices;  // String, StringList: allowed values (empty = any non-empty text)
  std::size_t min_elements = 1;      // lists: fewest elements (0: may be empty)
  std::size_t max_elements = 0;      // lists: most elements (0: no limit); == min_elements: a fixed-length array
  std::vector<KeySpec> fields;       // TableList: the fields of each table (scalar keys, arrays, Settings)
  bool required = false;             // a TableList field every table must have
  bool numbers_as_text = false;      // String: a TOML number is taken as its text (`direction = -1`)
  std::string unit;                  // "mm", "deg", "T", "" for none
  std::string help;
};

// Helpers to declare keys tersely.
KeySpec real_key(std::string key, double def, double min, double max, std::string unit,
                 std::string help, bool min_exclusive = false, bool max_exclusive = false);
KeySpec int_key(std::string key, long def, long min, long max, std::string help);
KeySpec string_key(std::string key, std::string def, std::vector<std::string> choices,
                   std::string help);
KeySpec bool_key(std::string key, bool def, std::string help);
// A String key that also takes a TOML number as its text: a number or a word such as "auto"
// (choices empty: any text, the reader checks it; otherwise the allowed spellings).
KeySpec number_or_word_key(std::string key, std::string def, std::vector<std::string> choices, std::string help);
// List keys: elements in [min, max] (numbers) or among choices (strings; empty: any non-empty text).
KeySpec real_list_key(std::string key, const std::vector<double>& def, double min, double max, std::string unit,
                      std::string help, bool min_exclusive = false, std::size_t min_elements = 1);
KeySpec int_list_key(std::string key, const std::vector<long>& def, long min, long max, std::string help,
                     std::size_t min_elements = 1);
KeySpec string_list_key(std::string key, const std::vector<std::string>& def, std::vector<std::string> choices,
                        std::string help, std::size_t min_elements = 1);

// Table-list keys: an array of tables (the value is the TOML text of an inline array, "" for none).
// `fields`: scalar fields (real_key, int_key, string_key, bool_key; `required` ones must be present),
// fixed-length number arrays (real_array_field) and Settings fields (settings_field: a table of
// key = scalar, nested tables flattened to dotted keys).
KeySpec table_list_key(std::string key, std::vector<KeySpec> fields, std::string def_toml, std::string help);
KeySpec settings_field(std::string name, std::string help);
// A table field of exactly `length` numbers, each in [min, max] (a TOML array, e.g. offset_mm = [2.5, 0]).
KeySpec real_array_field(std::string name, std::size_t length, double min, double max, std::string unit,
                         std::string help);
KeySpec required(KeySpec field);

using ConfigScalar = std::variant<double, long, std::string, bool>;
using ConfigList = std::vector<ConfigScalar>;

// One table of a table-list key; entries sorted by field, then key.
struct ConfigTableEntry {
  std::string field;  // the field's name ("label", "set")
  std::string key;    // a Settings field's dotted key ("fem.order"); empty for scalar fields
  ConfigScalar value;                      // a scalar or Settings field's value
  std::optional<ConfigList> array = {};    // an array field's elements (value unused)
};
struct ConfigTable {
  std::vector<ConfigTableEntry> entries;
  bool has(const std::string& field) const;
  // A String field's text ("" when absent).
  std::string text(const std::string& field) const;
  // A Settings field's key = value pairs (empty when absent).
  std::vector<std::pair<std::string, ConfigScalar>> settings(const std::string& field) const;
  // An array field's elements as numbers (empty when absent).
  std::vector<double> numbers(const std::string& field) const;
};
using ConfigTables = std::vector<ConfigTable>;
using ConfigValue = std::variant<double, long, std::string, bool, ConfigList, ConfigTables>;

// Text of a key's allowed range, e.g. "(0, 100] mm" or "one of two, diff4, ring:N".
std::string allowed_range(const KeySpec& s);

// Concatenate schemas (later ones may not redeclare a key).
std::vector<KeySpec> merge_schemas(std::vector<KeySpec> a, const std::vector<KeySpec>& b);

// The kinds of list keys (RealList, IntList, StringList) and their element type.
bool is_list(KeySpec::Type t);
// A list key of a fixed number of elements (real_array_field): a TOML array only.
bool fixed_length(const KeySpec& s);
// The scalar type of a list key's elements.
KeySpec::Type element_type(KeySpec::Type t);

}  // namespace magenc
