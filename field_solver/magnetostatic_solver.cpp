#include "magnetostatic_solver.hpp"

#include <omp.h>

#include <Eigen/IterativeLinearSolvers>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "errors.hpp"
#include "units.hpp"

namespace magenc::fem {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Wraps an Eigen preconditioner; Eigen's CG calls solve() once per iteration,
// which is where the progress line is printed.
template <class Inner>
class ProgressPreconditioner {
 public:
  ProgressPreconditioner() = default;
  template <class M> ProgressPreconditioner& analyzePattern(const M& m) { inner_.analyzePattern(m); return *this; }
  template <class M> ProgressPreconditioner& factorize(const M& m) { inner_.factorize(m); return *this; }
  template <class M> ProgressPreconditioner& compute(const M& m) { inner_.compute(m); return *this; }
  template <class Rhs> Eigen::VectorXd solve(const Rhs& b) const {
    ++calls_;
    if (every_ > 0 && calls_ % every_ == 0) {
      std::fprintf(stderr, "solve_field: CG iteration %ld (%.1f s)\n", calls_, seconds_since(t0_));
    }
    return inner_.solve(b);
  }
  Eigen::ComputationInfo info() { return inner_.info(); }
  void configure(int every) { every_ = every; calls_ = 0; t0_ = Clock::now(); }

 private:
  Inner inner_;
  int every_ = 0;
  mutable long calls_ = 0;
  Clock::time_point t0_ = Clock::now();
};

template <class Precond>
void run_cg(const SparseMatrix& K, const Eigen::VectorXd& f, const SolverOptions& o, Eigen::VectorXd& psi,
            SolveStats& st) {
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, ProgressPreconditioner<Precond>> cg;
  cg.setTolerance(o.tolerance);
  cg.setMaxIterations(o.max_iterations);
  cg.preconditioner().configure(o.progress_every);
  cg.compute(K);
  if (cg.info() != Eigen::Success) throw ComputeError("preconditioner setup failed (fem.preconditioner = " + o.preconditioner + ")");
  psi = cg.solve(f);
  st.iterations = cg.iterations();
  st.residual = cg.error();
  if (cg.info() != Eigen::Success) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "CG did not converge: relative residual %.3g > fem.tolerance = %.3g after %ld iterations "
                  "(fem.max_iterations = %d)",
                  st.residual, o.tolerance, st.iterations, o.max_iterations);
    throw ComputeError(buf);
  }
}

}  // namespace

MagnetostaticSolver::MagnetostaticSolver(DomainSpec domain, SolverOptions options)
    : domain_(std::move(domain)), options_(std::move(options)) {
  domain_.validate();
  if (options_.order != 1 && options_.order != 2)
    throw InputError("fem.order = " + std::to_string(options_.order) + " is out of range: allowed 1 or 2");
  if (options_.threads <= 0) options_.threads = omp_get_max_threads();
}

void MagnetostaticSolver::run() {
  const auto t0 = Clock::now();
  auto t = Clock::now();
  make_mesh();
  stats_.t_mesh_s = seconds_since(t);
  t = Clock::now();
  setup_system();
  stats_.t_setup_s = seconds_since(t);
  t = Clock::now();
  assemble_system();
  stats_.t_assemble_s = seconds_since(t);
  t = Clock::now();
  solve();
  stats_.t_solve_s = seconds_since(t);
  t = Clock::now();
  compute_cell_fields();
  stats_.t_post_s = seconds_since(t);
  stats_.t_total_s = seconds_since(t0);
}

// 1. Mesh the regions (TetGen).
void MagnetostaticSolver::make_mesh() {
  mesh_ = mesh_domain(domain_);
  stats_.nodes = mesh_.num_nodes();
  stats_.elements = mesh_.num_tets();
  stats_.boundary_faces = mesh_.boundary_faces.cols();
}

// 2. Dofs and per-cell materials.
void MagnetostaticSolver::setup_system() {
  space_ = std::make_unique<FeSpace>(mesh_, options_.order);
  stats_.dofs = space_->num_dofs();
  stats_.order = options_.order;
  stats_.threads = options_.threads;
  const int nt = mesh_.num_tets();
  mu_r_cell_.resize(nt);
  br_cell_.setZero(3, nt);
  const double a = deg_to_rad(domain_.magnet.magnetization_deg);
  const Eigen::Vector3d br(domain_.magnet.br_T * std::cos(a), domain_.magnet.br_T * std::sin(a), 0.0);
  for (int t = 0; t < nt; ++t) {
    mu_r_cell_[t] = domain_.mu_r(mesh_.region[t]);
    if (mesh_.region[t] == kRegionMagnet) br_cell_.col(t) = br;
  }
}

// 3. Stiffness (+ Robin) and load vector.
void MagnetostaticSolver::assemble_system() {
  K_ = assemble_stiffness(mesh_, *space_, mu_r_cell_, options_.robin, options_.threads);
  f_ = assemble_rhs(mesh_, *space_, br_cell_);
  if (!options_.robin) apply_zero_dirichlet(K_, f_, boundary_dofs(mesh_, *space_));
  stats_.nonzeros = K_.nonZeros();
}

// 4. Solve K psi = f with preconditioned CG.
void MagnetostaticSolver::solve() {
  Eigen::setNbThreads(options_.threads);
  if (options_.preconditioner == "ichol")
    run_cg<Eigen::IncompleteCholesky<double, Eigen::Lower>>(K_, f_, options_, psi_, stats_);
  else
    run_cg<Eigen::DiagonalPreconditioner<double>>(K_, f_, options_, psi_, stats_);
  if (!psi_.allFinite()) throw ComputeError("solution psi contains NaN or Inf");
  K_ = SparseMatrix();  // release memory before post-processing
}

// 5. Solution object, point locator and B at cell centroids.
void MagnetostaticSolver::compute_cell_fields() {
  FeSolution s;
  s.order = options_.order;
  s.points_mm = space_->dof_points();
  s.cell_dofs = space_->cell_dofs();
  s.psi_Tmm = psi_;
  s.region = mesh_.region;
  s.mu_r = mu_r_cell_;
  s.br_T = br_cell_;
  if (options_.recovery) s.recover_gradient();
  evaluator_ = std::make_unique<FieldEvaluator>(std::move(s));
  B_cell_ = evaluator_->B_cell_centroids();
  if (!B_cell_.allFinite()) throw ComputeError("B contains NaN or Inf");
}

}  // namespace magenc::fem
