#include "core/config.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>
#include <toml++/toml.h>

#include "core/errors.hpp"
#include "core/fp_trap.hpp"

namespace magenc {

KeySpec real_key(std::string key, double def, double min, double max, std::string unit,
                 std::string help, bool min_exclusive, bool max_exclusive) {
  KeySpec s;
  s.key = std::move(key);
  s.type = KeySpec::Type::Real;
  std::ostringstream os;
  os << std::setprecision(15) << def;
  s.default_value = os.str();
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

namespace {

std::string fmt_num(double v) {
  std::ostringstream os;
  os << std::setprecision(12) << v;
  return os.str();
}

std::string value_text(const ConfigValue& v) {
  if (auto d = std::get_if<double>(&v)) return fmt_num(*d);
  if (auto i = std::get_if<long>(&v)) return std::to_string(*i);
  if (auto s = std::get_if<std::string>(&v)) return *s;
  return std::get<bool>(v) ? "true" : "false";
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// Parse textual value per spec type (for defaults and --set).
ConfigValue parse_text(const KeySpec& s, const std::string& raw, const std::string& origin) {
  std::string t = trim(raw);
  auto fail = [&]() -> ConfigValue {
    throw InputError(origin + ": " + s.key + " = '" + raw + "' is not a valid value: allowed " +
                     allowed_range(s));
  };
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
  }
  return fail();
}

}  // namespace

std::string allowed_range(const KeySpec& s) {
  switch (s.type) {
    case KeySpec::Type::Real:
    case KeySpec::Type::Int: {
      std::string r = std::string(s.min_exclusive ? "(" : "[") + fmt_num(s.min) + ", " +
                      fmt_num(s.max) + (s.max_exclusive ? ")" : "]");
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
      if (!ok) range_fail(fmt_num(d));
      values_[s.key] = d;
      return;
    }
    case KeySpec::Type::Int: {
      long i;
      if (auto q = std::get_if<long>(&v)) i = *q;
      else if (auto p = std::get_if<double>(&v); p && std::isfinite(*p) && *p == std::floor(*p))
        i = static_cast<long>(*p);
      else throw InputError(where + s.key + " must be an integer: allowed " + allowed_range(s));
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

void Config::load_toml_string(const std::string& text, const std::string& origin) {
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
    if (auto d = node.as_floating_point()) v = d->get();
    else if (auto i = node.as_integer()) v = static_cast<long>(i->get());
    else if (auto str = node.as_string()) v = str->get();
    else if (auto b = node.as_boolean()) v = b->get();
    else throw InputError(origin + ": " + key + " has an unsupported TOML type: allowed " + allowed_range(s));
    assign_checked(s, v, origin);
  });
}

void Config::load_toml_file(const std::string& path) {
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
const std::string& Config::str(const std::string& key) const {
  const auto& v = values_.at(spec(key).key);
  if (auto s = std::get_if<std::string>(&v)) return *s;
  throw std::logic_error("config key is not a string: " + key);
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
      else if (auto d = std::get_if<double>(&v)) {
        std::string t = fmt_num(*d);
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
