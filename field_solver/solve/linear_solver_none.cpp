// Build without PETSc: only the Eigen backend; one process (linear_solver.hpp).
#include "core/errors.hpp"
#include "field_solver/solve/linear_solver.hpp"

namespace magenc::fem {

bool petsc_available() { return false; }

LinearSolverKind resolve_linear_solver(LinearSolverKind requested) {
  if (requested == LinearSolverKind::Auto || requested == LinearSolverKind::EigenPcg) return LinearSolverKind::EigenPcg;
  throw InputError("fem.solver = " + to_string(requested) +
                   " is not available: this build has no PETSc (install libpetsc-real-dev and rebuild); allowed "
                   "auto, eigen-pcg");
}

LinearSolveResult petsc_solve(const SparseMatrix&, const Eigen::VectorXd&, LinearSolverKind backend, double, int,
                              Eigen::VectorXd&, bool) {
  throw InputError("fem.solver = " + to_string(backend) + " is not available: this build has no PETSc");
}

int mpi_world_size() { return 1; }
std::vector<double> mpi_rank_peak_rss_mib() { return {}; }
MpiSession::MpiSession() = default;
MpiSession::~MpiSession() = default;
void MpiSession::serve() {}

}  // namespace magenc::fem
