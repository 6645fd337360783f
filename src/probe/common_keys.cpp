#include "probe/common_keys.hpp"

#include <utility>

#include "fields/field_table.hpp"
#include "fields/magnet.hpp"
#include "probe/environment.hpp"
#include "probe/mounting.hpp"
#include "probe/sensor.hpp"
#include "probe/speed.hpp"

namespace magenc {

std::vector<KeySpec> common_keys() {
  std::vector<KeySpec> keys = Magnet::keys();
  for (const auto& group : {sensor_keys(), StrayField::keys(), Environment::keys(), Mount::keys(), speed_keys(), field_check_keys()})
    keys = merge_schemas(std::move(keys), group);  // throws if a group redeclares a key
  return keys;
}

}  // namespace magenc
