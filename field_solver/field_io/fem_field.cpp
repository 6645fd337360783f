#include "field_solver/field_io/fem_field.hpp"

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

}  // namespace magenc
