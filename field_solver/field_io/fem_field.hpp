// FieldSource backed by an FE solution: a solve_field output directory
// (DIR/mesh.vtu, P1 or P2) or a solution solved in this process; B evaluated
// directly from the FE solution, not from the grids.
#pragma once
#include <filesystem>
#include <memory>

#include "field_solver/fe/fe_solution.hpp"
#include "fields/field_source.hpp"

namespace magenc {

class FemField final : public FieldSource {
 public:
  // Loads DIR/mesh.vtu; InputError if missing or malformed.
  explicit FemField(const std::filesystem::path& dir);
  // Takes a solution solved in this process (e.g. MagnetostaticSolver::solution()).
  explicit FemField(fem::FeSolution solution);
  std::string name() const override { return "fem"; }
  // B (T) at p (mm, magnet frame); InputError outside the mesh.
  Vec3 B_T(const Vec3& p_mm) const override;
  // Batches (3xN points, mm): FieldEvaluator::B_T's chunked walks with warm starts, the same values as
  // point by point; InputError naming the first point outside the mesh.
  Eigen::Matrix3Xd B_T(const Eigen::Matrix3Xd& p_mm) const override;
  Eigen::VectorXd Bz_T(const Eigen::Matrix3Xd& p_mm) const override;
  using FieldSource::B_T;
  using FieldSource::Bz_T;
  int order() const { return evaluator_->solution().order; }
  const fem::FieldEvaluator& evaluator() const { return *evaluator_; }

 private:
  std::unique_ptr<fem::FieldEvaluator> evaluator_;
};

}  // namespace magenc
