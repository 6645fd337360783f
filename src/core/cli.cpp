#include "core/cli.hpp"

#include <iostream>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"

namespace magenc {

namespace {

const char* type_name(KeySpec::Type t) {
  switch (t) {
    case KeySpec::Type::Real: return "real";
    case KeySpec::Type::Int: return "integer";
    case KeySpec::Type::String: return "string";
    case KeySpec::Type::Bool: return "bool";
    case KeySpec::Type::RealList: return "real list";
    case KeySpec::Type::IntList: return "integer list";
    case KeySpec::Type::StringList: return "string list";
    case KeySpec::Type::TableList: return "table list";
    case KeySpec::Type::Settings: return "settings";
  }
  return "";
}

nlohmann::json key_json(const KeySpec& s) {
  nlohmann::json j;
  j["key"] = s.key;
  j["type"] = type_name(s.type);
  j["default"] = s.default_value;
  j["range"] = allowed_range(s);
  j["unit"] = s.unit;
  j["help"] = s.help;
  const bool numeric = s.type == KeySpec::Type::Real || s.type == KeySpec::Type::Int ||
                       s.type == KeySpec::Type::RealList || s.type == KeySpec::Type::IntList;
  if (numeric) {
    j["min"] = s.min;
    j["max"] = s.max;
    j["min_exclusive"] = s.min_exclusive;
    j["max_exclusive"] = s.max_exclusive;
  }
  if (!s.choices.empty()) j["choices"] = s.choices;
  if (!s.fields.empty()) {
    j["fields"] = nlohmann::json::array();
    for (const auto& f : s.fields) j["fields"].push_back(key_json(f));
  }
  if (s.required) j["required"] = true;
  return j;
}

}  // namespace

std::string keys_json(const std::vector<KeySpec>& schema) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& s : schema) j.push_back(key_json(s));
  return j.dump(1) + "\n";
}

void add_common_options(CLI::App& app, CommonOptions& opts, const std::vector<KeySpec>& schema) {
  app.add_option("--config", opts.config_file, "TOML configuration file (defaults are embedded)");
  app.add_option("--set", opts.sets, "override one configuration key: section.key=value (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--out", opts.out, "output path");
  app.footer(Config(schema).describe());
  app.add_flag_callback(
      "--keys-json",
      [schema]() {
        std::cout << keys_json(schema);
        throw CLI::Success();
      },
      "print the declared configuration keys as JSON and exit");
}

Config load_config(const std::vector<KeySpec>& schema, const CommonOptions& opts) {
  Config cfg(schema);
  if (!opts.config_file.empty()) cfg.load_toml_file(opts.config_file);
  for (const auto& s : opts.sets) cfg.set(s);
  return cfg;
}

void parse_cli(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    std::exit(app.exit(e));
  } catch (const CLI::CallForAllHelp& e) {
    std::exit(app.exit(e));
  } catch (const CLI::Success& e) {  // --keys-json, after printing
    std::exit(app.exit(e));
  } catch (const CLI::ParseError& e) {
    throw InputError(std::string("command line: ") + e.what());
  }
}

}  // namespace magenc
