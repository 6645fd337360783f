// Field sources by name, as error_spectrum's --field takes them:
//   linear          the study's linear model Bz = k*x
//   analytic        exact field of the configured magnet ([magnet] keys)
//   grid:FILE.vti   samples a solve_field grid
//   table:FILE      a text table of B on a regular grid from another tool (field_table.hpp)
// fem:DIR (the FE solution in DIR) is field_solver's: executables that link it
// call open_field_source (field_solver/field_io/solved_field.hpp), which adds fem:DIR
// to these. Unknown names throw an InputError listing the allowed values.
#pragma once
#include <string>

#include "core/config.hpp"
#include "fields/field_source.hpp"
#include "fields/grid_field.hpp"

namespace magenc {

FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg);

// Options some sources take (error_spectrum's --interp for grid: sources).
struct FieldOptions {
  Interp interp = Interp::Cubic;  // grid: and table: interpolation (nearest, linear, cubic)
};
FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg, const FieldOptions& opts);

}  // namespace magenc
