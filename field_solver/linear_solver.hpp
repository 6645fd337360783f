// Linear-solver backends of the FEM (fem.solver) and the MPI session that
// lets `mpirun -n N solve_field` solve across ranks.
//
//   eigen-pcg   Eigen's CG with Jacobi or incomplete-Cholesky preconditioner
//               (fem.preconditioner); shared memory (OpenMP), no extra deps.
//   petsc-gamg  PETSc CG preconditioned with GAMG (smoothed aggregation
//               algebraic multigrid); iteration count ~independent of h.
//   petsc-hypre PETSc CG preconditioned with hypre BoomerAMG (HMIS, ext+i,
//               one aggressive level; PETSC_OPTIONS overrides).
//   auto        petsc-hypre when this build has PETSc, else eigen-pcg.
//
// What is distributed (PETSc backends under mpirun): rank 0 meshes, assembles
// and post-processes; for each linear solve it sends each rank a contiguous
// block of matrix rows (CSR) and of the load, all ranks build one MPIAIJ
// matrix, set up the multigrid and run CG together, and the solution is
// gathered back on rank 0. Mesh, assembly, recovery and output are not
// distributed.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "assembly.hpp"

namespace magenc::fem {

// Resolved backend name for a fem.solver value ("auto" -> what this build has).
// Throws InputError naming fem.solver when the backend is not compiled in.
std::string resolve_linear_solver(const std::string& requested);
bool petsc_available();

struct LinearSolveResult {
  long iterations = 0;
  double residual = 0;  // |f - K x| / |f| (true residual, 2-norm)
};

// Solves K x = f with a PETSc backend ("petsc-gamg" or "petsc-hypre") to the
// relative residual tol (unpreconditioned 2-norm); across all MPI ranks when
// the process runs under mpirun (rank 0 only calls this; the other ranks are
// in MpiSession::serve()). Throws ComputeError when CG does not converge.
LinearSolveResult petsc_solve(const SparseMatrix& K, const Eigen::VectorXd& f, const std::string& backend,
                              double tol, int max_iterations, Eigen::VectorXd& x);

// One per process of an executable that may run under mpirun. Initializes
// MPI/PETSc (no-op without PETSc). rank() > 0: call serve(), which takes part
// in every petsc_solve of rank 0 until rank 0's session ends (destructor).
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  void serve();

 private:
  int rank_ = 0, size_ = 1;
};

// Number of MPI ranks of this process's world (1 without PETSc/MPI).
int mpi_world_size();

// Peak RSS (MiB) of every rank, gathered on rank 0 at the end of the last
// petsc_solve (empty before one, and without PETSc).
std::vector<double> mpi_rank_peak_rss_mib();

}  // namespace magenc::fem
