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
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <variant>
#include <vector>

#include "core/config_keys.hpp"

namespace magenc {

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

  // The declaration of key, or nullptr when this configuration does not declare it (one lookup in an
  // index, not a scan of the schema).
  const KeySpec* find(const std::string& key) const;
  // The declared default of key as its declaration writes it; InputError for an undeclared key.
  const std::string& default_text(const std::string& key) const;
  const std::vector<KeySpec>& schema() const { return *schema_; }
  // The values in use, as a TOML document (echoed next to outputs).
  std::string to_toml() const;
  // The values in use as JSON text (object of sections).
  std::string to_json() const;
  // Human-readable list of keys (for --help epilogues).
  std::string describe() const;

 private:
  const KeySpec& spec(const std::string& key) const;
  void assign_checked(const KeySpec& s, const ConfigValue& v, const std::string& origin);
  // The schema and its index by key are shared by the copies of a configuration (a study's per-case copies
  // copy only the values).
  std::shared_ptr<const std::vector<KeySpec>> schema_;
  std::shared_ptr<const std::unordered_map<std::string, std::size_t>> index_;
  std::map<std::string, ConfigValue> values_;
};

}  // namespace magenc
