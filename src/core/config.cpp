#include "core/config.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <toml++/toml.h>
#include <type_traits>

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
  for (std::size_t i = 0; i < def.size(); ++i) s.default_value += (i ? "," : "") + fmt_sig(def[i], 15);
  s.min_elements = min_elements;
  return s;
}

KeySpec int_list_key(std::string key, const std::vector<long>& def, long min, long max, std::string help,
                     std::size_t min_elements) {
  KeySpec s = int_key(std::move(key), 0, min, max, std::move(help));
  s.type = KeySpec::Type::IntList;
  s.default_value.clear();
  for (std::size_t i = 0; i < def.size(); ++i) s.default_value += (i ? "," : "") + std::to_string(def[i]);
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

namespace {

bool is_list(KeySpec::Type t) {
  return t == KeySpec::Type::RealList || t == KeySpec::Type::IntList || t == KeySpec::Type::StringList;
}

// The scalar type of a list key's elements.
KeySpec::Type element_type(KeySpec::Type t) {
  if (t == KeySpec::Type::RealList) return KeySpec::Type::Real;
  if (t == KeySpec::Type::IntList) return KeySpec::Type::Int;
  if (t == KeySpec::Type::StringList) return KeySpec::Type::String;
  return t;
}

std::string scalar_text(const ConfigScalar& v) {
  if (auto d = std::get_if<double>(&v)) return fmt_sig(*d, 12);
  if (auto i = std::get_if<long>(&v)) return std::to_string(*i);
  if (auto s = std::get_if<std::string>(&v)) return *s;
  return std::get<bool>(v) ? "true" : "false";
}

std::string value_text(const ConfigValue& v) {
  if (auto l = std::get_if<ConfigList>(&v)) {
    std::string t;
    for (std::size_t i = 0; i < l->size(); ++i) t += (i ? "," : "") + scalar_text((*l)[i]);
    return t;
  }
  return std::visit([](const auto& x) -> std::string {
    if constexpr (std::is_same_v<std::decay_t<decltype(x)>, ConfigList>) return "";
    else return scalar_text(ConfigScalar(x));
  }, v);
}

// A TOML node as a configuration scalar; nullopt for arrays and tables.
std::optional<ConfigScalar> toml_scalar(const toml::node& node) {
  if (auto d = node.as_floating_point()) return ConfigScalar(d->get());
  if (auto i = node.as_integer()) return ConfigScalar(static_cast<long>(i->get()));
  if (auto str = node.as_string()) return ConfigScalar(str->get());
  if (auto b = node.as_boolean()) return ConfigScalar(b->get());
  return std::nullopt;
}

// Bounds of TOML text before toml++ parses it (defined below).
void check_toml_bounds(const std::string& text, const std::string& origin);

// Parse textual value per spec type (for defaults and --set).
ConfigValue parse_text(const KeySpec& s, const std::string& raw, const std::string& origin) {
  std::string t = trim(raw);
  auto fail = [&]() -> ConfigValue {
    throw InputError(origin + ": " + s.key + " = '" + raw + "' is not a valid value: allowed " +
                     allowed_range(s));
  };
  if (is_list(s.type)) {
    ConfigList elements;
    if (!t.empty() && t.front() == '[') {
      // A TOML array, as in a file: --set 'key=[1, 2]'.
      check_toml_bounds(t, origin);
      toml::table tbl;
      try {
        const FpTrapPause parsing_input;  // strtod of 1e999 raises FE_OVERFLOW: input, not a bug (fp_trap.hpp)
        tbl = toml::parse("value = " + t, origin);
      } catch (const toml::parse_error& e) {
        throw InputError(origin + ": " + s.key + " = '" + raw + "' is not a TOML array (" +
                         std::string(e.description()) + "): allowed " + allowed_range(s));
      }
      const toml::array* a = tbl["value"].as_array();
      if (!a) return fail();
      for (std::size_t i = 0; i < a->size(); ++i) {
        auto e = toml_scalar(*a->get(i));
        if (!e)
          throw InputError(origin + ": " + s.key + " element " + std::to_string(i + 1) + " of " +
                           std::to_string(a->size()) + " is an array or table: allowed " + allowed_range(s));
        elements.push_back(*e);
      }
      return elements;
    }
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
        elements.push_back(std::visit([](const auto& x) -> ConfigScalar {
          if constexpr (std::is_same_v<std::decay_t<decltype(x)>, ConfigList>) return ConfigScalar(0.0);
          else return ConfigScalar(x);
        }, parse_text(e, parts[i], origin)));
      } catch (const InputError&) {
        throw InputError(origin + ": " + s.key + " element " + std::to_string(i + 1) + " of " +
                         std::to_string(parts.size()) + " = '" + trim(parts[i]) + "' is not a valid value: allowed " +
                         allowed_range(s));
      }
    }
    return elements;
  }
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
      break;  // handled above
  }
  return fail();
}

}  // namespace

std::string allowed_range(const KeySpec& s) {
  if (is_list(s.type)) {
    KeySpec e = s;
    e.type = element_type(s.type);
    std::string what;
    if (e.type == KeySpec::Type::String)
      what = s.choices.empty() ? "non-empty strings" : "strings, each " + allowed_range(e);
    else
      what = std::string(e.type == KeySpec::Type::Int ? "integers" : "numbers") + ", each " + allowed_range(e);
    return "an array of " + std::to_string(s.min_elements) + " or more " + what +
           " (or the same as comma-separated text)";
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

void Config::assign_checked(const KeySpec& s, const ConfigValue& v, const std::string& origin) {
  const std::string where = origin.empty() ? "" : origin + ": ";
  if (is_list(s.type)) {
    const ConfigList* l = std::get_if<ConfigList>(&v);
    if (!l) {
      // A scalar in a TOML file: a string is the comma-separated form, anything else is not a list.
      if (auto text = std::get_if<std::string>(&v)) return assign_checked(s, parse_text(s, *text, origin), origin);
      throw InputError(where + s.key + " must be an array: allowed " + allowed_range(s));
    }
    if (l->size() < s.min_elements)
      throw InputError(where + s.key + " has " + std::to_string(l->size()) + " elements: allowed " + allowed_range(s));
    KeySpec e = s;
    e.type = element_type(s.type);
    ConfigList checked;
    const ConfigValue before = values_.at(s.key);  // each element is checked through values_[s.key]
    struct Restore {
      std::map<std::string, ConfigValue>& values;
      const std::string& key;
      const ConfigValue& before;
      bool done = false;
      ~Restore() {
        if (!done) values[key] = before;
      }
    } restore{values_, s.key, before};
    for (std::size_t i = 0; i < l->size(); ++i) {
      const ConfigScalar& x = (*l)[i];
      const std::string shown = std::holds_alternative<std::string>(x) ? "'" + std::get<std::string>(x) + "'"
                                                                      : scalar_text(x);
      const std::string element = s.key + " element " + std::to_string(i + 1) + " of " + std::to_string(l->size());
      if (e.type == KeySpec::Type::String && std::holds_alternative<std::string>(x) &&
          trim(std::get<std::string>(x)).empty())
        throw InputError(where + element + " is empty: allowed " + allowed_range(s));
      try {
        std::visit([&](const auto& y) { assign_checked(e, ConfigValue(y), ""); }, x);
      } catch (const InputError&) {
        throw InputError(where + element + " = " + shown + " is not valid: allowed " + allowed_range(s));
      }
      checked.push_back(std::visit([](const auto& y) -> ConfigScalar {
        if constexpr (std::is_same_v<std::decay_t<decltype(y)>, ConfigList>) return ConfigScalar(0.0);
        else return ConfigScalar(y);
      }, values_.at(s.key)));
    }
    values_[s.key] = checked;
    restore.done = true;
    return;
  }
  auto range_fail = [&](const std::string& shown) {
    throw InputError(where + s.key + " = " + shown + " is out of range: allowed " + allowed_range(s));
  };
  switch (s.type) {
    case KeySpec::Type::Real: {
      double d;
      if (auto p = std::get_if<double>(&v)) d = *p;
      else if (auto q = std::get_if<long>(&v)) d = static_cast<double>(*q);
      else throw InputError(where + s.key + " must be a number: allowed " + allowed_range(s));
      const bool ok = std::isfinite(d) && (s.min_exclusive ? d > s.min : d >= s.min) &&
                      (s.max_exclusive ? d < s.max : d <= s.max);
      if (!ok) range_fail(fmt_sig(d, 12));
      values_[s.key] = d;
      return;
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
      values_[s.key] = i;
      return;
    }
    case KeySpec::Type::String: {
      auto p = std::get_if<std::string>(&v);
      if (!p) throw InputError(where + s.key + " must be a string: allowed " + allowed_range(s));
      if (!s.choices.empty()) {
        bool ok = false;
        for (const auto& c : s.choices) ok = ok || c == *p;
        if (!ok) range_fail("'" + *p + "'");
      }
      values_[s.key] = *p;
      return;
    }
    case KeySpec::Type::Bool: {
      auto p = std::get_if<bool>(&v);
      if (!p) throw InputError(where + s.key + " must be true or false");
      values_[s.key] = *p;
      return;
    }
    case KeySpec::Type::RealList:
    case KeySpec::Type::IntList:
    case KeySpec::Type::StringList:
      break;  // handled above
  }
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
void walk_table(const toml::table& tbl, const std::string& prefix,
                const std::function<void(const std::string&, const toml::node&)>& leaf) {
  for (const auto& [k, node] : tbl) {
    std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (auto sub = node.as_table()) walk_table(*sub, key, leaf);
    else leaf(key, node);
  }
}
}  // namespace

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
  walk_table(tbl, "", [&](const std::string& key, const toml::node& node) {
    const KeySpec& s = spec(key);
    ConfigValue v;
    if (auto x = toml_scalar(node)) {
      v = std::visit([](const auto& y) { return ConfigValue(y); }, *x);
    } else if (auto a = node.as_array(); a && is_list(s.type)) {
      ConfigList elements;
      for (std::size_t i = 0; i < a->size(); ++i) {
        auto e = toml_scalar(*a->get(i));
        if (!e)
          throw InputError(origin + ": " + key + " element " + std::to_string(i + 1) + " of " +
                           std::to_string(a->size()) + " is an array or table: allowed " + allowed_range(s));
        elements.push_back(*e);
      }
      v = elements;
    } else {
      throw InputError(origin + ": " + key + " has an unsupported TOML type: allowed " + allowed_range(s));
    }
    assign_checked(s, v, origin);
  });
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
      if (auto str = std::get_if<std::string>(&v)) os << '"' << *str << '"';
      else if (std::holds_alternative<ConfigList>(v)) os << '"' << value_text(v) << '"';
      else if (auto d = std::get_if<double>(&v)) {
        std::string t = fmt_sig(*d, 12);
        if (t.find_first_of(".eEn") == std::string::npos) t += ".0";
        os << t;
      } else os << value_text(v);
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
    if (auto str = std::get_if<std::string>(&v)) os << '"' << *str << '"';
    else if (std::holds_alternative<ConfigList>(v)) os << '"' << value_text(v) << '"';
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

std::vector<KeySpec> common_keys() {
  const double big = 1000.0;  // mm: a sanity bound on every length
  return {
      real_key("magnet.radius_mm", 2.0, 0, big, "mm", "magnet radius R", true),
      real_key("magnet.height_mm", 4.0, 0, big, "mm", "magnet height L (axis z, centred at 0)", true),
      real_key("magnet.br_T", 1.2, 0, 10, "T", "remanence Br = mu0*M0", true),
      real_key("magnet.mu_r", 1.05, 1, 1e6, "", "recoil permeability of the magnet (FEM only)"),
      real_key("magnet.magnetization_deg", 0.0, -360, 360, "deg",
               "direction of M in the xy plane of the magnet frame"),
      real_key("magnet.magnetization_elevation_deg", 0.0, -90, 90, "deg",
               "elevation of M out of the xy plane: M = M0 (cos el cos az, cos el sin az, sin el)"),
      real_key("sensor.plane_height_mm", 2.55, 0, big, "mm", "sensing plane height h above the top face",
               true),
      real_key("sensor.r0_mm", 2.4, 0, big, "mm", "nominal probe radius r0", true),
      string_key("sensor.array", "two", {}, "probe array: two, diff4 or ring:N (N >= 3)"),
      int_key("sensor.steps", 3600, 16, 10000000, "samples M of theta over one turn"),
      real_key("sensor.offset_cos_mT", 0.0, -1000, 1000, "mT", "offset added to the cos channel (signal chain)"),
      real_key("sensor.offset_sin_mT", 0.0, -1000, 1000, "mT", "offset added to the sin channel (signal chain)"),
      real_key("sensor.gain_mismatch", 0.0, -1, 10, "",
               "gain mismatch g: sin channel scaled by 1 + g (signal chain)", true),
      real_key("sensor.phase_error_deg", 0.0, -90, 90, "deg",
               "phase error delta of the sin channel: u_s' = (1+g)(u_s cos delta + u_c sin delta) + os", true, true),
      real_key("mount.sx_mm", 0.0, -big, big, "mm", "static eccentricity x (sensor off axis)"),
      real_key("mount.sy_mm", 0.0, -big, big, "mm", "static eccentricity y"),
      real_key("mount.dx_mm", 0.0, -big, big, "mm", "dynamic eccentricity x (magnet off axis)"),
      real_key("mount.dy_mm", 0.0, -big, big, "mm", "dynamic eccentricity y"),
      real_key("mount.dz_mm", 0.0, -big, big, "mm", "air-gap offset (+ = farther from the magnet)"),
      real_key("mount.tilt_x_deg", 0.0, -45, 45, "deg", "sensor tilt a about x (first; Rs = Ry(b) Rx(a))"),
      real_key("mount.tilt_y_deg", 0.0, -45, 45, "deg", "sensor tilt b about y (second, fixed axes)"),
      real_key("mount.magnet_tilt_deg", 0.0, -45, 45, "deg",
               "magnet tilt g on the shaft, about the centre of its bottom face"),
      real_key("mount.magnet_tilt_azimuth_deg", 0.0, -360, 360, "deg",
               "azimuth psi (rotor frame) towards which the tilted magnet's top leans"),
  };
}

}  // namespace magenc
