// The eigen-pcg backend of fem.solver (linear_solver.hpp): Eigen's conjugate gradients with a Jacobi
// or incomplete-Cholesky preconditioner, a progress line and a short residual history.
#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "field_solver/solve/linear_solver.hpp"

namespace magenc::fem {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Wraps an Eigen preconditioner; Eigen's CG calls solve(r_k) once per iteration with the current
// residual r_k (and once before the loop with r_0), which is where the progress line is printed and
// the residual history is kept. A residual that is not finite (breakdown on an indefinite or singular
// system) or that has grown 1e8-fold above its smallest value (divergence) stops the solve at once.
template <class Inner>
class ProgressPreconditioner {
 public:
  ProgressPreconditioner() = default;
  template <class M> ProgressPreconditioner& analyzePattern(const M& m) { inner_.analyzePattern(m); return *this; }
  template <class M> ProgressPreconditioner& factorize(const M& m) { inner_.factorize(m); return *this; }
  template <class M> ProgressPreconditioner& compute(const M& m) { inner_.compute(m); return *this; }
  template <class Rhs> Eigen::VectorXd solve(const Rhs& b) const {
    const long k = calls_++;
    if (every_ > 0 && k > 0 && k % every_ == 0) {
      std::cerr << "solve_field: CG iteration " << k << " (" << fmt(seconds_since(t0_), 1) << " s)\n";
    }
    const double rel = rhs_norm_ > 0 ? b.norm() / rhs_norm_ : b.norm();
    history_.record(k, rel);
    if (!std::isfinite(rel))
      throw ComputeError("CG broke down at iteration " + std::to_string(k) +
                         ": residual is not finite (K not symmetric positive definite?); " + history_.text());
    if (rel > 1e8 * history_.min_rel)
      throw ComputeError("CG diverged at iteration " + std::to_string(k) + ": relative residual " + num(rel) +
                         " is 1e8 times its minimum " + num(history_.min_rel) +
                         " (K not symmetric positive definite?); " + history_.text());
    return inner_.solve(b);
  }
  Eigen::ComputationInfo info() { return inner_.info(); }
  void configure(int every, double rhs_norm) {
    every_ = every;
    calls_ = 0;
    rhs_norm_ = rhs_norm;
    history_ = CgResidualHistory{};
    t0_ = Clock::now();
  }
  const CgResidualHistory& history() const { return history_; }

 private:
  Inner inner_;
  int every_ = 0;
  double rhs_norm_ = 1;
  mutable long calls_ = 0;
  mutable CgResidualHistory history_;
  Clock::time_point t0_ = Clock::now();
};

template <class Precond>
LinearSolveResult run_cg(const SparseMatrix& K, const Eigen::VectorXd& f, const LinearSolveSettings& o,
                         Eigen::VectorXd& x) {
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, ProgressPreconditioner<Precond>> cg;
  cg.setTolerance(o.tolerance);
  cg.setMaxIterations(o.max_iterations);
  cg.preconditioner().configure(o.progress_every, f.norm());
  cg.compute(K);
  if (cg.info() != Eigen::Success)
    throw ComputeError("preconditioner setup failed (fem.preconditioner = " + to_string(o.preconditioner) + ")");
  x = cg.solve(f);
  LinearSolveResult r;
  r.iterations = cg.iterations();
  r.residual = cg.error();
  if (cg.info() != Eigen::Success || !std::isfinite(r.residual) || !x.allFinite()) {
    throw ComputeError("CG did not converge: relative residual " + num(r.residual) + " > fem.tolerance = " +
                       num(o.tolerance) + " after " + std::to_string(r.iterations) + " iterations (fem.max_iterations = " +
                       std::to_string(o.max_iterations) + "); " + cg.preconditioner().history().text());
  }
  return r;
}

}  // namespace

void CgResidualHistory::record(long iteration, double rel) {
  ++count;
  if (std::isfinite(rel)) min_rel = std::min(min_rel, rel);
  // Iterations 0, 1, 2, 4, 8, ... and the last few: a short history whatever the iteration count.
  if (iteration > 0 && (iteration & (iteration - 1)) == 0) {
    sampled.emplace_back(iteration, rel);
  } else if (iteration == 0) {
    sampled.emplace_back(0, rel);
  }
  last[static_cast<std::size_t>(iteration % long(last.size()))] = {iteration, rel};
}

std::string CgResidualHistory::text() const {
  std::vector<std::pair<long, double>> all = sampled;
  for (const auto& p : last)
    if (p.first >= 0 && std::none_of(all.begin(), all.end(), [&](const auto& q) { return q.first == p.first; }))
      all.push_back(p);
  std::sort(all.begin(), all.end());
  std::string t = "residual history (iteration: |r|/|f|)";
  for (std::size_t i = 0; i < all.size(); ++i) t += (i ? ", " : " ") + std::to_string(all[i].first) + ": " + num(all[i].second);
  return t;
}

LinearSolveResult eigen_pcg_solve(const SparseMatrix& K, const Eigen::VectorXd& f, const LinearSolveSettings& settings,
                                  Eigen::VectorXd& x) {
  if (settings.preconditioner == Preconditioner::IChol)
    return run_cg<Eigen::IncompleteCholesky<double, Eigen::Lower>>(K, f, settings, x);
  return run_cg<Eigen::DiagonalPreconditioner<double>>(K, f, settings, x);
}

}  // namespace magenc::fem
