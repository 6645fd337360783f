// PETSc backends of fem.solver (linear_solver.hpp): CG + GAMG or hypre
// BoomerAMG, on one process or across the ranks of mpirun.
#include <mpi.h>
#include <sys/resource.h>
#include <petscksp.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "core/mpi_launch.hpp"
#include "core/third_party_leaks.hpp"
#include "field_solver/solve/linear_solver.hpp"


namespace magenc::fem {
namespace {

void check(PetscErrorCode ierr, const char* what) {
  if (ierr != 0) throw ComputeError(std::string("PETSc error in ") + what + " (code " + std::to_string(static_cast<int>(ierr)) + ")");
}

void finalize_petsc() {
  PetscBool fin = PETSC_FALSE;
  PetscFinalized(&fin);
  MAGENC_IGNORE_THIRD_PARTY_LEAKS;
  if (!fin) PetscFinalize();
}

// MPI + PETSc once per process; finalized at exit.
void ensure_petsc() {
  PetscBool init = PETSC_FALSE;
  PetscInitialized(&init);
  if (init) return;
  // PETSc's own SIGSEGV/SIGFPE handlers would mask the Debug builds' FP trap
  // and run_main's reporting; options still come from PETSC_OPTIONS.
  PetscOptionsSetValue(nullptr, "-no_signal_handler", "true");
  {
    MAGENC_IGNORE_THIRD_PARTY_LEAKS;
    check(PetscInitializeNoArguments(), "PetscInitialize");
  }
  std::atexit(finalize_petsc);
}

// BoomerAMG settings for 3-D P1/P2 Laplace-type problems, applied unless
// PETSC_OPTIONS sets the same option: strong threshold 0.5 (hypre's advice for
// 3-D; PETSc's 0.25 is its 2-D value), HMIS coarsening, ext+i interpolation
// truncated to 4 entries per row, one level of aggressive coarsening. On the
// default quadrant (619k P2 unknowns, one thread, CPU s): setup 1.7 vs GAMG's
// 3.1, setup + CG to 1e-6 5.3 (18 iterations) vs 5.9 (30) (docs/benchmarks.md).
void set_boomeramg_defaults() {
  static const char* const kDefaults[][2] = {
      {"-pc_hypre_boomeramg_strong_threshold", "0.5"}, {"-pc_hypre_boomeramg_coarsen_type", "HMIS"},
      {"-pc_hypre_boomeramg_interp_type", "ext+i"},    {"-pc_hypre_boomeramg_P_max", "4"},
      {"-pc_hypre_boomeramg_agg_nl", "1"}};
  for (const auto& kv : kDefaults) {
    PetscBool set = PETSC_FALSE;
    check(PetscOptionsHasName(nullptr, nullptr, kv[0], &set), "PetscOptionsHasName");
    if (!set) check(PetscOptionsSetValue(nullptr, kv[0], kv[1]), "PetscOptionsSetValue");
  }
}

// Command broadcast by rank 0 to the ranks waiting in serve().
enum Command : int { kQuit = 0, kSolve = 1 };
struct Header {
  double cmd = kQuit, n = 0, backend = 0, max_iterations = 0, tol = 0;
};
// backend: 0 GAMG, 1 BoomerAMG; + 2 for a nonsymmetric matrix (BiCGSTAB instead of CG).
int backend_code(LinearSolverKind b, bool nonsymmetric) {
  return (b == LinearSolverKind::PetscHypre ? 1 : 0) + (nonsymmetric ? 2 : 0);
}

// Non-blocking broadcast of the header; the waiting ranks poll it with a
// sleep so that they do not spin a core while rank 0 meshes and assembles.
void bcast_header(Header& h, bool poll) {
  MPI_Request req;
  MPI_Ibcast(&h, 5, MPI_DOUBLE, 0, MPI_COMM_WORLD, &req);
  if (!poll) {
    MPI_Wait(&req, MPI_STATUS_IGNORE);
    return;
  }
  int done = 0;
  while (true) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) return;
    timespec ts{0, 2'000'000};  // 2 ms
    nanosleep(&ts, nullptr);
  }
}

// Row range [lo, hi) of rank r for n rows over size ranks.
void row_range(long n, int r, int size, int& lo, int& hi) {
  lo = static_cast<int>(n * r / size);
  hi = static_cast<int>(n * (r + 1) / size);
}

struct LocalSystem {  // this rank's rows, CSR with global columns
  int n_global = 0, lo = 0, hi = 0;
  std::vector<PetscInt> rowptr, cols;
  std::vector<PetscScalar> vals, f;
};

constexpr int kTagRowptr = 101, kTagCols = 102, kTagVals = 103, kTagRhs = 104;

// Every rank: assemble the MPIAIJ matrix from its rows, solve, return its x rows.
LinearSolveResult solve_local(LocalSystem& s, int code, double tol, int max_iterations, std::vector<double>& x_local) {
  const int backend = code % 2;
  const bool nonsymmetric = code >= 2;
  const int m = s.hi - s.lo;
  Mat A;
  check(MatCreateMPIAIJWithArrays(PETSC_COMM_WORLD, m, m, s.n_global, s.n_global, s.rowptr.data(), s.cols.data(),
                                  s.vals.data(), &A),
        "MatCreateMPIAIJWithArrays");
  // The values are copied: free the CSR before the multigrid setup.
  std::vector<PetscInt>().swap(s.rowptr);
  std::vector<PetscInt>().swap(s.cols);
  std::vector<PetscScalar>().swap(s.vals);
  if (!nonsymmetric) {
    check(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
    check(MatSetOption(A, MAT_SPD, PETSC_TRUE), "MatSetOption");
  }
  Vec b, x;
  check(MatCreateVecs(A, &x, &b), "MatCreateVecs");
  PetscScalar* pb;
  check(VecGetArray(b, &pb), "VecGetArray");
  for (int i = 0; i < m; ++i) pb[i] = s.f[static_cast<size_t>(i)];
  check(VecRestoreArray(b, &pb), "VecRestoreArray");
  check(VecSet(x, 0.0), "VecSet");
  KSP ksp;
  PC pc;
  check(KSPCreate(PETSC_COMM_WORLD, &ksp), "KSPCreate");
  check(KSPSetOperators(ksp, A, A), "KSPSetOperators");
  check(KSPSetType(ksp, nonsymmetric ? KSPBCGS : KSPCG), "KSPSetType");
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  if (backend == 1) {
    check(PCSetType(pc, PCHYPRE), "PCSetType(hypre)");
    check(PCHYPRESetType(pc, "boomeramg"), "PCHYPRESetType");
    set_boomeramg_defaults();
  } else {
    check(PCSetType(pc, PCGAMG), "PCSetType(gamg)");
  }
  // Stop on |f - K x| / |f| < tol, the same criterion as the Eigen CG.
  check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  check(KSPSetTolerances(ksp, tol, 0.0, PETSC_DEFAULT, max_iterations), "KSPSetTolerances");
  check(KSPSetFromOptions(ksp), "KSPSetFromOptions");  // PETSC_OPTIONS may tune it
  check(KSPSolve(ksp, b, x), "KSPSolve");
  KSPConvergedReason reason;
  PetscInt its;
  PetscReal rnorm, bnorm;
  check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
  check(KSPGetIterationNumber(ksp, &its), "KSPGetIterationNumber");
  check(KSPGetResidualNorm(ksp, &rnorm), "KSPGetResidualNorm");
  check(VecNorm(b, NORM_2, &bnorm), "VecNorm");
  LinearSolveResult r;
  r.iterations = its;
  r.residual = bnorm > 0 ? rnorm / bnorm : 0.0;
  x_local.resize(static_cast<size_t>(m));
  const PetscScalar* px;
  check(VecGetArrayRead(x, &px), "VecGetArrayRead");
  for (int i = 0; i < m; ++i) x_local[static_cast<size_t>(i)] = px[i];
  check(VecRestoreArrayRead(x, &px), "VecRestoreArrayRead");
  KSPDestroy(&ksp);
  VecDestroy(&x);
  VecDestroy(&b);
  MatDestroy(&A);
  if (reason < 0 && reason != KSP_DIVERGED_ITS) r.iterations = -static_cast<long>(reason) - 1000000;  // marks a breakdown
  if (reason == KSP_DIVERGED_ITS) r.iterations = -r.iterations - 1;                                    // marks the cap
  return r;
}

// Rank > 0: receive this rank's rows from rank 0.
LocalSystem receive_rows(const Header& h, int rank, int size) {
  LocalSystem s;
  s.n_global = static_cast<int>(h.n);
  row_range(s.n_global, rank, size, s.lo, s.hi);
  const int m = s.hi - s.lo;
  s.rowptr.resize(static_cast<size_t>(m) + 1);
  MPI_Recv(s.rowptr.data(), m + 1, MPIU_INT, 0, kTagRowptr, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  const int nnz = s.rowptr.back();
  s.cols.resize(static_cast<size_t>(nnz));
  s.vals.resize(static_cast<size_t>(nnz));
  s.f.resize(static_cast<size_t>(m));
  MPI_Recv(s.cols.data(), nnz, MPIU_INT, 0, kTagCols, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  MPI_Recv(s.vals.data(), nnz, MPIU_SCALAR, 0, kTagVals, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  MPI_Recv(s.f.data(), m, MPIU_SCALAR, 0, kTagRhs, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return s;
}

std::vector<double> g_rank_rss_mib;  // rank 0: peak RSS of each rank after the last solve

void gather_rss(int rank, int size) {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  double mine = static_cast<double>(u.ru_maxrss) / 1024.0;
  std::vector<double> all(static_cast<size_t>(size));
  MPI_Gather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (rank == 0) g_rank_rss_mib = all;
}

// Breadth-first (Cuthill-McKee-like) ordering of the matrix graph: perm[new] =
// old. The FE numbering puts all vertex dofs before all P2 edge dofs, so
// contiguous row blocks of it would couple every row of one rank with the
// other's; level sets of a BFS from a peripheral node are spatially compact
// slabs, so contiguous blocks of the BFS order have small interfaces.
std::vector<int> bfs_order(const SparseMatrix& K) {
  const int n = static_cast<int>(K.rows());
  const int* op = K.outerIndexPtr();
  const int* ix = K.innerIndexPtr();
  std::vector<int> perm;
  perm.reserve(static_cast<size_t>(n));
  std::vector<char> seen(static_cast<size_t>(n), 0);
  auto bfs = [&](int start, std::vector<int>& order) {
    size_t head = order.size();
    order.push_back(start);
    seen[static_cast<size_t>(start)] = 1;
    while (head < order.size()) {
      const int r = order[head++];
      for (int k = op[r]; k < op[r + 1]; ++k)
        if (!seen[static_cast<size_t>(ix[k])]) {
          seen[static_cast<size_t>(ix[k])] = 1;
          order.push_back(ix[k]);
        }
    }
  };
  for (int s0 = 0; s0 < n; ++s0) {
    if (seen[static_cast<size_t>(s0)]) continue;
    // One pass to find a far node of this component, then order from it.
    const size_t base = perm.size();
    bfs(s0, perm);
    const int far = perm.back();
    for (size_t k = base; k < perm.size(); ++k) seen[static_cast<size_t>(perm[k])] = 0;
    perm.resize(base);
    bfs(far, perm);
  }
  return perm;
}

// Rows [lo, hi) of P K P^T in CSR (columns renumbered and sorted).
void permuted_rows(const SparseMatrix& K, const std::vector<int>& perm, const std::vector<int>& inv, int lo, int hi,
                   std::vector<PetscInt>& rowptr, std::vector<PetscInt>& cols, std::vector<PetscScalar>& vals) {
  const int* op = K.outerIndexPtr();
  const int* ix = K.innerIndexPtr();
  const double* v = K.valuePtr();
  rowptr.assign(1, 0);
  cols.clear();
  vals.clear();
  std::vector<std::pair<int, double>> row;
  for (int i = lo; i < hi; ++i) {
    const int r = perm[static_cast<size_t>(i)];
    row.clear();
    for (int k = op[r]; k < op[r + 1]; ++k) row.emplace_back(inv[static_cast<size_t>(ix[k])], v[k]);
    std::sort(row.begin(), row.end());
    for (const auto& [c, a] : row) {
      cols.push_back(c);
      vals.push_back(a);
    }
    rowptr.push_back(static_cast<PetscInt>(cols.size()));
  }
}

void gather_solution(const std::vector<double>& x_local, int n, int size, double* x_all) {
  std::vector<int> counts(static_cast<size_t>(size)), displs(static_cast<size_t>(size));
  for (int r = 0; r < size; ++r) {
    int lo, hi;
    row_range(n, r, size, lo, hi);
    counts[static_cast<size_t>(r)] = hi - lo;
    displs[static_cast<size_t>(r)] = lo;
  }
  MPI_Gatherv(x_local.data(), static_cast<int>(x_local.size()), MPI_DOUBLE, x_all, counts.data(), displs.data(),
              MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

}  // namespace

bool petsc_available() { return true; }

LinearSolverKind resolve_linear_solver(LinearSolverKind requested) {
  return requested == LinearSolverKind::Auto ? LinearSolverKind::PetscHypre : requested;
}

int mpi_world_size() {
  PetscBool init = PETSC_FALSE;
  PetscInitialized(&init);
  if (!init && !started_by_mpi_launcher()) return 1;  // (MPI starts with the first PETSc solve)
  ensure_petsc();
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

LinearSolveResult petsc_solve(const SparseMatrix& K_in, const Eigen::VectorXd& f, LinearSolverKind backend, double tol,
                              int max_iterations, Eigen::VectorXd& x, bool nonsymmetric) {
  ensure_petsc();
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (rank != 0) throw ComputeError("petsc_solve called on MPI rank " + std::to_string(rank) + " (ranks > 0 serve)");
  SparseMatrix Kc;
  const SparseMatrix* Kp = &K_in;
  if (!K_in.isCompressed()) {
    Kc = K_in;
    Kc.makeCompressed();
    Kp = &Kc;
  }
  const SparseMatrix& K = *Kp;
  const int n = static_cast<int>(K.rows());
  Header h;
  h.cmd = kSolve;
  h.n = n;
  h.backend = backend_code(backend, nonsymmetric);
  h.max_iterations = max_iterations;
  h.tol = tol;
  LocalSystem s;
  s.n_global = n;
  row_range(n, 0, size, s.lo, s.hi);
  std::vector<int> perm, inv;  // several ranks: rows in BFS order (perm[new] = old)
  if (size > 1) {
    bcast_header(h, false);
    perm = bfs_order(K);
    inv.resize(perm.size());
    for (size_t i = 0; i < perm.size(); ++i) inv[static_cast<size_t>(perm[i])] = static_cast<int>(i);
    // Send each rank its contiguous block of the permuted rows (global columns).
    std::vector<PetscInt> rp, cols;
    std::vector<PetscScalar> vals, fr;
    for (int r = 1; r < size; ++r) {
      int lo, hi;
      row_range(n, r, size, lo, hi);
      permuted_rows(K, perm, inv, lo, hi, rp, cols, vals);
      fr.resize(static_cast<size_t>(hi - lo));
      for (int i = lo; i < hi; ++i) fr[static_cast<size_t>(i - lo)] = f[perm[static_cast<size_t>(i)]];
      MPI_Send(rp.data(), hi - lo + 1, MPIU_INT, r, kTagRowptr, MPI_COMM_WORLD);
      MPI_Send(cols.data(), static_cast<int>(cols.size()), MPIU_INT, r, kTagCols, MPI_COMM_WORLD);
      MPI_Send(vals.data(), static_cast<int>(vals.size()), MPIU_SCALAR, r, kTagVals, MPI_COMM_WORLD);
      MPI_Send(fr.data(), hi - lo, MPIU_SCALAR, r, kTagRhs, MPI_COMM_WORLD);
    }
    permuted_rows(K, perm, inv, s.lo, s.hi, s.rowptr, s.cols, s.vals);
    s.f.resize(static_cast<size_t>(s.hi));
    for (int i = 0; i < s.hi; ++i) s.f[static_cast<size_t>(i)] = f[perm[static_cast<size_t>(i)]];
  } else {
    const int* op = K.outerIndexPtr();
    s.rowptr.assign(op, op + s.hi + 1);
    s.cols.assign(K.innerIndexPtr(), K.innerIndexPtr() + op[s.hi]);
    s.vals.assign(K.valuePtr(), K.valuePtr() + op[s.hi]);
    s.f.assign(f.data(), f.data() + s.hi);
  }
  std::vector<double> x_local;
  LinearSolveResult r = solve_local(s, static_cast<int>(h.backend + 0.5), tol, max_iterations, x_local);
  x.resize(n);
  if (size > 1) {
    std::vector<double> xp(static_cast<size_t>(n));
    gather_solution(x_local, n, size, xp.data());
    for (int i = 0; i < n; ++i) x[perm[static_cast<size_t>(i)]] = xp[static_cast<size_t>(i)];
  } else {
    std::copy(x_local.begin(), x_local.end(), x.data());
  }
  gather_rss(0, size);
  if (r.iterations < 0) {
    const std::string ksp = nonsymmetric ? "BiCGSTAB" : "CG";
    if (r.iterations <= -1000000)
      throw ComputeError(ksp + " did not converge: PETSc KSP reason " + std::to_string(-(r.iterations + 1000000)) +
                         " (fem.solver = " + to_string(backend) + ")");
    throw ComputeError(ksp + " did not converge: relative residual " + num(r.residual) + " > fem.tolerance = " + num(tol) +
                       " after " + std::to_string(-r.iterations - 1) + " iterations (fem.max_iterations = " +
                       std::to_string(max_iterations) + ", fem.solver = " + to_string(backend) + ")");
  }
  return r;
}

std::vector<double> mpi_rank_peak_rss_mib() { return g_rank_rss_mib; }

MpiSession::MpiSession() {
  if (!started_by_mpi_launcher()) return;  // one rank: PETSc starts with its first solve
  ensure_petsc();
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (rank_ == 0 && size_ > 1) {
    Header h;  // kQuit
    bcast_header(h, false);
  }
}

void MpiSession::serve() {
  while (true) {
    Header h;
    bcast_header(h, true);
    if (h.cmd == static_cast<double>(kQuit)) return;
    LocalSystem s = receive_rows(h, rank_, size_);
    std::vector<double> x_local;
    solve_local(s, static_cast<int>(h.backend + 0.5), h.tol, static_cast<int>(h.max_iterations), x_local);
    gather_solution(x_local, s.n_global, size_, nullptr);
    gather_rss(rank_, size_);
  }
}

}  // namespace magenc::fem
