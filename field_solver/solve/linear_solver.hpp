// Linear-solver backends of the FEM (fem.solver) and the MPI session that
// lets `mpirun -n N solve_field` solve across ranks.
//
//   eigen-pcg   Eigen's CG with Jacobi or incomplete-Cholesky preconditioner
//               (fem.preconditioner); shared memory (OpenMP), no extra deps
//               (linear_solver_eigen.cpp).
//   petsc-gamg  PETSc CG preconditioned with GAMG (smoothed aggregation
//               algebraic multigrid); iteration count ~independent of h.
//   petsc-hypre PETSc CG preconditioned with hypre BoomerAMG (HMIS, ext+i,
//               one aggressive level; PETSC_OPTIONS overrides).
//   auto        petsc-hypre when this build has PETSc, else eigen-pcg.
// (linear_solver_petsc.cpp; linear_solver_none.cpp in builds without PETSc.)
// The option values are enums, parsed once from the keys' strings (fem_config.cpp).
//
// What is distributed (PETSc backends under mpirun): rank 0 meshes, assembles
// and post-processes; for each linear solve it sends each rank a contiguous
// block of matrix rows (CSR) and of the load, all ranks build one MPIAIJ
// matrix, set up the multigrid and run CG together, and the solution is
// gathered back on rank 0. Mesh, assembly, recovery and output are not
// distributed.
#pragma once
#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "field_solver/fe/assembly.hpp"

namespace magenc::fem {

// fem.solver.
enum class LinearSolverKind { Auto, PetscGamg, PetscHypre, EigenPcg };
// fem.preconditioner (eigen-pcg only).
enum class Preconditioner { Jacobi, IChol };

// The values as the keys spell them ("auto", "petsc-gamg", "petsc-hypre", "eigen-pcg"; "jacobi", "ichol"),
// in declaration order, and back; an unknown name is an InputError naming the key and the allowed values.
std::string to_string(LinearSolverKind kind);
std::string to_string(Preconditioner pc);
const std::vector<std::string>& linear_solver_names();
const std::vector<std::string>& preconditioner_names();
LinearSolverKind linear_solver_from_string(const std::string& name);
Preconditioner preconditioner_from_string(const std::string& name);

// The backend a fem.solver value means in this build (Auto -> PetscHypre with PETSc, else EigenPcg).
// Throws InputError naming fem.solver when the backend is not compiled in.
LinearSolverKind resolve_linear_solver(LinearSolverKind requested);
bool petsc_available();

// How to solve one system: a resolved backend and the CG stopping rule.
struct LinearSolveSettings {
  LinearSolverKind backend = LinearSolverKind::EigenPcg;
  Preconditioner preconditioner = Preconditioner::Jacobi;  // eigen-pcg
  double tolerance = 1e-10;    // CG stop: |f - K x| / |f| below this
  int max_iterations = 20000;  // CG iteration cap (ComputeError when reached)
  int progress_every = 500;    // eigen-pcg: stderr progress line every N CG iterations (0: quiet)
};

struct LinearSolveResult {
  long iterations = 0;
  double residual = 0;  // |f - K x| / |f| (true residual for PETSc, Eigen's estimate for eigen-pcg)
};

// Solves K x = f (K symmetric positive definite) with settings.backend (not Auto).
LinearSolveResult linear_solve(const SparseMatrix& K, const Eigen::VectorXd& f, const LinearSolveSettings& settings,
                               Eigen::VectorXd& x);

// Relative residuals |r_k| / |f| of a CG solve, kept short: iterations 0, 1, 2, 4, 8, ... and the
// last 4. text() is the history part of the one-line error of a failed solve.
struct CgResidualHistory {
  std::vector<std::pair<long, double>> sampled;
  std::array<std::pair<long, double>, 4> last{{{-1, 0}, {-1, 0}, {-1, 0}, {-1, 0}}};
  double min_rel = std::numeric_limits<double>::infinity();
  long count = 0;
  void record(long iteration, double rel);
  std::string text() const;
};

// The eigen-pcg backend (linear_solver_eigen.cpp): Eigen's CG with settings.preconditioner. ComputeError
// with the residual history when the iteration cap is reached, when the residual stops being finite
// (breakdown) or grows 1e8-fold (divergence: K indefinite).
LinearSolveResult eigen_pcg_solve(const SparseMatrix& K, const Eigen::VectorXd& f, const LinearSolveSettings& settings,
                                  Eigen::VectorXd& x);

// Solves K x = f with a PETSc backend (PetscGamg or PetscHypre) to the
// relative residual tol (unpreconditioned 2-norm); across all MPI ranks when
// the process runs under mpirun (rank 0 only calls this; the other ranks are
// in MpiSession::serve()). Throws ComputeError when CG does not converge.
// nonsymmetric: K need not be symmetric (the Newton Jacobian of a B-H solve):
// BiCGSTAB instead of CG with the same multigrid, same stopping rule.
LinearSolveResult petsc_solve(const SparseMatrix& K, const Eigen::VectorXd& f, LinearSolverKind backend, double tol,
                              int max_iterations, Eigen::VectorXd& x, bool nonsymmetric = false);

// One per process of an executable that may run under mpirun. Under an MPI
// launcher it initializes MPI/PETSc; without one (one rank) PETSc starts with
// the first petsc_solve (no-op without PETSc). rank() > 0: call serve(), which takes part
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
