#include "core/config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <toml++/toml.h>
#include <type_traits>

#include "core/defaults.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/fp_trap.hpp"

namespace magenc {

KeySpec real_key(std::string key, double def, double min, double max, std::string unit,
                 std::string help, bool min_exclusive, bool max_exclusive) {
  KeySpec s;
  s.key = std::move(key);
  s.type = KeySpec::Type::Real;
  s.default_value = fmt_sig(def, 15);
  s.min = min;
  s.max = max;
  s.min_exclusive = min_exclusive;
  s.max_exclusive = max_exclusive;
  s.unit = std::move(unit);
  s.help = std::move(help);
  return s;
}

KeySpec int_key(std::string key, long def, long min, long max, std::string help) {
  KeySpec s;
  s.key = std::move(key);
  s.type = KeySpec::Type::Int;
  s.default_value = std::to_string(def);
  s.min = static_cast<double>(min);
  s.max = static_cast<double>(max);
  s.help = std::move(help);
  return s;
}

KeySpec string_key(std::string key, std::string def, std::vector<std::string> choices,
                   std::string help) {
  KeySpec s;
  s.key = std::move(key);
  s.type = KeySpec::Type::String;
  s.default_value = std::move(def);
  s.choices = std::move(choices);
  s.help = std::move(help);
  return s;
}

KeySpec number_or_word_key(std::string key, std::string def, std::vector<std::string> choices, std::string help) {
  KeySpec s = string_key(std::move(key), std::move(def), std::move(choices), std::move(help));
  s.numbers_as_text = true;
  return s;
}

KeySpec bool_key(std::string key, bool def, std::string help) {
  KeySpec s;
  s.key = std::move(key);
  s.type = KeySpec::Type::Bool;
  s.default_value = def ? "true" : "false";
  s.help = std::move(help);
  return s;
}

KeySpec real_list_key(std::string key, const std::vector<double>& def, double min, double max, std::string unit,
                      std::string help, bool min_exclusive, std::size_t min_elements) {
  KeySpec s = real_key(std::move(key), 0.0, min, max, std::move(unit), std::move(help), min_exclusive);
  s.type = KeySpec::Type::RealList;
  s.default_value.clear();
  for (std::size_t i = 0; i < def.size(); ++i) {
    if (i) s.default_value += ',';  // not ("," or "") + text: GCC 12 reports a false -Wrestrict for that once inlined
    s.default_value += fmt_sig(def[i], 15);
  }
  s.min_elements = min_elements;
  return s;
}

KeySpec int_list_key(std::string key, const std::vector<long>& def, long min, long max, std::string help,
                     std::size_t min_elements) {
  KeySpec s = int_key(std::move(key), 0, min, max, std::move(help));
  s.type = KeySpec::Type::IntList;
  s.default_value.clear();
  for (std::size_t i = 0; i < def.size(); ++i) {
    if (i) s.default_value += ',';  // as in real_list_key (GCC 12's false -Wrestrict)
    s.default_value += std::to_string(def[i]);
  }
  s.min_elements = min_elements;
  return s;
}

KeySpec string_list_key(std::string key, const std::vector<std::string>& def, std::vector<std::string> choices,
                        std::string help, std::size_t min_elements) {
  std::string text;
  for (std::size_t i = 0; i < def.size(); ++i) text += (i ? "," : "") + def[i];
  KeySpec s = string_key(std::move(key), text, std::move(choices), std::move(help));
  s.type = KeySpec::Type::StringList;
  s.min_elements = min_elements;
  return s;
}

KeySpec table_list_key(std::string key, std::vector<KeySpec> fields, std::string def_toml, std::string help) {
  KeySpec s;
  s.key = std::move(key);
  s.type = KeySpec::Type::TableList;
  s.fields = std::move(fields);
  s.default_value = std::move(def_toml);
  s.min_elements = 0;
  s.help = std::move(help);
  return s;
}

KeySpec settings_field(std::string name, std::string help) {
  KeySpec s;
  s.key = std::move(name);
  s.type = KeySpec::Type::Settings;
  s.help = std::move(help);
  return s;
}

KeySpec real_array_field(std::string name, std::size_t length, double min, double max, std::string unit,
                         std::string help) {
  KeySpec s = real_list_key(std::move(name), std::vector<double>(length, 0.0), min, max, std::move(unit),
                            std::move(help), false, length);
  s.max_elements = length;
  return s;
}

KeySpec required(KeySpec field) {
  field.required = true;
  return field;
}

bool ConfigTable::has(const std::string& field) const {
  for (const auto& e : entries)
    if (e.field == field) return true;
  return false;
}

std::string ConfigTable::text(const std::string& field) const {
  for (const auto& e : entries)
    if (e.field == field && e.key.empty())
      if (auto p = std::get_if<std::string>(&e.value)) return *p;
  return "";
}

std::vector<std::pair<std::string, ConfigScalar>> ConfigTable::settings(const std::string& field) const {
  std::vector<std::pair<std::string, ConfigScalar>> out;
  for (const auto& e : entries)
    if (e.field == field && !e.key.empty()) out.emplace_back(e.key, e.value);
  return out;
}

std::vector<double> ConfigTable::numbers(const std::string& field) const {
  std::vector<double> out;
  for (const auto& e : entries)
    if (e.field == field && e.array)
      for (const auto& x : *e.array) {
        if (auto d = std::get_if<double>(&x)) out.push_back(*d);
        else if (auto l = std::get_if<long>(&x)) out.push_back(static_cast<double>(*l));
      }
  return out;
}

namespace {

bool is_list(KeySpec::Type t) {
  return t == KeySpec::Type::RealList || t == KeySpec::Type::IntList || t == KeySpec::Type::StringList;
}

// A list key of a fixed number of elements (real_array_field): a TOML array only.
bool fixed_length(const KeySpec& s) { return is_list(s.type) && s.max_elements > 0 && s.max_elements == s.min_elements; }

// The scalar type of a list key's elements.
KeySpec::Type element_type(KeySpec::Type t) {
  if (t == KeySpec::Type::RealList) return KeySpec::Type::Real;
  if (t == KeySpec::Type::IntList) return KeySpec::Type::Int;
  if (t == KeySpec::Type::StringList) return KeySpec::Type::String;
  return t;
}

// A scalar value as a ConfigScalar (lists and tables: 0.0; callers pass scalars).
ConfigScalar as_scalar(const ConfigValue& v) {
  return std::visit([](const auto& x) -> ConfigScalar {
    using T = std::decay_t<decltype(x)>;
    if constexpr (std::is_same_v<T, ConfigList> || std::is_same_v<T, ConfigTables>) return ConfigScalar(0.0);
    else return ConfigScalar(x);
  }, v);
}

std::string scalar_text(const ConfigScalar& v) {
  if (auto d = std::get_if<double>(&v)) return fmt_sig(*d, 12);
  if (auto i = std::get_if<long>(&v)) return std::to_string(*i);
  if (auto s = std::get_if<std::string>(&v)) return *s;
  return std::get<bool>(v) ? "true" : "false";
}

// Text of a scalar or list value (lists: comma-separated); not for tables.
std::string value_text(const ConfigValue& v) {
  if (auto l = std::get_if<ConfigList>(&v)) {
    std::string t;
    for (std::size_t i = 0; i < l->size(); ++i) t += (i ? "," : "") + scalar_text((*l)[i]);
    return t;
  }
  return std::visit([](const auto& x) -> std::string {
    using T = std::decay_t<decltype(x)>;
    if constexpr (std::is_same_v<T, ConfigList> || std::is_same_v<T, ConfigTables>) return "";
    else return scalar_text(ConfigScalar(x));
  }, v);
}

// A string as a TOML basic string or JSON string (the escapes both share).
std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (const unsigned char c : text) {
    if (c == '"' || c == '\\') q += '\\', q += static_cast<char>(c);
    else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      q += buf;
    } else q += static_cast<char>(c);
  }
  return q + '"';
}

// A real as TOML (and JSON) writes it: 12 significant digits, always with a '.', 'e' or "nan"/"inf".
std::string real_text(double d) {
  std::string t = fmt_sig(d, 12);
  if (t.find_first_of(".eEn") == std::string::npos) t += ".0";
  return t;
}

std::string scalar_toml(const ConfigScalar& v) {
  if (auto s = std::get_if<std::string>(&v)) return quoted(*s);
  if (auto d = std::get_if<double>(&v)) return real_text(*d);
  return scalar_text(v);
}

// A dotted key as TOML: bare components where allowed, else quoted.
std::string dotted_key_toml(const std::string& key) {
  std::string out;
  std::size_t start = 0;
  while (true) {
    const auto dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    bool bare = !part.empty();
    for (const char c : part) bare = bare && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
    out += (start ? "." : "") + (bare ? part : quoted(part));
    if (dot == std::string::npos) return out;
    start = dot + 1;
  }
}

// Tables as one TOML inline array: [{ label = "a", set = { fem.order = 1 } }, ...]; `sep` between tables.
std::string tables_toml(const ConfigTables& tables, const std::string& open, const std::string& sep,
                        const std::string& close) {
  std::string out = "[";
  for (std::size_t i = 0; i < tables.size(); ++i) {
    out += (i ? sep : open) + "{ ";
    const auto& entries = tables[i].entries;
    for (std::size_t j = 0; j < entries.size();) {
      const ConfigTableEntry& e = entries[j];
      out += (j ? ", " : "") + dotted_key_toml(e.field) + " = ";
      if (e.array) {
        out += "[";
        for (std::size_t k = 0; k < e.array->size(); ++k) out += (k ? ", " : "") + scalar_toml((*e.array)[k]);
        out += "]";
        ++j;
        continue;
      }
      if (e.key.empty()) {
        out += scalar_toml(e.value);
        ++j;
        continue;
      }
      out += "{ ";
      for (std::size_t k = j; j < entries.size() && entries[j].field == e.field && !entries[j].key.empty(); ++j)
        out += (j == k ? "" : ", ") + dotted_key_toml(entries[j].key) + " = " + scalar_toml(entries[j].value);
      out += " }";
    }
    out += " }";
  }
  return out + (tables.empty() ? "" : close) + "]";
}

// Tables as a JSON array of objects (Settings fields as objects of their dotted keys).
std::string tables_json(const ConfigTables& tables) {
  std::string out = "[";
  for (std::size_t i = 0; i < tables.size(); ++i) {
    out += std::string(i ? ", " : "") + "{";
    const auto& entries = tables[i].entries;
    for (std::size_t j = 0; j < entries.size();) {
      const ConfigTableEntry& e = entries[j];
      out += (j ? ", " : "") + quoted(e.field) + ": ";
      if (e.array) {
        out += "[";
        for (std::size_t k = 0; k < e.array->size(); ++k) {
          const ConfigScalar& x = (*e.array)[k];
          out += (k ? ", " : "") + (std::holds_alternative<double>(x) ? fmt_sig(std::get<double>(x), 12) : scalar_toml(x));
        }
        out += "]";
        ++j;
        continue;
      }
      if (e.key.empty()) {
        out += std::holds_alternative<double>(e.value) ? fmt_sig(std::get<double>(e.value), 12) : scalar_toml(e.value);
        ++j;
        continue;
      }
      out += "{";
      for (std::size_t k = j; j < entries.size() && entries[j].field == e.field && !entries[j].key.empty(); ++j)
        out += (j == k ? "" : ", ") + quoted(entries[j].key) + ": " +
               (std::holds_alternative<double>(entries[j].value) ? fmt_sig(std::get<double>(entries[j].value), 12)
                                                                  : scalar_toml(entries[j].value));
      out += "}";
    }
    out += "}";
  }
  return out + "]";
}

// A TOML node as a configuration scalar; nullopt for arrays and tables.
std::optional<ConfigScalar> toml_scalar(const toml::node& node) {
  if (auto d = node.as_floating_point()) return ConfigScalar(d->get());
  if (auto i = node.as_integer()) return ConfigScalar(static_cast<long>(i->get()));
  if (auto str = node.as_string()) return ConfigScalar(str->get());
  if (auto b = node.as_boolean()) return ConfigScalar(b->get());
  return std::nullopt;
}

// The elements of a TOML array of a list key (a file's or --set's): scalars only.
ConfigList toml_list(const KeySpec& s, const toml::array& a, const std::string& origin) {
  ConfigList elements;
  for (std::size_t i = 0; i < a.size(); ++i) {
    auto e = toml_scalar(*a.get(i));
    if (!e)
      throw InputError(origin + ": " + s.key + " element " + std::to_string(i + 1) + " of " + std::to_string(a.size()) +
                       " is an array or table: allowed " + allowed_range(s));
    elements.push_back(*e);
  }
  return elements;
}

// Bounds of TOML text before toml++ parses it (defined below).
void check_toml_bounds(const std::string& text, const std::string& origin);

// A --set value written in TOML (an inline array or array of tables) as the table {value = TEXT};
// a parse error is the InputError whose text message(description) builds from the parser's description.
template <class Message>
toml::table parse_inline_toml(const std::string& text, const std::string& origin, Message&& message) {
  check_toml_bounds(text, origin);
  try {
    const FpTrapPause parsing_input;  // strtod of 1e999 raises FE_OVERFLOW: input, not a bug (fp_trap.hpp)
    return toml::parse("value = " + text, origin);
  } catch (const toml::parse_error& e) {
    throw InputError(message(std::string(e.description())));
  }
}

// Calls leaf(dotted key, node) for every node of tbl that is not a table, and for the tables
// stop(dotted key) names (the tables of a table-list key written as [key] instead of [[key]]).
void walk_table(const toml::table& tbl, const std::string& prefix,
                const std::function<void(const std::string&, const toml::node&)>& leaf,
                const std::function<bool(const std::string&)>& stop = {}) {
  for (const auto& [k, node] : tbl) {
    std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (auto sub = node.as_table(); sub && !(stop && stop(key))) walk_table(*sub, key, leaf, stop);
    else leaf(key, node);
  }
}

const KeySpec* field_spec(const KeySpec& s, const std::string& name) {
  for (const auto& f : s.fields)
    if (f.key == name) return &f;
  return nullptr;
}

// The one-line error of element i (0-based) of n of a table-list key.
[[noreturn]] void table_fail(const KeySpec& s, const std::string& where, std::size_t i, std::size_t n,
                             const std::string& why) {
  throw InputError(where + s.key + " element " + std::to_string(i + 1) + " of " + std::to_string(n) + ": " + why +
                   ": allowed " + allowed_range(s));
}

// A TOML array of tables as the tables of table-list key s (structure only: check_tables checks the fields).
ConfigTables toml_tables(const KeySpec& s, const toml::node& node, const std::string& where) {
  const toml::array* a = node.as_array();
  if (!a)
    throw InputError(where + s.key + " must be an array of tables ([[" + s.key + "]] sections or = [{ ... }]): allowed " +
                     allowed_range(s));
  ConfigTables out;
  for (std::size_t i = 0; i < a->size(); ++i) {
    const auto fail = [&](const std::string& why) { table_fail(s, where, i, a->size(), why); };
    const toml::table* t = a->get(i)->as_table();
    if (!t) fail(a->get(i)->as_array() ? "is an array, not a table" : "is not a table");
    ConfigTable table;
    for (const auto& [k, value] : *t) {
      const std::string name(k.str());
      const KeySpec* f = field_spec(s, name);
      if (!f) fail("unknown field '" + name + "'");
      if (f->type == KeySpec::Type::Settings) {
        const toml::table* settings = value.as_table();
        if (!settings) fail(name + " is not a table of key = value");
        walk_table(*settings, "", [&](const std::string& key, const toml::node& x) {
          const auto v = toml_scalar(x);
          if (!v) fail(name + " key " + key + " is an array: allowed a number, string or boolean");
          table.entries.push_back({name, key, *v});
        });
      } else if (const toml::array* elements = value.as_array(); elements && is_list(f->type)) {
        ConfigList list;
        for (std::size_t m = 0; m < elements->size(); ++m) {
          const auto v = toml_scalar(*elements->get(m));
          if (!v)
            fail("field " + name + " element " + std::to_string(m + 1) + " of " + std::to_string(elements->size()) +
                 " is an array or table");
          list.push_back(*v);
        }
        table.entries.push_back({name, "", ConfigScalar(0.0), std::move(list)});
      } else {
        const auto v = toml_scalar(value);
        if (!v) fail(is_list(f->type) ? "field " + name + " must be an array" : name + " is an array or table");
        table.entries.push_back({name, "", *v});
      }
    }
    out.push_back(std::move(table));
  }
  return out;
}

// A Settings key (a table of key = scalar as the value of one key, e.g. calibration.at = { mount.sx_mm = 0.1 })
// is held as one table whose entries are field "set" with the dotted keys (nested tables flattened).
ConfigTables settings_tables(const KeySpec& s, const toml::node& node, const std::string& where) {
  const toml::table* t = node.as_table();
  if (!t) throw InputError(where + s.key + " must be a table: allowed " + allowed_range(s));
  ConfigTable table;
  walk_table(*t, "", [&](const std::string& key, const toml::node& x) {
    const auto v = toml_scalar(x);
    if (!v) throw InputError(where + s.key + " key " + key + " is an array: allowed " + allowed_range(s));
    table.entries.push_back({"set", key, *v});
  });
  return {table};
}

// A Settings value as a JSON object of its dotted keys.
std::string settings_json(const ConfigTables& t) {
  std::string out = "{";
  if (!t.empty())
    for (std::size_t j = 0; j < t.front().entries.size(); ++j) {
      const ConfigTableEntry& e = t.front().entries[j];
      out += (j ? ", " : "") + quoted(e.key) + ": " +
             (std::holds_alternative<double>(e.value) ? fmt_sig(std::get<double>(e.value), 12) : scalar_toml(e.value));
    }
  return out + "}";
}

// A Settings value as TOML: { a.b = 1, c = "x" } ({} when empty).
std::string settings_toml(const ConfigTables& t) {
  if (t.empty() || t.front().entries.empty()) return "{}";
  std::string out = "{ ";
  const auto& e = t.front().entries;
  for (std::size_t j = 0; j < e.size(); ++j)
    out += (j ? ", " : "") + dotted_key_toml(e[j].key) + " = " + scalar_toml(e[j].value);
  return out + " }";
}

// Parse textual value per spec type (for defaults and --set).
ConfigValue parse_text(const KeySpec& s, const std::string& raw, const std::string& origin);

// A Settings or TableList value: a TOML inline table / array of tables (empty: none).
ConfigValue parse_tables_text(const KeySpec& s, const std::string& raw, const std::string& t, const std::string& origin) {
  if (s.type == KeySpec::Type::Settings) {
    if (t.empty()) return ConfigTables{ConfigTable{}};
    const toml::table tbl = parse_inline_toml(t, origin, [&](const std::string& why) {
      return origin + ": " + s.key + " is not a TOML inline table (" + why + "): allowed " + allowed_range(s);
    });
    const toml::node* value = tbl.get("value");
    if (!value) throw InputError(origin + ": " + s.key + " is not a TOML inline table: allowed " + allowed_range(s));
    return settings_tables(s, *value, origin + ": ");
  }
  // TableList
  if (t.empty()) return ConfigTables{};
  if (t.front() == '[') {
    const toml::table tbl = parse_inline_toml(t, origin, [&](const std::string& why) {
      return origin + ": " + s.key + " is not a TOML array of tables (" + why + "): allowed " + allowed_range(s);
    });
    const toml::node* value = tbl.get("value");
    if (!value) throw InputError(origin + ": " + s.key + " is not a TOML array of tables: allowed " + allowed_range(s));
    return toml_tables(s, *value, origin + ": ");
  }
  throw InputError(origin + ": " + s.key + " = '" + raw + "' is not a TOML array of tables: allowed " +
                   allowed_range(s) + ", e.g. [{ label = \"P1\", set = { fem.order = 1 } }], empty: none");
}

// A list value: a TOML array, or comma-separated text with each element parsed as a scalar.
ConfigValue parse_list_text(const KeySpec& s, const std::string& raw, const std::string& t, const std::string& origin) {
  auto fail = [&]() -> ConfigValue {
    throw InputError(origin + ": " + s.key + " = '" + raw + "' is not a valid value: allowed " +
                     allowed_range(s));
  };
  ConfigList elements;
  if (!t.empty() && t.front() == '[') {
    // A TOML array, as in a file: --set 'key=[1, 2]'.
    const toml::table tbl = parse_inline_toml(t, origin, [&](const std::string& why) {
      return origin + ": " + s.key + " = '" + raw + "' is not a TOML array (" + why + "): allowed " + allowed_range(s);
    });
    const toml::array* a = tbl["value"].as_array();
    if (!a) return fail();
    return toml_list(s, *a, origin);
  }
  if (fixed_length(s)) return fail();  // a fixed-length array: a TOML array only
  // Comma-separated text (earlier configurations): each element parsed as a scalar of the element type.
  KeySpec e = s;
  e.type = element_type(s.type);
  std::vector<std::string> parts;
  if (!t.empty()) {
    std::stringstream ss(t);
    for (std::string part; std::getline(ss, part, ',');) parts.push_back(part);
    if (t.back() == ',') parts.push_back("");
  }
  for (std::size_t i = 0; i < parts.size(); ++i) {
    try {
      elements.push_back(as_scalar(parse_text(e, parts[i], origin)));
    } catch (const InputError&) {
      throw InputError(origin + ": " + s.key + " element " + std::to_string(i + 1) + " of " +
                       std::to_string(parts.size()) + " = '" + trim(parts[i]) + "' is not a valid value: allowed " +
                       allowed_range(s));
    }
  }
  return elements;
}

ConfigValue parse_text(const KeySpec& s, const std::string& raw, const std::string& origin) {
  std::string t = trim(raw);
  auto fail = [&]() -> ConfigValue {
    throw InputError(origin + ": " + s.key + " = '" + raw + "' is not a valid value: allowed " +
                     allowed_range(s));
  };
  if (s.type == KeySpec::Type::Settings || s.type == KeySpec::Type::TableList) return parse_tables_text(s, raw, t, origin);
  if (is_list(s.type)) return parse_list_text(s, raw, t, origin);
  switch (s.type) {
    case KeySpec::Type::Real: {
      if (t.empty()) return fail();
      std::size_t pos = 0;
      double v = 0;
      try {
        // strtod raises FE_OVERFLOW for out-of-range text such as 1e999 (and stod then throws):
        // bad input, reported below as such, not a numerical bug, so untrapped (fp_trap.hpp).
        const FpTrapPause parsing_input;
        v = std::stod(t, &pos);
      } catch (...) {
        return fail();
      }
      if (pos != t.size()) return fail();
      return v;
    }
    case KeySpec::Type::Int: {
      if (t.empty()) return fail();
      std::size_t pos = 0;
      long v = 0;
      try {
        v = std::stol(t, &pos);
      } catch (...) {
        return fail();
      }
      if (pos != t.size()) return fail();
      return v;
    }
    case KeySpec::Type::String:
      if (t.size() >= 2 && (t.front() == '"' || t.front() == '\'') && t.back() == t.front())
        t = t.substr(1, t.size() - 2);
      return t;
    case KeySpec::Type::Bool:
      if (t == "true" || t == "1" || t == "yes") return true;
      if (t == "false" || t == "0" || t == "no") return false;
      return fail();
    case KeySpec::Type::RealList:
    case KeySpec::Type::IntList:
    case KeySpec::Type::StringList:
    case KeySpec::Type::TableList:
    case KeySpec::Type::Settings:
      break;  // handled above
  }
  return fail();
}

}  // namespace

std::string allowed_range(const KeySpec& s) {
  if (s.type == KeySpec::Type::TableList) {
    std::string r = "an array of tables {";
    for (std::size_t i = 0; i < s.fields.size(); ++i) {
      const KeySpec& f = s.fields[i];
      r += (i ? ", " : "") + f.key + " = " +
           (f.type == KeySpec::Type::Settings ? "{ key = value, ... }"
            : f.type == KeySpec::Type::String && f.choices.empty() ? "a non-empty string"
                                                                   : allowed_range(f)) +
           (f.required ? " (required)" : "");
    }
    return r + "}";
  }
  if (s.type == KeySpec::Type::Settings) return "{ key = value, ... }";
  if (is_list(s.type)) {
    KeySpec e = s;
    e.type = element_type(s.type);
    std::string what;
    if (e.type == KeySpec::Type::String)
      what = s.choices.empty() ? "non-empty strings" : "strings, each " + allowed_range(e);
    else
      what = std::string(e.type == KeySpec::Type::Int ? "integers" : "numbers") + ", each " + allowed_range(e);
    if (fixed_length(s)) return "an array of " + std::to_string(s.min_elements) + " " + what;
    const std::string count = std::to_string(s.min_elements) +
                              (s.max_elements > 0 ? " to " + std::to_string(s.max_elements) : std::string(" or more"));
    return "an array of " + count + " " + what + " (or the same as comma-separated text)";
  }
  switch (s.type) {
    case KeySpec::Type::Real:
    case KeySpec::Type::Int: {
      std::string r = std::string(s.min_exclusive ? "(" : "[") + fmt_sig(s.min, 12) + ", " +
                      fmt_sig(s.max, 12) + (s.max_exclusive ? ")" : "]");
      if (s.type == KeySpec::Type::Int) r = "integer in " + r;
      if (!s.unit.empty()) r += " " + s.unit;
      return r;
    }
    case KeySpec::Type::String: {
      if (s.choices.empty()) return "a string";
      std::string r = "one of ";
      for (std::size_t i = 0; i < s.choices.size(); ++i) r += (i ? ", " : "") + s.choices[i];
      return r;
    }
    case KeySpec::Type::Bool:
      return "true or false";
    case KeySpec::Type::RealList:
    case KeySpec::Type::IntList:
    case KeySpec::Type::StringList:
    case KeySpec::Type::TableList:
    case KeySpec::Type::Settings:
      break;  // handled above
  }
  return "";
}

Config::Config(std::vector<KeySpec> schema) : schema_(std::move(schema)) {
  for (const auto& s : schema_) {
    if (values_.count(s.key)) throw std::logic_error("config key declared twice: " + s.key);
    values_[s.key] = ConfigValue{};  // placeholder so spec lookups during defaults work
  }
  for (const auto& s : schema_) assign_checked(s, parse_text(s, s.default_value, "default"), "default");
}

const KeySpec& Config::spec(const std::string& key) const {
  for (const auto& s : schema_)
    if (s.key == key) return s;
  std::string known;
  for (const auto& s : schema_) known += (known.empty() ? "" : ", ") + s.key;
  throw InputError("unknown configuration key '" + key + "': allowed keys are " + known);
}

bool Config::has(const std::string& key) const { return values_.count(key) > 0; }

namespace {

// A scalar value of scalar key s, checked (range, choices, type) and normalized (an integral
// double of an Int key becomes a long, an integer of a Real key a double).
ConfigValue checked_scalar(const KeySpec& s, const ConfigValue& v, const std::string& where) {
  auto range_fail = [&](const std::string& shown) {
    throw InputError(where + s.key + " = " + shown + " is out of range: allowed " + allowed_range(s));
  };
  switch (s.type) {
    case KeySpec::Type::Real: {
      double d;
      if (auto p = std::get_if<double>(&v)) d = *p;
      else if (auto q = std::get_if<long>(&v)) d = static_cast<double>(*q);
      else throw InputError(where + s.key + " must be a number: allowed " + allowed_range(s));
      // +inf only for a key whose declared upper bound is +inf (inclusive): "no limit" (sensor.field_max_mT).
      const bool inf_ok = std::isinf(s.max) && !s.max_exclusive && d == s.max;
      const bool ok = (std::isfinite(d) || inf_ok) && (s.min_exclusive ? d > s.min : d >= s.min) &&
                      (s.max_exclusive ? d < s.max : d <= s.max);
      if (!ok) range_fail(fmt_sig(d, 12));
      return d;
    }
    case KeySpec::Type::Int: {
      long i;
      if (auto q = std::get_if<long>(&v)) i = *q;
      else if (auto p = std::get_if<double>(&v); p && std::isfinite(*p) && *p == std::floor(*p)) {
        // Range-checked as a double first: casting 1e300 to long is undefined (float-cast-overflow).
        if (*p < s.min || *p > s.max) range_fail(fmt_sig(*p, 12));
        i = static_cast<long>(*p);
      } else throw InputError(where + s.key + " must be an integer: allowed " + allowed_range(s));
      if (static_cast<double>(i) < s.min || static_cast<double>(i) > s.max)
        range_fail(std::to_string(i));
      return i;
    }
    case KeySpec::Type::String: {
      auto p = std::get_if<std::string>(&v);
      std::string number_text;
      if (!p && s.numbers_as_text) {
        if (auto q = std::get_if<long>(&v)) number_text = std::to_string(*q);
        else if (auto d = std::get_if<double>(&v); d && std::isfinite(*d)) number_text = fmt_sig(*d, 17);
        if (!number_text.empty()) p = &number_text;
      }
      if (!p) throw InputError(where + s.key + " must be a string: allowed " + allowed_range(s));
      if (!s.choices.empty()) {
        bool ok = false;
        for (const auto& c : s.choices) ok = ok || c == *p;
        if (!ok) range_fail("'" + *p + "'");
      }
      return *p;
    }
    case KeySpec::Type::Bool: {
      auto p = std::get_if<bool>(&v);
      if (!p) throw InputError(where + s.key + " must be true or false");
      return *p;
    }
    default:
      throw std::logic_error("checked_scalar: not a scalar key: " + s.key);
  }
}

// Why entry e of array field f (real_array_field) is not valid ("" when it is); its elements normalized.
std::string array_field_error(const KeySpec& f, ConfigTableEntry& e) {
  if (!e.array || !e.key.empty()) return "field " + e.field + " must be an array";
  ConfigList& l = *e.array;
  if (l.size() < f.min_elements || (f.max_elements > 0 && l.size() > f.max_elements))
    return "field " + e.field + " has " + std::to_string(l.size()) + " element" + (l.size() == 1 ? "" : "s");
  KeySpec element = f;
  element.type = element_type(f.type);
  for (std::size_t k = 0; k < l.size(); ++k) {
    element.key = "field " + e.field + " element " + std::to_string(k + 1) + " of " + std::to_string(l.size());
    try {
      l[k] = as_scalar(checked_scalar(element, std::visit([](const auto& y) { return ConfigValue(y); }, l[k]), ""));
    } catch (const InputError& err) {
      std::string why = err.what();  // "field x element 1 of 2 = nan is out of range: allowed ...": cut below
      if (const auto cut = why.find(": allowed "); cut != std::string::npos) why.erase(cut);
      return why;
    }
  }
  return "";
}

// The tables of table-list key s, checked: declared fields only, required ones present, scalar
// fields valid (non-empty text for a free String), array fields of their length with valid elements,
// Settings values finite; entries sorted by field and key.
ConfigTables checked_tables(const KeySpec& s, ConfigTables tables, const std::string& where) {
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const auto fail = [&](const std::string& why) { table_fail(s, where, i, tables.size(), why); };
    auto& entries = tables[i].entries;
    std::stable_sort(entries.begin(), entries.end(), [](const ConfigTableEntry& a, const ConfigTableEntry& b) {
      return a.field != b.field ? a.field < b.field : a.key < b.key;
    });
    for (std::size_t j = 0; j < entries.size(); ++j) {
      ConfigTableEntry& e = entries[j];
      const KeySpec* f = field_spec(s, e.field);
      if (!f) fail("unknown field '" + e.field + "'");
      if (j > 0 && entries[j - 1].field == e.field && entries[j - 1].key == e.key)
        fail(e.field + (e.key.empty() ? "" : " key " + e.key) + " is given twice");
      if (f->type == KeySpec::Type::Settings) {
        if (e.key.empty() || e.key.front() == '.' || e.key.back() == '.' || e.key.find("..") != std::string::npos)
          fail(e.field + " is not a table of key = value");
        if (auto d = std::get_if<double>(&e.value); d && !std::isfinite(*d))
          fail(e.field + " key " + e.key + " = " + fmt_sig(*d, 6) + " is not finite");
        continue;
      }
      if (is_list(f->type)) {
        if (const std::string why = array_field_error(*f, e); !why.empty()) fail(why);
        continue;
      }
      if (e.array) fail("field " + e.field + " is an array");
      if (!e.key.empty()) fail(e.field + " is not a table");
      if (f->type == KeySpec::Type::String && f->choices.empty())
        if (auto p = std::get_if<std::string>(&e.value); p && trim(*p).empty()) fail(e.field + " is empty");
      try {
        e.value = as_scalar(checked_scalar(*f, ConfigValue(std::visit([](const auto& y) { return ConfigValue(y); },
                                                                      e.value)), ""));
      } catch (const InputError& err) {
        std::string why = err.what();  // "label must be a string: allowed a string": the fields are named below
        if (const auto cut = why.find(": allowed "); cut != std::string::npos) why.erase(cut);
        fail("field " + why);
      }
    }
    for (const auto& f : s.fields)
      if (f.required && !tables[i].has(f.key)) fail("has no " + f.key);
  }
  return tables;
}

}  // namespace

void Config::assign_checked(const KeySpec& s, const ConfigValue& v, const std::string& origin) {
  const std::string where = origin.empty() ? "" : origin + ": ";
  if (s.type == KeySpec::Type::Settings) {
    const auto* t = std::get_if<ConfigTables>(&v);
    if (!t || t->size() != 1) throw InputError(where + s.key + " must be a table: allowed " + allowed_range(s));
    ConfigTable table = t->front();
    auto& e = table.entries;
    std::stable_sort(e.begin(), e.end(), [](const ConfigTableEntry& a, const ConfigTableEntry& b) { return a.key < b.key; });
    for (std::size_t j = 0; j < e.size(); ++j) {
      if (e[j].key.empty() || e[j].key.front() == '.' || e[j].key.back() == '.' || e[j].key.find("..") != std::string::npos)
        throw InputError(where + s.key + " is not a table of key = value: allowed " + allowed_range(s));
      if (j > 0 && e[j - 1].key == e[j].key)
        throw InputError(where + s.key + " key " + e[j].key + " is given twice: allowed " + allowed_range(s));
      if (auto d = std::get_if<double>(&e[j].value); d && !std::isfinite(*d))
        throw InputError(where + s.key + " key " + e[j].key + " = " + fmt_sig(*d, 6) + " is not finite: allowed " +
                         allowed_range(s));
    }
    values_[s.key] = ConfigTables{table};
    return;
  }
  if (s.type == KeySpec::Type::TableList) {
    if (auto t = std::get_if<ConfigTables>(&v)) {
      values_[s.key] = checked_tables(s, *t, where);
      return;
    }
    throw InputError(where + s.key + " must be an array of tables ([[" + s.key + "]] sections or = [{ ... }]): allowed " +
                     allowed_range(s));
  }
  if (is_list(s.type)) {
    const ConfigList* l = std::get_if<ConfigList>(&v);
    if (!l) {
      // A scalar in a TOML file: a string is the comma-separated form, anything else is not a list.
      if (auto text = std::get_if<std::string>(&v)) return assign_checked(s, parse_text(s, *text, origin), origin);
      throw InputError(where + s.key + " must be an array: allowed " + allowed_range(s));
    }
    if (l->size() < s.min_elements || (s.max_elements > 0 && l->size() > s.max_elements))
      throw InputError(where + s.key + " has " + std::to_string(l->size()) + " elements: allowed " + allowed_range(s));
    KeySpec e = s;
    e.type = element_type(s.type);
    ConfigList checked;
    for (std::size_t i = 0; i < l->size(); ++i) {
      const ConfigScalar& x = (*l)[i];
      const std::string shown = std::holds_alternative<std::string>(x) ? "'" + std::get<std::string>(x) + "'"
                                                                      : scalar_text(x);
      const std::string element = s.key + " element " + std::to_string(i + 1) + " of " + std::to_string(l->size());
      if (e.type == KeySpec::Type::String && std::holds_alternative<std::string>(x) &&
          trim(std::get<std::string>(x)).empty())
        throw InputError(where + element + " is empty: allowed " + allowed_range(s));
      try {
        checked.push_back(as_scalar(checked_scalar(e, std::visit([](const auto& y) { return ConfigValue(y); }, x), "")));
      } catch (const InputError&) {
        throw InputError(where + element + " = " + shown + " is not valid: allowed " + allowed_range(s));
      }
    }
    values_[s.key] = checked;
    return;
  }
  values_[s.key] = checked_scalar(s, v, where);
}

void Config::set_value(const std::string& key, const ConfigValue& value) {
  assign_checked(spec(key), value, "");
}

void Config::set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos)
    throw InputError("--set '" + assignment + "': expected section.key=value");
  const std::string key = trim(assignment.substr(0, eq));
  const KeySpec& s = spec(key);
  assign_checked(s, parse_text(s, assignment.substr(eq + 1), "--set"), "--set");
}

namespace {
// toml++ parses recursively: a 50,000-level dotted header ([a.a.a...]) or deeply nested inline
// tables/arrays overflow the stack. Every declared key is "section.name" (a few levels at most), so
// bound the input before parsing: size, dotted-key depth per line, bracket/brace nesting.
constexpr std::size_t kMaxTomlBytes = std::size_t(1) << 20;  // 1 MiB
constexpr int kMaxTomlDepth = 8;
void check_toml_bounds(const std::string& text, const std::string& origin) {
  if (text.size() > kMaxTomlBytes)
    throw InputError(origin + ": " + std::to_string(text.size()) + " bytes: allowed at most " +
                     std::to_string(kMaxTomlBytes) + " bytes of TOML");
  int line = 1, dots = 0;
  std::string open;  // stack of the '[' and '{' not yet closed
  char quote = 0;
  bool comment = false, value = false;  // value: after '=' of the current key (dots there are decimals)
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      dots = 0;
      comment = false;
      if (open.empty()) value = false;  // arrays and inline tables may continue on the next line
      quote = 0;  // single-line strings end here (an unterminated one is toml++'s error to report)
      continue;
    }
    if (comment) continue;
    if (quote) {
      if (c == '\\' && quote == '"') ++i;
      else if (c == quote) quote = 0;
      continue;
    }
    if (c == '"' || c == '\'') quote = c;
    else if (c == '#') comment = true;
    else if (c == '=') value = true, dots = 0;
    else if (c == '.' && !value) ++dots;
    else if (c == '[' || c == '{') {
      open.push_back(c);
      if (c == '{') value = false, dots = 0;  // an inline table starts with a key
    } else if (c == ']' || c == '}') {
      if (!open.empty()) open.pop_back();
      if (c == '}') value = true;  // the inline table was the value of the enclosing key
    } else if (c == ',' && !open.empty() && open.back() == '{') value = false, dots = 0;
    const int nest = static_cast<int>(open.size());
    if (dots > kMaxTomlDepth || nest > kMaxTomlDepth)
      throw InputError(origin + ": line " + std::to_string(line) + ": keys or tables nested deeper than " +
                       std::to_string(kMaxTomlDepth) + " levels: allowed section.key (at most " +
                       std::to_string(kMaxTomlDepth) + ")");
  }
}
}  // namespace

void Config::load_toml_string(const std::string& text, const std::string& origin) {
  check_toml_bounds(text, origin);
  toml::table tbl;
  try {
    // toml++ reads floats through strtod, which raises FE_OVERFLOW for 1e999 (a value the range
    // checks below reject): input parsing, untrapped (fp_trap.hpp).
    const FpTrapPause parsing_input;
    tbl = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << origin << ": malformed TOML at line " << e.source().begin.line << ": " << e.description();
    throw InputError(os.str());
  }
  const auto table_list = [&](const std::string& key) {
    for (const auto& s : schema_)
      if (s.key == key) return s.type == KeySpec::Type::TableList || s.type == KeySpec::Type::Settings;
    return false;
  };
  walk_table(tbl, "", [&](const std::string& key, const toml::node& node) {
    const KeySpec& s = spec(key);
    ConfigValue v;
    if (s.type == KeySpec::Type::TableList) {
      v = toml_tables(s, node, origin + ": ");
    } else if (s.type == KeySpec::Type::Settings) {
      v = settings_tables(s, node, origin + ": ");
    } else if (auto x = toml_scalar(node)) {
      v = std::visit([](const auto& y) { return ConfigValue(y); }, *x);
    } else if (auto a = node.as_array(); a && is_list(s.type)) {
      v = toml_list(s, *a, origin);
    } else {
      throw InputError(origin + ": " + key + " has an unsupported TOML type: allowed " + allowed_range(s));
    }
    assign_checked(s, v, origin);
  }, table_list);
}

void Config::load_toml_file(const std::string& path) {
  std::error_code ec;
  // A directory opens as an empty stream (it read as an empty TOML: defaults, silently).
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError("--config " + path + ": not a file (" +
                     (std::filesystem::exists(path, ec) ? "a directory or special file" : "does not exist") + ")");
  if (std::filesystem::file_size(path, ec) > kMaxTomlBytes)
    throw InputError("--config " + path + ": larger than " + std::to_string(kMaxTomlBytes) + " bytes of TOML");
  std::ifstream in(path);
  if (!in) throw InputError("--config " + path + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  load_toml_string(ss.str(), path);
}

double Config::real(const std::string& key) const {
  const auto& v = values_.at(spec(key).key);
  if (auto d = std::get_if<double>(&v)) return *d;
  throw std::logic_error("config key is not real: " + key);
}
long Config::integer(const std::string& key) const {
  const auto& v = values_.at(spec(key).key);
  if (auto i = std::get_if<long>(&v)) return *i;
  throw std::logic_error("config key is not integer: " + key);
}
std::string Config::str(const std::string& key) const {
  const auto& v = values_.at(spec(key).key);
  if (auto s = std::get_if<std::string>(&v)) return *s;
  if (std::holds_alternative<ConfigList>(v)) return value_text(v);
  throw std::logic_error("config key is not a string: " + key);
}
ConfigTables Config::tables(const std::string& key) const {
  const auto& v = values_.at(spec(key).key);
  if (auto t = std::get_if<ConfigTables>(&v)) return *t;
  throw std::logic_error("config key is not a table list: " + key);
}
namespace {
// The elements of a list value as T (a list key of the matching type: right_type).
template <class T>
std::vector<T> elements_of(const ConfigValue& v, bool right_type, const std::string& key, const std::string& what) {
  const auto* l = std::get_if<ConfigList>(&v);
  if (!l || !right_type) throw std::logic_error("config key is not a list of " + what + ": " + key);
  std::vector<T> out;
  for (const auto& x : *l) out.push_back(std::get<T>(x));
  return out;
}
}  // namespace

std::vector<double> Config::reals(const std::string& key) const {
  const KeySpec& s = spec(key);
  return elements_of<double>(values_.at(s.key), s.type == KeySpec::Type::RealList, key, "reals");
}
std::vector<long> Config::integers(const std::string& key) const {
  const KeySpec& s = spec(key);
  return elements_of<long>(values_.at(s.key), s.type == KeySpec::Type::IntList, key, "integers");
}
std::vector<double> Config::numbers(const std::string& key) const {
  const KeySpec& s = spec(key);
  if (s.type == KeySpec::Type::RealList) return reals(key);
  const auto ints = elements_of<long>(values_.at(s.key), s.type == KeySpec::Type::IntList, key, "numbers");
  return std::vector<double>(ints.begin(), ints.end());
}
std::vector<std::string> Config::strings(const std::string& key) const {
  const KeySpec& s = spec(key);
  return elements_of<std::string>(values_.at(s.key), s.type == KeySpec::Type::StringList, key, "strings");
}
bool Config::flag(const std::string& key) const {
  const auto& v = values_.at(spec(key).key);
  if (auto b = std::get_if<bool>(&v)) return *b;
  throw std::logic_error("config key is not bool: " + key);
}

std::string Config::to_toml() const {
  // Group by section, in declaration order.
  std::vector<std::string> sections;
  for (const auto& s : schema_) {
    const auto dot = s.key.rfind('.');
    const std::string sec = dot == std::string::npos ? "" : s.key.substr(0, dot);
    bool seen = false;
    for (const auto& x : sections) seen = seen || x == sec;
    if (!seen) sections.push_back(sec);
  }
  std::ostringstream os;
  for (const auto& sec : sections) {
    if (!sec.empty()) os << "[" << sec << "]\n";
    for (const auto& s : schema_) {
      const auto dot = s.key.rfind('.');
      const std::string ksec = dot == std::string::npos ? "" : s.key.substr(0, dot);
      if (ksec != sec) continue;
      const std::string name = dot == std::string::npos ? s.key : s.key.substr(dot + 1);
      const auto& v = values_.at(s.key);
      os << name << " = ";
      if (auto str = std::get_if<std::string>(&v)) os << quoted(*str);
      else if (std::holds_alternative<ConfigList>(v)) os << quoted(value_text(v));
      else if (auto t = std::get_if<ConfigTables>(&v))
        os << (s.type == KeySpec::Type::Settings ? settings_toml(*t) : tables_toml(*t, "\n  ", ",\n  ", ",\n"));
      else if (auto d = std::get_if<double>(&v)) os << real_text(*d);
      else os << value_text(v);
      os << "\n";
    }
    os << "\n";
  }
  return os.str();
}

std::string Config::to_json() const {
  std::ostringstream os;
  os << "{";
  bool first = true;
  for (const auto& s : schema_) {
    const auto& v = values_.at(s.key);
    os << (first ? "" : ", ") << '"' << s.key << "\": ";
    first = false;
    if (auto str = std::get_if<std::string>(&v)) os << quoted(*str);
    else if (std::holds_alternative<ConfigList>(v)) os << quoted(value_text(v));
    else if (auto t = std::get_if<ConfigTables>(&v))
      os << (s.type == KeySpec::Type::Settings ? settings_json(*t) : tables_json(*t));
    else if (auto d = std::get_if<double>(&v); d && !std::isfinite(*d)) os << quoted(real_text(*d));  // "inf": JSON has no infinity
    else os << value_text(v);
  }
  os << "}";
  return os.str();
}

std::string Config::describe() const {
  std::ostringstream os;
  os << "Configuration keys (--config FILE.toml, --set key=value):\n";
  for (const auto& s : schema_) {
    os << "  " << std::left << std::setw(30) << s.key << " default " << s.default_value;
    os << ", allowed " << allowed_range(s) << ". " << s.help << "\n";
  }
  return os.str();
}

std::vector<KeySpec> merge_schemas(std::vector<KeySpec> a, const std::vector<KeySpec>& b) {
  for (const auto& s : b) {
    for (const auto& x : a)
      if (x.key == s.key) throw std::logic_error("config key declared twice: " + s.key);
    a.push_back(s);
  }
  return a;
}

namespace {
// calibration.at: a table of any configuration keys, set over the run's own values for the calibration state.
KeySpec calibration_at_key() {
  KeySpec s;
  s.key = "calibration.at";
  s.type = KeySpec::Type::Settings;
  s.default_value = "{ mount.sx_mm = 0.1, mount.dx_mm = 0.1 }";
  s.help = "the calibration state: a table of configuration keys (mount, sensor, ...) set over the run's own "
           "values, e.g. { mount.sx_mm = 0.1, mount.dx_mm = 0.1 }";
  return s;
}
}  // namespace

std::vector<KeySpec> calibration_keys() {
  return {
      // Calibration (docs/physics.md "Calibration"; analysis/calibration.hpp).
      string_key("calibration.method", "none", {},
                 "factory correction taken at calibration.at: none, harmonics:N (least-squares harmonics of the "
                 "error over the sensor's angle), lut:K (K-point periodic linear table), ogp (channel offsets, "
                 "gain ratio, phase)"),
      calibration_at_key(),
  };
}

}  // namespace magenc
