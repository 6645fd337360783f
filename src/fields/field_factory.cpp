#include "fields/field_factory.hpp"

#include <map>
#include <memory>
#include <mutex>

#include "fields/analytic_field.hpp"
#include "fields/field_table.hpp"
#include "core/errors.hpp"

namespace magenc {

namespace {
// Registry of schemes served by other libraries ("fem").
struct SchemeRegistry {
  std::mutex mutex;
  std::map<std::string, FieldSchemeMaker> makers;
};
SchemeRegistry& scheme_registry() {
  static SchemeRegistry r;
  return r;
}
}  // namespace

void register_field_scheme(const std::string& scheme, FieldSchemeMaker maker) {
  auto& r = scheme_registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.makers[scheme] = std::move(maker);
}

FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg) {
  return make_field_source(spec, cfg, FieldOptions{});
}

FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg, const FieldOptions& opts) {
  if (spec == "linear") return std::make_shared<LinearField>();
  if (spec == "analytic") return std::make_shared<AnalyticField>(Magnet::from_config(cfg));
  if (spec.rfind("grid:", 0) == 0) {
    const std::string file = spec.substr(5);
    if (file.empty()) throw InputError("--field grid: needs a file: grid:FILE.vti (plane.vti or box.vti of solve_field)");
    try {
      return GridField::from_file(file, opts.interp);
    } catch (const InputError& e) {
      throw InputError("--field " + spec + ": " + e.what());
    }
  }
  if (spec.rfind("table:", 0) == 0) {
    const std::string file = spec.substr(6);
    if (file.empty())
      throw InputError("--field table: needs a file: table:FILE (a text table of B on a regular grid, interfaces.md)");
    try {
      return table_field_from_file(file, cfg, opts.interp);
    } catch (const InputError& e) {
      throw InputError("--field " + spec + ": " + e.what());
    }
  }
  if (const auto colon = spec.find(':'); colon != std::string::npos) {
    const std::string scheme = spec.substr(0, colon);
    FieldSchemeMaker maker;
    {
      auto& r = scheme_registry();
      std::lock_guard<std::mutex> lock(r.mutex);
      if (auto it = r.makers.find(scheme); it != r.makers.end()) maker = it->second;
    }
    if (maker) return maker(spec.substr(colon + 1), cfg, opts);
    if (scheme == "fem")
      throw InputError("--field " + spec + ": fem: sources come from the field_solver library, which this "
                       "executable does not register: allowed linear, analytic, grid:FILE.vti, table:FILE");
  }
  throw InputError("--field '" + spec + "' is not a field source: allowed linear, analytic, grid:FILE.vti, table:FILE, fem:DIR");
}

}  // namespace magenc
