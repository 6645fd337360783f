#include "field_factory.hpp"

#include <memory>

#include "analytic_field.hpp"
#include "errors.hpp"

namespace magenc {

FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg) {
  if (spec == "linear") return std::make_shared<LinearField>();
  if (spec == "analytic") return std::make_shared<AnalyticField>(Magnet::from_config(cfg));
  if (spec.rfind("grid:", 0) == 0 || spec.rfind("fem:", 0) == 0)
    throw InputError("--field " + spec +
                     ": grid:/fem: fields need a solved field (solve_field), not available in this build yet: "
                     "allowed linear, analytic");
  throw InputError("--field '" + spec + "' is not a field source: allowed linear, analytic, grid:FILE.vti, fem:DIR");
}

}  // namespace magenc
