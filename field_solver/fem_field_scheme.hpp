// Registers the "fem:DIR" field scheme with src/fields/field_factory (which cannot
// depend on field_solver/): after register_fem_field_scheme(),
// make_field_source("fem:DIR", ...) returns a FemField evaluating the FE
// solution in DIR/mesh.vtu directly. Call it once at the start of any
// executable that links magenc_fem and takes --field (error_spectrum, studies).
#pragma once

namespace magenc {

void register_fem_field_scheme();

}  // namespace magenc
