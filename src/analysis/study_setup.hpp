// The set-up a study's summary states (the magnet, the sensing plane, r0, samples per turn, the channel
// offsets), read once from the configuration, so that reports format typed values and read no keys.
#pragma once
#include <string>

#include "core/config.hpp"

namespace magenc {

struct StudySetup {
  double magnet_radius_mm = 0;      // magnet.radius_mm (R)
  double magnet_height_mm = 0;      // magnet.height_mm (L)
  double magnet_br_T = 0;           // magnet.br_T as configured (before any material's temperature model)
  double magnet_mu_r = 1;           // magnet.mu_r (FEM only)
  std::string magnet_material;      // magnet.material, "none" (or "" where the schema has no such key)
  double plane_height_mm = 0;       // sensor.plane_height_mm: above the magnet's top face
  double r0_mm = 0;                 // sensor.r0_mm
  long steps = 0;                   // sensor.steps
  double offset_cos_mT = 0, offset_sin_mT = 0;  // sensor.offset_cos_mT, sensor.offset_sin_mT
  static StudySetup from_config(const Config& cfg);
};

}  // namespace magenc
