// The keys every executable shares (docs/interfaces.md): [magnet], [sensor], [stray], [environment],
// [mount], [speed], [checks]. Each group is declared beside the type that reads it (Magnet::keys() in fields/magnet,
// sensor_keys() in probe/sensor, StrayField::keys() and Environment::keys() in probe/environment,
// Mount::keys() in probe/mounting, speed_keys() in probe/speed, field_check_keys() in fields/field_table); this is the first layer that sees them all.
#pragma once
#include <vector>

#include "core/config.hpp"

namespace magenc {

// Magnet, sensor, stray field, temperature, mount, speed and plausibility-check keys, in that order (the order of config.toml).
std::vector<KeySpec> common_keys();

}  // namespace magenc
