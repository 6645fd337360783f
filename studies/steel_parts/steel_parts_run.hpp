// The study steel_parts as one library call: the configured magnet alone, in a
// steel cup (its bore on the magnet's curved face, its base under the bottom
// face), in a brass cup of the same shape, on a steel shaft (touching the
// bottom face), above a steel end shield (a disk with a bore, below the
// magnet); each steel part linear (steel_parts.linear_material) and nonlinear
// (steel_parts.bh_file, Newton). For every solve: the iterations, the largest
// |B| in the part, Bz along x on the sensing plane, and the angle-error spectra
// of the FE field for each array of study.arrays under the ideal mount and each
// of sx, sy, dx, dy alone at steel_parts.offset_mm, with the field window of the
// [sensor] keys. Results: studies/steel_parts/steel_parts_result.hpp; outputs:
// studies/steel_parts/steel_parts_report.hpp.
#pragma once
#include <filesystem>
#include <vector>

#include "studies/steel_parts/steel_parts_result.hpp"
#include "core/config.hpp"
#include "fields/grid.hpp"
#include "field_solver/mesh/geometry.hpp"

namespace magenc::fem {

// fem_keys() plus study.arrays and the steel_parts.* keys.
std::vector<KeySpec> steel_parts_keys();

// The study's parts for a magnet of radius R and height L (mm): "steel cup", "brass cup",
// "steel shaft", "end shield" with the material `material` (brass cup: "brass").
PartSpec steel_parts_part(const std::string& variant, const Config& cfg, const std::string& material);

// The grid of the files below: the vertical plane y = 0 through the magnet's axis, from 2.5 mm
// beyond the magnet and the part (radially and below) to 1.5 mm above the sensing plane, step 0.05 mm.
GridData steel_parts_slice_grid(const Config& cfg, const PartSpec& part, double plane_z_mm);

// Runs every solve (progress on stderr). steel_parts.bh_file is looked up as given, then in
// each of search_dirs. InputError, before any solve, when the configuration sets [[parts]]
// (the study places its own) or a file or material is bad. With a field_dir, the solve of the
// steel cup (the nonlinear one when steel_parts.nonlinear, else the linear one) also writes, for
// ParaView, field_dir/bodies.vtu (the magnet and the cup: field_outputs.hpp's write_bodies_vtu)
// and field_dir/slice_y0.vti (B on steel_parts_slice_grid); field_dir's last component is
// recorded as SteelPartsResult::field_files_dir.
SteelPartsResult run_steel_parts(const Config& cfg, const std::vector<std::filesystem::path>& search_dirs,
                                 const std::filesystem::path& field_dir = {});

}  // namespace magenc::fem
