#include "report/setup_text.hpp"

#include "core/format.hpp"

namespace magenc {

std::string magnet_text(const StudySetup& s) {
  return "R = " + fmt(s.magnet_radius_mm, 2) + " mm, L = " + fmt(s.magnet_height_mm, 2) + " mm, Br = " +
         fmt(s.magnet_br_T, 2) + " T";
}

}  // namespace magenc
