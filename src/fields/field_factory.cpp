#include "fields/field_factory.hpp"

#include <memory>

#include "fields/analytic_field.hpp"
#include "fields/field_table.hpp"
#include "fields/multipole_field.hpp"
#include "core/errors.hpp"

namespace magenc {

FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg) {
  return make_field_source(spec, cfg, FieldOptions{});
}

FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg, const FieldOptions& opts) {
  if (spec == "linear") return std::make_shared<LinearField>();
  if (spec == "analytic") {
    const Magnet magnet = Magnet::from_config(cfg);
    if (!magnet.is_uniform()) return std::make_shared<MultipoleField>(magnet);
    return std::make_shared<AnalyticField>(magnet);
  }
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
      throw InputError("--field table: needs a file: table:FILE (a text table of B on a regular grid, docs/interfaces.md)");
    try {
      return table_field_from_file(file, cfg, opts.interp);
    } catch (const InputError& e) {
      throw InputError("--field " + spec + ": " + e.what());
    }
  }
  if (spec.rfind("fem:", 0) == 0)
    throw InputError("--field " + spec + ": fem: sources come from the field_solver library, which this "
                     "executable does not link: allowed linear, analytic, grid:FILE.vti, table:FILE");
  throw InputError("--field '" + spec + "' is not a field source: allowed linear, analytic, grid:FILE.vti, table:FILE, fem:DIR");
}

}  // namespace magenc
