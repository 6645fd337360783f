// Declared configuration: every key is declared once with its type, default,
// allowed range, unit and help text; values come from the defaults, then a
// TOML file (--config), then --set key=value overrides, in that order.
// Unknown keys, wrong types, NaN and out-of-range values are InputErrors whose
// message names the key and its allowed range.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace magenc {

struct KeySpec {
  enum class Type { Real, Int, String, Bool };
  std::string key;        // dotted "section.name", e.g. "magnet.radius_mm"
  Type type = Type::Real;
  std::string default_value;  // textual default, parsed like a --set value
  double min = -1e300;        // numeric range (Real/Int); see *_exclusive
  double max = 1e300;
  bool min_exclusive = false;  // true: value must be > min (e.g. sizes > 0)
  bool max_exclusive = false;
  std::vector<std::string> choices;  // String: allowed values (empty = any)
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

using ConfigValue = std::variant<double, long, std::string, bool>;

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
  const std::string& str(const std::string& key) const;
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

// Keys every executable shares: [magnet], [sensor], [mount] (interfaces.md).
std::vector<KeySpec> common_keys();

// Concatenate schemas (later ones may not redeclare a key).
std::vector<KeySpec> merge_schemas(std::vector<KeySpec> a, const std::vector<KeySpec>& b);

}  // namespace magenc
