// The probe setup of the tests: one array on the study magnet's sensing plane.
#pragma once
#include <string>

#include "probe/angle_error.hpp"

namespace magenc::test {

// `array` (ProbeArray::parse) at radius r0_mm on the sensing plane z_s = 4.55 mm (L/2 + h of the study
// magnet), `steps` theta samples per turn; the rest (signal chain, magnet height) at ProbeSetup's defaults.
inline ProbeSetup probe_setup(const std::string& array, int steps = 3600, double r0_mm = 2.4) {
  ProbeSetup s;
  s.array = ProbeArray::parse(array);
  s.r0_mm = r0_mm;
  s.plane_z_mm = 4.55;
  s.steps = steps;
  return s;
}

}  // namespace magenc::test
