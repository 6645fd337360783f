// The configuration's engine: the schema and its index, checked values, the typed getters.
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
#include <type_traits>

#include "core/config_detail.hpp"
#include "core/defaults.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/fp_trap.hpp"

namespace magenc {

using namespace config_detail;

Config::Config(std::vector<KeySpec> schema)
    : schema_(std::make_shared<const std::vector<KeySpec>>(std::move(schema))) {
  auto index = std::make_shared<std::unordered_map<std::string, std::size_t>>();
  for (std::size_t i = 0; i < schema_->size(); ++i)
    if (!index->emplace((*schema_)[i].key, i).second)
      throw std::logic_error("config key declared twice: " + (*schema_)[i].key);
  index_ = std::move(index);
  for (const auto& s : *schema_) values_[s.key] = ConfigValue{};  // placeholder so spec lookups during defaults work
  for (const auto& s : *schema_) assign_checked(s, parse_text(s, s.default_value, "default"), "default");
}

const KeySpec* Config::find(const std::string& key) const {
  const auto it = index_->find(key);
  return it == index_->end() ? nullptr : &(*schema_)[it->second];
}

const KeySpec& Config::spec(const std::string& key) const {
  if (const KeySpec* s = find(key)) return *s;
  std::string known;
  for (const auto& s : *schema_) known += (known.empty() ? "" : ", ") + s.key;
  throw InputError("unknown configuration key '" + key + "': allowed keys are " + known);
}

const std::string& Config::default_text(const std::string& key) const { return spec(key).default_value; }

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

}  // namespace magenc
