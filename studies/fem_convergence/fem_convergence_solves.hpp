// The study fem_convergence as one library call: the FEM's Bz on the sensing
// plane against the exact field (magnet mu_r forced to 1) for the zone edge
// lengths of convergence.h_zone_list and each order of convergence.orders;
// then at one mesh the faceting of the curved face and the truncation radius;
// then the total potential against the reduced one (permeable magnet) and the
// split one (permeable shaft). Results: studies/fem_convergence/fem_convergence_engine.hpp; outputs:
// studies/fem_convergence/fem_convergence_report.hpp.
#pragma once
#include <vector>

#include "studies/fem_convergence/fem_convergence_engine.hpp"
#include "core/config.hpp"

namespace magenc::fem {

// fem_keys() plus the convergence.* keys.
std::vector<KeySpec> fem_convergence_keys();

// Runs every solve of the study (progress lines on stderr). InputError, before any solve, for fewer
// than 2 zone edge lengths or a potential_mu_r / shaft_mu_r in (0, 1).
FemConvergenceResult run_fem_convergence(const Config& cfg);

}  // namespace magenc::fem
