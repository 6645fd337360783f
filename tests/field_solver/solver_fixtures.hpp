// Shared setup of the FEM tests that solve meshes/coarse.toml through the configuration, as
// solve_field does (test_reduced_potential.cpp, test_split_potential.cpp, test_linear_solvers.cpp).
#pragma once
#include <unistd.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/cli.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "fields/grid.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"

namespace magenc::fem::test {

// The settings of meshes/coarse.toml with --set `first`, then `sets` (a later --set wins).
inline FemSettings coarse_settings(const std::vector<std::string>& sets, const std::string& first = "fem.order=2") {
  magenc::CommonOptions o;
  o.config_file = std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml";
  o.sets = sets;
  o.sets.insert(o.sets.begin(), first);
  return fem_settings_from_config(magenc::load_config(solve_field_schema(), o));
}

// Plane grid of the tests: |x|, |y| <= 3 mm at z_s, 0.25 mm.
inline magenc::GridData plane(const FemSettings& s) {
  return magenc::GridData::from_range({-3, -3, s.plane_z_mm}, {3, 3, s.plane_z_mm}, {0.25, 0.25, 1});
}

// v followed by more.
inline std::vector<std::string> with(std::vector<std::string> v, const std::vector<std::string>& more) {
  v.insert(v.end(), more.begin(), more.end());
  return v;
}

// The coarse mesh solved with `sets` and, unless empty, fem.potential = potential (set last).
inline std::unique_ptr<MagnetostaticSolver> solved(std::vector<std::string> sets, const std::string& potential = "") {
  if (!potential.empty()) sets.push_back("fem.potential=" + potential);
  const FemSettings s = coarse_settings(sets);
  auto solver = std::make_unique<MagnetostaticSolver>(s.domain, s.solver);
  solver->run();
  return solver;
}

// RMS and max of |B_a - B_b| on the grid, relative to the peak |B_b|.
inline std::pair<double, double> diff(const FieldEvaluator& a, const FieldEvaluator& b, const magenc::GridData& g) {
  const Eigen::Matrix3Xd P = g.points_mm();
  const Eigen::Matrix3Xd A = a.B_T(P), B = b.B_T(P);
  const double peak = B.colwise().norm().maxCoeff();
  const Eigen::VectorXd d = (A - B).colwise().norm();
  return {std::sqrt(d.squaredNorm() / static_cast<double>(d.size())) / peak, d.maxCoeff() / peak};
}

// Volume per region id of a mesh (mm^3).
inline std::map<int, double> region_volumes(const TetMesh& m) {
  std::map<int, double> v;
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) J.col(k) = m.nodes.col(m.tets(k + 1, t)) - m.nodes.col(m.tets(0, t));
    v[m.region[t]] += std::abs(J.determinant()) / 6.0;
  }
  return v;
}

// A B-H table file in the temporary directory (rows as given, full precision); the caller removes it.
inline std::string bh_file(const std::string& name, const std::vector<std::pair<double, double>>& rows) {
  const std::string path = (std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()) + ".csv")).string();
  std::ofstream out(path);
  out << std::setprecision(17) << "H_A_per_m,B_T\n";
  for (const auto& [H, B] : rows) out << H << "," << B << "\n";
  return path;
}

}  // namespace magenc::fem::test
