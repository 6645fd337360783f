// Build without PETSc: only the Eigen backend; one process (linear_solver.hpp).
#include "core/errors.hpp"
#include "linear_solver.hpp"

namespace magenc::fem {

bool petsc_available() { return false; }

std::string resolve_linear_solver(const std::string& requested) {
  if (requested == "auto" || requested == "eigen-pcg") return "eigen-pcg";
  throw InputError("fem.solver = " + requested +
                   " is not available: this build has no PETSc (install libpetsc-real-dev and rebuild); allowed "
                   "auto, eigen-pcg");
}

LinearSolveResult petsc_solve(const SparseMatrix&, const Eigen::VectorXd&, const std::string& backend, double, int,
                              Eigen::VectorXd&) {
  throw InputError("fem.solver = " + backend + " is not available: this build has no PETSc");
}

int mpi_world_size() { return 1; }
std::vector<double> mpi_rank_peak_rss_mib() { return {}; }
MpiSession::MpiSession() = default;
MpiSession::~MpiSession() = default;
void MpiSession::serve() {}

}  // namespace magenc::fem
