// Results of the study steel_parts (the solves: studies/steel_parts/steel_parts_run.hpp; the
// outputs: studies/steel_parts/steel_parts_report.hpp): the default magnet alone, in a steel
// cup, in a brass cup, on a steel shaft, above a steel end shield; the steel
// parts linear (a constant mu_r) and nonlinear (a B-H curve); for each solve the
// angle-error spectra of the FE field under the ideal mount and each mounting
// offset alone, and the field the chip sees against its window.
#pragma once
#include <string>
#include <vector>

#include "probe/angle_error.hpp"
#include "probe/mounting.hpp"
#include "probe/sensor.hpp"

namespace magenc {

// One FE solve of the study.
struct SteelPartsSolve {
  std::string variant;      // "magnet alone", "steel cup", ...
  std::string model;        // "linear" or "nonlinear" (the part's material)
  std::string parts;        // the part as configured (shape, radii, z range), "" for none
  std::string material;     // the part's material as configured ("" for none)
  std::string potential;    // total, reduced or split
  long dofs = 0, elements = 0;
  int nonlinear_iterations = 0, newton_steps = 0;
  std::vector<double> nonlinear_residuals;  // |f - K(mu) psi| / |f| after each iteration
  long linear_iterations = 0;
  double t_solve_s = 0;     // mesh + assembly + solve (MagnetostaticSolver::run)
  double part_B_max_T = 0;  // largest |B| at a cell centroid of the part (0: no part)
  double part_mu_r_min = 0; // smallest relative permeability of a part cell (nonlinear: the most saturated)
  std::vector<double> profile_x_mm, profile_Bz_mT;  // Bz along the x axis on the sensing plane
};

// One mounting case of one solve and one probe array.
struct SteelPartsCase {
  std::string variant, model, array, mount_label;  // mount_label: "ideal", "sx", "sy", "dx", "dy"
  Mount mount;
  Spectrum spectrum;
  double field_min_mT = 0, field_max_mT = 0;  // the chip's field (angle_error.hpp)
  bool in_window = true;
};

struct SteelPartsResult {
  std::vector<SteelPartsSolve> solves;
  std::vector<SteelPartsCase> cases;
  std::vector<std::string> arrays;
  double offset_mm = 0;       // each offset alone at this value
  double r0_mm = 0, plane_z_mm = 0, magnet_radius_mm = 0, magnet_height_mm = 0, br_T = 0;
  FieldWindow window;
  std::string linear_material, bh_file;  // the steel parts' materials
  double linear_mu_r = 0;
  // The FE field files of one solve for ParaView (studies/steel_parts/steel_parts_run.hpp), in the folder
  // field_files_dir of the study's output ("" when none were written): bodies.vtu and slice_y0.vti.
  std::string field_files_dir, field_files_solve;  // the folder, the solve they show ("steel cup (nonlinear)")
  std::vector<std::string> field_files;             // file names in that folder
  double slice_step_mm = 0;                         // the node spacing of slice_y0.vti
  double t_field_files_s = 0;                       // time to evaluate and write them
};

}  // namespace magenc
