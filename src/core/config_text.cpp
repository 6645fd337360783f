// The configuration as text, in and out: TOML files and strings, --set values, to_toml, to_json, describe.
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

#include "core/config_detail.hpp"
#include "core/defaults.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/fp_trap.hpp"

namespace magenc {

using namespace config_detail;

void Config::set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos)
    throw InputError("--set '" + assignment + "': expected section.key=value");
  const std::string key = trim(assignment.substr(0, eq));
  const KeySpec& s = spec(key);
  assign_checked(s, parse_text(s, assignment.substr(eq + 1), "--set"), "--set");
}

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
    const KeySpec* s = find(key);
    return s && (s->type == KeySpec::Type::TableList || s->type == KeySpec::Type::Settings);
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

std::string Config::to_toml() const {
  // Group by section, in declaration order.
  std::vector<std::string> sections;
  for (const auto& s : *schema_) {
    const auto dot = s.key.rfind('.');
    const std::string sec = dot == std::string::npos ? "" : s.key.substr(0, dot);
    bool seen = false;
    for (const auto& x : sections) seen = seen || x == sec;
    if (!seen) sections.push_back(sec);
  }
  std::ostringstream os;
  for (const auto& sec : sections) {
    if (!sec.empty()) os << "[" << sec << "]\n";
    for (const auto& s : *schema_) {
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
  for (const auto& s : *schema_) {
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
  for (const auto& s : *schema_) {
    os << "  " << std::left << std::setw(30) << s.key << " default " << s.default_value;
    os << ", allowed " << allowed_range(s) << ". " << s.help << "\n";
  }
  return os.str();
}

}  // namespace magenc
