// The four outputs of a solve (interfaces.md): mesh.vtu, plane.vti, box.vti, solve.json.
#pragma once
#include <filesystem>
#include <string>

#include "fem_config.hpp"
#include "magnetostatic_solver.hpp"

namespace magenc::fem {

// Peak resident set size of this process so far (MiB, getrusage).
double peak_rss_mib();

// Evaluates the grids and writes all four files into dir (an AtomicDir's
// temporary directory). config_json: the configuration in use (echoed).
void write_field_outputs(const std::filesystem::path& dir, const FemSettings& settings, const MagnetostaticSolver& solver,
                         const std::string& config_json);

}  // namespace magenc::fem
