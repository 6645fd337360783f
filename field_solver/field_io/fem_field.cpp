#include "field_solver/field_io/fem_field.hpp"

#include <string>
#include <utility>

#include "core/errors.hpp"
#include "field_solver/field_io/vtk_io.hpp"

namespace magenc {

FemField::FemField(const std::filesystem::path& dir)
    : evaluator_(std::make_unique<fem::FieldEvaluator>(fem::read_solution_vtu(dir / "mesh.vtu"))) {}

FemField::FemField(fem::FeSolution solution)
    : evaluator_(std::make_unique<fem::FieldEvaluator>(std::move(solution))) {}

Vec3 FemField::B_T(const Vec3& p) const {
  auto b = evaluator_->B_T(p);
  if (!b)
    throw InputError("fem field: point (" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) +
                     ") mm lies outside the FE mesh");
  return *b;
}

Eigen::Matrix3Xd FemField::B_T(const Eigen::Matrix3Xd& p) const {
  try {
    return evaluator_->B_T(p);
  } catch (const InputError& e) {
    throw InputError(std::string("fem field: ") + e.what());
  }
}

Eigen::VectorXd FemField::Bz_T(const Eigen::Matrix3Xd& p) const { return B_T(p).row(2).transpose(); }

}  // namespace magenc
