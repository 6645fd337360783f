#include "fem_field_scheme.hpp"

#include <memory>

#include "core/errors.hpp"
#include "fem_field.hpp"
#include "fields/field_factory.hpp"

namespace magenc {

void register_fem_field_scheme() {
  register_field_scheme("fem", [](const std::string& dir, const Config&, const FieldOptions&) -> FieldSourcePtr {
    if (dir.empty()) throw InputError("--field fem: needs a directory: fem:DIR (a solve_field output, e.g. output/field)");
    try {
      return std::make_shared<FemField>(dir);
    } catch (const InputError& e) {
      throw InputError("--field fem:" + dir + ": " + e.what());
    }
  });
}

}  // namespace magenc
