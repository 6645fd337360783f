#include "core/cli.hpp"

#include "core/errors.hpp"

namespace magenc {

void add_common_options(CLI::App& app, CommonOptions& opts, const std::vector<KeySpec>& schema) {
  app.add_option("--config", opts.config_file, "TOML configuration file (defaults are embedded)");
  app.add_option("--set", opts.sets, "override one configuration key: section.key=value (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--out", opts.out, "output path");
  app.footer(Config(schema).describe());
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
  } catch (const CLI::ParseError& e) {
    throw InputError(std::string("command line: ") + e.what());
  }
}

}  // namespace magenc
