#include "analysis/study_setup.hpp"

namespace magenc {

StudySetup StudySetup::from_config(const Config& cfg) {
  StudySetup s;
  s.magnet_radius_mm = cfg.real("magnet.radius_mm");
  s.magnet_height_mm = cfg.real("magnet.height_mm");
  s.magnet_br_T = cfg.real("magnet.br_T");
  s.magnet_mu_r = cfg.real("magnet.mu_r");
  if (cfg.has("magnet.material")) s.magnet_material = cfg.str("magnet.material");
  s.plane_height_mm = cfg.real("sensor.plane_height_mm");
  s.r0_mm = cfg.real("sensor.r0_mm");
  s.steps = cfg.integer("sensor.steps");
  s.offset_cos_mT = cfg.real("sensor.offset_cos_mT");
  s.offset_sin_mT = cfg.real("sensor.offset_sin_mT");
  return s;
}

}  // namespace magenc
