// Declared configuration: every key is declared once with its type, default,
// allowed range, unit and help text; values come from the defaults, then a
// TOML file (--config), then --set key=value overrides, in that order.
// Unknown keys, wrong types, NaN and out-of-range values are InputErrors whose
// message names the key and its allowed range.
// List keys (RealList, IntList, StringList) take a TOML array (`orders = [1, 2]`,
// `--set 'convergence.orders=[1, 2]'`) or, for compatibility with earlier
// configurations, comma-separated text (`orders = "1,2"`, `--set convergence.orders=1,2`);
// every element is checked like a scalar key of its type, and an error names the
// element (1-based) and the count. Readers take the elements with reals(), integers(),
// numbers() or strings(); no reader splits text.
// Table-list keys (TableList) are TOML arrays of tables with declared fields, e.g.
//   [[provenance.fem_variants]]
//   label = "coarse P1"
//   config = "meshes/coarse.toml"
//   set = { fem.order = 1 }          # a Settings field: a table of key = scalar (dotted keys flattened)
// and on the command line the same as an inline array, `--set 'key=[{label = "P1", set = {fem.order = 1}}]'`
// (empty text or [] for none). Readers take them with tables().
// A table field may also be a fixed-length array of numbers (real_array_field, e.g. offset_mm = [2.5, 0]):
// a TOML array only (never comma-separated text), every element checked like a Real key, an error
// naming the field, the element and the count. Readers take its elements with ConfigTable::numbers().
#pragma once
#include <map>
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

class Config {
 public:
  explicit Config(std::vector<KeySpec> schema);

  // Merge a TOML file / string. Every leaf must be a declared key.
  void load_toml_file(const std::string& path);
  void load_toml_string(const std::string& text, const std::string& origin = "<string>");
  // Apply one "section.key=value" override (value parsed per the key's type).
  void set(const std::string& assignment);
  // Set a value programmatically (checked against the spec).
  void set_value(const std::string& key, const ConfigValue& value);

  double real(const std::string& key) const;
  long integer(const std::string& key) const;
  // A String key's value; for a list key its elements as comma-separated text (as earlier
  // configurations wrote them, and as config.toml echoes them).
  std::string str(const std::string& key) const;
  // Elements of a list key (checked when set: readers do no parsing of their own).
  std::vector<double> reals(const std::string& key) const;
  std::vector<long> integers(const std::string& key) const;
  std::vector<double> numbers(const std::string& key) const;  // a RealList or an IntList as doubles
  std::vector<std::string> strings(const std::string& key) const;
  // Tables of a table-list key (fields checked when set).
  ConfigTables tables(const std::string& key) const;
  bool flag(const std::string& key) const;
  bool has(const std::string& key) const;

  const std::vector<KeySpec>& schema() const { return schema_; }
  // The values in use, as a TOML document (echoed next to outputs).
  std::string to_toml() const;
  // The values in use as JSON text (object of sections).
  std::string to_json() const;
  // Human-readable list of keys (for --help epilogues).
  std::string describe() const;

 private:
  const KeySpec& spec(const std::string& key) const;
  void assign_checked(const KeySpec& s, const ConfigValue& v, const std::string& origin);
  std::vector<KeySpec> schema_;
  std::map<std::string, ConfigValue> values_;
};

// Text of a key's allowed range, e.g. "(0, 100] mm" or "one of two, diff4, ring:N".
std::string allowed_range(const KeySpec& s);

// calibration.method and calibration.at: declared only by the executables that apply a calibration
// (error_spectrum, calibrate); everywhere else they are unknown keys, never silently ignored.
std::vector<KeySpec> calibration_keys();

// Concatenate schemas (later ones may not redeclare a key).
std::vector<KeySpec> merge_schemas(std::vector<KeySpec> a, const std::vector<KeySpec>& b);

}  // namespace magenc
