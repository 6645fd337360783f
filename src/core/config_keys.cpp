// The configuration's declarations: key factories, table fields, allowed ranges, merging schemas.
#include "core/config_keys.hpp"

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
#include <type_traits>

#include "core/defaults.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/fp_trap.hpp"

namespace magenc {

bool is_list(KeySpec::Type t) {
  return t == KeySpec::Type::RealList || t == KeySpec::Type::IntList || t == KeySpec::Type::StringList;
}

bool fixed_length(const KeySpec& s) { return is_list(s.type) && s.max_elements > 0 && s.max_elements == s.min_elements; }

KeySpec::Type element_type(KeySpec::Type t) {
  if (t == KeySpec::Type::RealList) return KeySpec::Type::Real;
  if (t == KeySpec::Type::IntList) return KeySpec::Type::Int;
  if (t == KeySpec::Type::StringList) return KeySpec::Type::String;
  return t;
}

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

std::vector<KeySpec> merge_schemas(std::vector<KeySpec> a, const std::vector<KeySpec>& b) {
  for (const auto& s : b) {
    for (const auto& x : a)
      if (x.key == s.key) throw std::logic_error("config key declared twice: " + s.key);
    a.push_back(s);
  }
  return a;
}

}  // namespace magenc
