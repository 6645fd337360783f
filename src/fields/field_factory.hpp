// Field sources by name, as error_spectrum's --field takes them:
//   linear          the study's linear model Bz = k*x
//   analytic        exact field of the configured magnet ([magnet] keys)
//   grid:FILE.vti   (issue: FEM-driven studies) samples a solve_field grid
//   fem:DIR         (issue: FEM-driven studies) evaluates the FE solution in DIR
//   table:FILE      a text table of B on a regular grid from another tool (field_table.hpp)
// Unknown names throw an InputError listing the allowed values.
#pragma once
#include <functional>
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

// Schemes "NAME:ARG" served by libraries that link magenc (src/ cannot depend
// on them): field_solver's register_fem_field_scheme() installs "fem", and
// executables that link magenc_fem call it once before make_field_source.
// maker(arg, cfg, opts) gets the text after "NAME:". Thread-safe; a second
// registration of a name replaces the first.
using FieldSchemeMaker =
    std::function<FieldSourcePtr(const std::string& arg, const Config& cfg, const FieldOptions& opts)>;
void register_field_scheme(const std::string& scheme, FieldSchemeMaker maker);

}  // namespace magenc
