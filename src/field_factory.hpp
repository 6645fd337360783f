// Field sources by name, as error_spectrum's --field takes them:
//   linear          the study's linear model Bz = k*x
//   analytic        exact field of the configured magnet ([magnet] keys)
//   grid:FILE.vti   (issue: FEM-driven studies) samples a solve_field grid
//   fem:DIR         (issue: FEM-driven studies) evaluates the FE solution in DIR
// Unknown names throw an InputError listing the allowed values.
#pragma once
#include <string>

#include "config.hpp"
#include "field_source.hpp"

namespace magenc {

FieldSourcePtr make_field_source(const std::string& spec, const Config& cfg);

}  // namespace magenc
