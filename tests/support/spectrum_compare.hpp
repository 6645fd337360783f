// Test helper: a field source against the exact field in the probe pipeline, one eccentricity at a time.
#pragma once
#include <string>

#include "fields/field_source.hpp"
#include "probe/angle_error.hpp"

namespace magenc::test {

// For each eccentricity sx, sy, dx, dy of `offset_mm` alone on `setup`, the error spectra of `exact` and
// of `field`: calls check(name, spectrum of exact, spectrum of field) with name "sx", "sy", "dx" or "dy".
// The checks (tolerances, which coefficients) stay in the test that calls it.
template <class Check>
void compare_spectra_per_eccentricity(const FieldSource& exact, const FieldSource& field, const ProbeSetup& setup,
                                      double offset_mm, Check check) {
  for (const std::string off : {"sx", "sy", "dx", "dy"}) {
    Mount m;
    (off == "sx" ? m.sx_mm : off == "sy" ? m.sy_mm : off == "dx" ? m.dx_mm : m.dy_mm) = offset_mm;
    check(off, error_spectrum(exact, setup, m), error_spectrum(field, setup, m));
  }
}

}  // namespace magenc::test
