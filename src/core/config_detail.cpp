// The configuration's text helpers (core/config_detail.hpp): values as text, TOML as values, bounds of TOML input.
#include "core/config_detail.hpp"

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

namespace magenc::config_detail {

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
    for (std::size_t i = 0; i < l->size(); ++i) {
      if (i) t += ',';
      t += scalar_text((*l)[i]);
    }
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
                const std::function<bool(const std::string&)>& stop) {
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

// toml++ parses recursively: a 50,000-level dotted header ([a.a.a...]) or deeply nested inline
// tables/arrays overflow the stack. Every declared key is "section.name" (a few levels at most), so
// bound the input before parsing: size, dotted-key depth per line, bracket/brace nesting.
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

}  // namespace magenc::config_detail
