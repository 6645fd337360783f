// The outputs of a solve (docs/interfaces.md): plane.vti, box.vti, solve.json and,
// when asked (output.mesh_vtu), mesh.vtu.
#pragma once
#include <filesystem>
#include <string>

#include "fem_config.hpp"
#include "magnetostatic_solver.hpp"

namespace magenc::fem {

// Peak resident set size of this process so far (MiB, getrusage).
double peak_rss_mib();

// Evaluates the grids and writes plane.vti, box.vti, solve.json and, with
// output.mesh_vtu, mesh.vtu into dir (an AtomicDir's
// temporary directory). config_json: the configuration in use (echoed).
void write_field_outputs(const std::filesystem::path& dir, const FemSettings& settings, const MagnetostaticSolver& solver,
                         const std::string& config_json);

}  // namespace magenc::fem
