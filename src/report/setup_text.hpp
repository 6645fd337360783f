// How summaries name the magnet: one home for the line every study prints ("R = 3.00 mm, L = 2.50 mm,
// Br = 1.20 T"), from the typed set-up (analysis/study_setup.hpp).
#pragma once
#include <string>

#include "analysis/study_setup.hpp"

namespace magenc {

// "R = <R> mm, L = <L> mm, Br = <Br> T", two decimals each.
std::string magnet_text(const StudySetup& s);

}  // namespace magenc
