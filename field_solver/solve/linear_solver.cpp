// fem.solver and fem.preconditioner values and the dispatch to a backend (linear_solver.hpp).
#include <algorithm>

#include "core/errors.hpp"
#include "field_solver/solve/linear_solver.hpp"

namespace magenc::fem {
namespace {

constexpr std::array<LinearSolverKind, 4> kSolvers{LinearSolverKind::Auto, LinearSolverKind::PetscGamg,
                                                   LinearSolverKind::PetscHypre, LinearSolverKind::EigenPcg};
constexpr std::array<Preconditioner, 2> kPreconditioners{Preconditioner::Jacobi, Preconditioner::IChol};

template <class Enum, std::size_t N>
std::vector<std::string> names_of(const std::array<Enum, N>& values) {
  std::vector<std::string> n;
  for (Enum v : values) n.push_back(to_string(v));
  return n;
}

template <class Enum, std::size_t N>
Enum from_name(const std::string& key, const std::string& name, const std::array<Enum, N>& values,
               const std::vector<std::string>& names) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string allowed;
    for (const auto& n : names) allowed += (allowed.empty() ? "" : ", ") + n;
    throw InputError(key + " = " + name + " is out of range: allowed " + allowed);
  }
  return values[static_cast<std::size_t>(it - names.begin())];
}

}  // namespace

std::string to_string(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::Auto: return "auto";
    case LinearSolverKind::PetscGamg: return "petsc-gamg";
    case LinearSolverKind::PetscHypre: return "petsc-hypre";
    case LinearSolverKind::EigenPcg: return "eigen-pcg";
  }
  return "?";
}

std::string to_string(Preconditioner pc) { return pc == Preconditioner::IChol ? "ichol" : "jacobi"; }

const std::vector<std::string>& linear_solver_names() {
  static const std::vector<std::string> n = names_of(kSolvers);
  return n;
}

const std::vector<std::string>& preconditioner_names() {
  static const std::vector<std::string> n = names_of(kPreconditioners);
  return n;
}

LinearSolverKind linear_solver_from_string(const std::string& name) {
  return from_name("fem.solver", name, kSolvers, linear_solver_names());
}

Preconditioner preconditioner_from_string(const std::string& name) {
  return from_name("fem.preconditioner", name, kPreconditioners, preconditioner_names());
}

LinearSolveResult linear_solve(const SparseMatrix& K, const Eigen::VectorXd& f, const LinearSolveSettings& settings,
                               Eigen::VectorXd& x) {
  switch (settings.backend) {
    case LinearSolverKind::EigenPcg: return eigen_pcg_solve(K, f, settings, x);
    case LinearSolverKind::PetscGamg:
    case LinearSolverKind::PetscHypre:
      return petsc_solve(K, f, settings.backend, settings.tolerance, settings.max_iterations, x);
    case LinearSolverKind::Auto: break;
  }
  throw ComputeError("linear_solve: fem.solver = auto was not resolved to a backend");
}

}  // namespace magenc::fem
