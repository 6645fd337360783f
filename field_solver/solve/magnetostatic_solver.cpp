#include "field_solver/solve/magnetostatic_solver.hpp"

#include <omp.h>

#include <Eigen/IterativeLinearSolvers>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include "core/errors.hpp"
#include "core/format.hpp"
#include "field_solver/fe/element.hpp"
#include "field_solver/solve/linear_solver.hpp"
#include "field_solver/solve/nonlinear.hpp"
#include "field_solver/solve/reduced_potential.hpp"
#include "field_solver/mesh/sector_magnetization.hpp"
#include "field_solver/mesh/symmetric_mesh.hpp"

namespace magenc::fem {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Wall time of a sequence of stages: run(seconds, stage) runs one and stores its time;
// total_s() is the time since construction.
class StageTimer {
 public:
  template <class Stage> void run(double& seconds, Stage&& stage) {
    const auto t = Clock::now();
    stage();
    seconds = seconds_since(t);
  }
  double total_s() const { return seconds_since(t0_); }

 private:
  Clock::time_point t0_ = Clock::now();
};

// Relative permeability per cell of `mesh` (region ids -> domain materials).
Eigen::VectorXd cell_mu_r(const DomainSpec& domain, const TetMesh& mesh) {
  Eigen::VectorXd mu(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) mu[t] = domain.mu_r(mesh.region[t]);
  return mu;
}

// Remanence per cell (T, 3 x n_tets): br in the magnet's cells, 0 elsewhere.
Eigen::Matrix3Xd cell_br(const TetMesh& mesh, const Eigen::Vector3d& br_T) {
  Eigen::Matrix3Xd b = Eigen::Matrix3Xd::Zero(3, mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.region[t] == kRegionMagnet) b.col(t) = br_T;
  return b;
}

// The magnet magnetized along one axis only: br_T has one non-zero component c,
// the result has |Br_c| along +-x_c (the source field of that component alone).
Magnet component_magnet(const Magnet& magnet, const Eigen::Vector3d& br_T) {
  int c = 0;
  br_T.cwiseAbs().maxCoeff(&c);
  Magnet m = magnet;
  m.br_T = std::abs(br_T[c]);
  m.magnetization_deg = c == 0 ? (br_T[c] < 0 ? 180.0 : 0.0) : c == 1 ? (br_T[c] < 0 ? 270.0 : 90.0) : 0.0;
  m.magnetization_elevation_deg = c == 2 ? (br_T[c] < 0 ? -90.0 : 90.0) : 0.0;
  return m;
}

}  // namespace

std::string to_string(Potential p) {
  switch (p) {
    case Potential::Auto: return "auto";
    case Potential::Total: return "total";
    case Potential::Reduced: return "reduced";
    case Potential::Split: return "split";
  }
  return "?";
}

const std::vector<std::string>& potential_names() {
  static const std::vector<std::string> n{to_string(Potential::Auto), to_string(Potential::Total),
                                          to_string(Potential::Reduced), to_string(Potential::Split)};
  return n;
}

Potential potential_from_string(const std::string& name) {
  for (Potential p : {Potential::Auto, Potential::Total, Potential::Reduced, Potential::Split})
    if (to_string(p) == name) return p;
  throw InputError("fem.potential = " + name + " is out of range: allowed auto, total, reduced, split");
}

MagnetostaticSolver::MagnetostaticSolver(DomainSpec domain, SolverOptions options)
    : domain_(std::move(domain)), options_(std::move(options)) {
  domain_.validate();
  if (options_.order != 1 && options_.order != 2)
    throw InputError("fem.order = " + std::to_string(options_.order) + " is out of range: allowed 1 or 2");
  if (options_.threads <= 0) options_.threads = omp_get_max_threads();
  options_.solver = resolve_linear_solver(options_.solver);
  // A sector pattern (multipole or radial ring): its magnetization per cell (sector_magnetization.hpp) in the
  // total potential; the reduced and split potentials would need the exact field inside the material.
  if (!domain_.magnet.is_uniform() && options_.potential != Potential::Auto && options_.potential != Potential::Total)
    throw InputError("fem.potential = " + to_string(options_.potential) + " with magnet.pattern = " +
                     pattern_name(domain_.magnet.pattern) + " is not supported: allowed total or auto (the total potential "
                     "with the sectors' magnetization in the magnet's cells)");
  if (options_.potential == Potential::Auto)
    options_.potential = !domain_.magnet.is_uniform() || domain_.has_permeable_part_touching_magnet() ? Potential::Total
                         : domain_.shaft.enabled || domain_.has_permeable_part() ? Potential::Split
                                                                                 : Potential::Reduced;
  if (options_.potential == Potential::Split && domain_.has_permeable_part_touching_magnet())
    throw InputError("fem.potential = split with a permeable part touching the magnet is not supported (the magnet's "
                     "exact source field and its faceted mesh disagree on the contact face): use fem.potential = total "
                     "(or auto), or leave a gap between part and magnet");
  if (domain_.mesh.symmetric && !domain_.magnet.is_uniform()) {
    // The mirrored wedge meshes and the quadrant solve assume the uniform magnet's symmetries (a potential odd
    // or even across x = 0 and y = 0 per magnetization component, no facets inside the magnet).
    domain_.mesh.symmetric = false;
    mesh_layout_ = "whole domain: magnet.pattern = " + pattern_name(domain_.magnet.pattern) +
                   " is meshed and solved whole (mesh.symmetric = true not applied)";
  } else if (domain_.mesh.symmetric && domain_.has_off_axis_part()) {
    // Never symmetrize a domain without the symmetry: mesh and solve it whole, and say so.
    domain_.mesh.symmetric = false;
    mesh_layout_ = "whole domain: a part off the axis breaks the mirror symmetry (mesh.symmetric = true not applied)";
  } else {
    mesh_layout_ = domain_.mesh.symmetric ? "symmetric D" + std::to_string(domain_.mesh.symmetry_order) + " mesh"
                                          : "whole domain";
  }
}

void MagnetostaticSolver::run() {
  StageTimer timer;
  timer.run(stats_.t_mesh_s, [&] { make_mesh(); });
  timer.run(stats_.t_setup_s, [&] { setup_system(); });
  if (domain_.has_nonlinear_part()) {
    timer.run(stats_.t_solve_s, [&] { solve_nonlinear(); });  // assembly inside, once per iteration
  } else {
    timer.run(stats_.t_assemble_s, [&] { assemble_system(); });
    timer.run(stats_.t_solve_s, [&] { solve(); });
  }
  timer.run(stats_.t_post_s, [&] { compute_cell_fields(); });
  stats_.t_total_s = timer.total_s();
}

// 1. Mesh the regions (TetGen).
void MagnetostaticSolver::make_mesh() {
  // B-H parts: the problem is nonlinear, no superposition of magnetization components. With one
  // component (x, y or z) |grad psi|, hence mu_r(|H|), has the mirror symmetry of that component's
  // potential: Newton runs on the quadrant with its parity. Else the whole mesh is solved.
  quadrant_solve_ = domain_.mesh.symmetric && options_.quadrant;
  if (quadrant_solve_ && domain_.has_nonlinear_part() && nonlinear_component() < 0) {
    quadrant_solve_ = false;
    mesh_layout_ += ", whole mesh solved: B-H parts with a magnetization not along x, y or z (no superposition of "
                    "the components' quadrant solves in a nonlinear problem)";
  }
  if (domain_.mesh.symmetric) {
    quad_ = mesh_quadrant(domain_);
    mesh_ = mirror_quadrant_mesh(quad_);
  } else {
    mesh_ = mesh_domain(domain_);
  }
  stats_.nodes = mesh_.num_nodes();
  stats_.elements = mesh_.num_tets();
  stats_.boundary_faces = mesh_.boundary_faces.cols();
}

// The one non-zero component (0 x, 1 y, 2 z) of the magnet's remanence, -1 if there are several
// (components below 1e-12 of |Br| are zero, as in QuadrantSolve::assemble).
int MagnetostaticSolver::nonlinear_component() const {
  const Eigen::Vector3d br_T = domain_.magnet.remanence_T();
  int c = -1, n = 0;
  for (int k = 0; k < 3; ++k)
    if (std::abs(br_T[k]) >= 1e-12 * domain_.magnet.br_T) {
      c = k;
      ++n;
    }
  return n == 1 ? c : -1;
}

// 2. Dofs and per-cell materials.
void MagnetostaticSolver::setup_system() {
  space_ = std::make_unique<FeSpace>(mesh_, options_.order);
  stats_.dofs = space_->num_dofs();
  stats_.order = options_.order;
  stats_.threads = options_.threads;
  mu_r_cell_ = cell_mu_r(domain_, mesh_);
  br_cell_ = magnet_cell_remanence(mesh_, domain_.magnet);
  cell_total_.clear();
  if (options_.potential == Potential::Split) {
    cell_total_ = total_potential_cells(mesh_, domain_);
    if (std::none_of(cell_total_.begin(), cell_total_.end(), [](char c) { return c != 0; }))
      cell_total_.clear();  // no permeable part: the split is the reduced potential
  }
  stats_.solved_dofs = stats_.dofs;
  if (quadrant_solve_) {
    quadrant_ = std::make_unique<QuadrantSolve>(std::move(quad_), options_.order);
    stats_.solved_dofs = quadrant_->num_dofs();
  }
  quad_ = TetMesh();
}

// 3. Stiffness (+ Robin) and load vector.
void MagnetostaticSolver::assemble_system() {
  const Eigen::Vector3d br_T = domain_.magnet.remanence_T();
  if (quadrant_solve_) {
    // The quadrant's cells carry the same materials; one load per non-zero
    // component of Br (magnetization_deg = 0, no elevation: x only).
    const Eigen::VectorXd mu = cell_mu_r(domain_, quadrant_->mesh());
    quadrant_->assemble(mu, br_T, domain_.magnet.br_T, options_.robin, options_.threads,
                        [&](const TetMesh& m, const FeSpace& sp, const Eigen::Vector3d& br) {
                          const int odd_axis = std::abs(br[0]) > 0 ? 0 : std::abs(br[1]) > 0 ? 1 : -1;
                          return potential_load(m, sp, mu, br, component_magnet(domain_.magnet, br), odd_axis);
                        });
    stats_.nonzeros = quadrant_->nonzeros();
    return;
  }
  {  // swap, not assign: Eigen 3.4's SparseMatrix has no move assignment (K_ = f() copies)
    SparseMatrix K = assemble_stiffness(mesh_, *space_, mu_r_cell_, options_.robin, options_.threads);
    K_.swap(K);
  }
  PotentialLoad load = potential_load(mesh_, *space_, mu_r_cell_, br_T, domain_.magnet, -1);
  f_ = std::move(load.f);
  interface_phi_s_ = std::move(load.interface_phi_s);
  if (!options_.robin) apply_zero_dirichlet(K_, f_, boundary_dofs(mesh_, *space_));
  stats_.nonzeros = K_.nonZeros();
}

// The load of the configured potential for remanence br_T (total potential) or,
// equivalently, the source magnet `source` (reduced and split: its exact field;
// split: odd_axis 0 or 1 when the potential is odd across x_odd_axis = 0, else -1).
PotentialLoad MagnetostaticSolver::potential_load(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r,
                                                  const Eigen::Vector3d& br_T, const Magnet& source, int odd_axis) const {
  PotentialLoad l;
  if (options_.potential == Potential::Total) {
    l.f = assemble_rhs(mesh, space, source.is_uniform() ? cell_br(mesh, br_T) : magnet_cell_remanence(mesh, source));
  } else if (options_.potential == Potential::Reduced || cell_total_.empty()) {
    l.f = assemble_reaction_rhs(mesh, space, mu_r, AnalyticField(source));
  } else {
    const AnalyticField field(source);
    const std::vector<char> total = total_potential_cells(mesh, domain_);
    l.interface_phi_s = interface_source_potential(space, total, field, odd_axis);
    l.f = assemble_split_rhs(mesh, space, mu_r, total, field, l.interface_phi_s);
  }
  return l;
}

// 4. Solve K psi = f (one solve, or one per magnetization component on the quadrant).
void MagnetostaticSolver::solve() {
  Eigen::setNbThreads(options_.threads);
  auto cg = [&](const SparseMatrix& K, const Eigen::VectorXd& f, Eigen::VectorXd& x) {
    LinearSolveResult st;
    if (f.squaredNorm() == 0.0) {
      x = Eigen::VectorXd::Zero(f.size());  // reduced potential, mu_r = 1 everywhere: no reaction
    } else {
      st = linear_solve(K, f, options_.linear(), x);
    }
    stats_.iterations += st.iterations;
    stats_.residual = std::max(stats_.residual, st.residual);
    ++stats_.solves;
  };
  stats_.iterations = 0;
  stats_.residual = 0;
  stats_.solves = 0;
  if (quadrant_solve_) {
    psi_ = quadrant_->solve_and_mirror(space_->dof_points(), cg, &interface_phi_s_);
    quadrant_.reset();
  } else {
    cg(K_, f_, psi_);
  }
  if (!psi_.allFinite()) throw ComputeError("solution psi contains NaN or Inf");
  SparseMatrix().swap(K_);  // release memory before post-processing (K_ = SparseMatrix() would keep it)
}

// The nonlinear solve's load f (the magnet's; on the quadrant component comp's alone), zero at the
// fixed dofs as apply_zero_dirichlet leaves it; sets interface_phi_s_ (mirrored on the quadrant).
Eigen::VectorXd MagnetostaticSolver::nonlinear_load(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_cell,
                                                    int comp, const std::vector<int>& fixed) {
  const Eigen::Vector3d br_T = domain_.magnet.remanence_T();
  Eigen::Vector3d br = br_T;
  if (quadrant_solve_) {
    br = Eigen::Vector3d::Zero();
    br[comp] = br_T[comp];
  }
  PotentialLoad load = potential_load(mesh, space, mu_cell, br, quadrant_solve_ ? component_magnet(domain_.magnet, br) : domain_.magnet,
                                      comp < 2 ? comp : -1);
  for (int d : fixed) load.f[d] = 0.0;
  interface_phi_s_ = load.interface_phi_s.size() > 0 && quadrant_solve_
                         ? quadrant_->mirror(space_->dof_points(), load.interface_phi_s, comp)
                         : std::move(load.interface_phi_s);
  return std::move(load.f);
}

void MagnetostaticSolver::throw_not_converged(const std::vector<double>& hist, double tolerance) {
  std::string h;
  for (size_t j = 0; j < hist.size(); ++j) h += (j ? ", " : "") + std::to_string(j + 1) + ": " + num(hist[j]);
  throw ComputeError("nonlinear solve did not converge: residual " + num(hist.back()) + " > fem.nonlinear_tolerance = " +
                     num(tolerance) + " after " + std::to_string(hist.size()) +
                     " iterations (fem.nonlinear_max_iterations); residual history " + h);
}

// Inexact Newton direction: J d = -R solved to eta |R|, eta = min(0.1, max(r, 0.5 tol / r)) (no
// tighter than the step needs to reach the tolerance; never below fem.tolerance). J is not
// symmetric (mu_r and its derivative at the centroid, the P2 gradients across the cell): BiCGSTAB,
// with the multigrid of fem.solver when it is a PETSc one, else (eigen-pcg) Eigen's BiCGSTAB with
// Jacobi, on one thread below kSerialKrylovDofs unknowns: its ~2 sparse products per iteration are
// too small to share (on 2 busy cores the threads' barriers cost more than they save: the cup's
// quadrant, 13,713 unknowns, 5.3 s -> 1.9 s with 2 threads, docs/benchmarks.md). False when it fails.
bool MagnetostaticSolver::newton_direction(const SparseMatrix& J, const Eigen::VectorXd& R, double r, Eigen::VectorXd& d,
                                           long& linear_iterations) const {
  constexpr Eigen::Index kSerialKrylovDofs = 20000;
  const double eta = std::max(options_.tolerance, std::min(0.1, std::max(r, 0.5 * options_.nonlinear_tolerance / r)));
  if (options_.solver == LinearSolverKind::PetscHypre || options_.solver == LinearSolverKind::PetscGamg) {
    try {
      const LinearSolveResult st = petsc_solve(J, -R, options_.solver, eta, options_.max_iterations, d, true);
      linear_iterations += st.iterations;
      return d.allFinite();
    } catch (const ComputeError&) {
      return false;  // not converged: the caller takes the fixed-point step
    }
  }
  Eigen::setNbThreads(J.rows() < kSerialKrylovDofs ? 1 : options_.threads);
  Eigen::BiCGSTAB<SparseMatrix, Eigen::DiagonalPreconditioner<double>> bicg;
  bicg.setTolerance(eta);
  bicg.setMaxIterations(options_.max_iterations);
  bicg.compute(J);
  d = bicg.solve(-R);
  Eigen::setNbThreads(options_.threads);
  linear_iterations += bicg.iterations();
  return bicg.info() == Eigen::Success && d.allFinite();
}

// The converged iterate into psi_ and mu_r_cell_: on the quadrant mirrored onto the whole mesh, whose
// cells are the quadrant's mirrored, so mu_r from the mirrored psi.
void MagnetostaticSolver::store_nonlinear_solution(Eigen::VectorXd& psi, Eigen::VectorXd& mu_cell, int comp) {
  if (quadrant_solve_) {
    psi_ = quadrant_->mirror(space_->dof_points(), psi, comp);
    quadrant_.reset();
    mu_r_cell_ = secant_mu_r(mesh_, *space_, cell_bh_curves(domain_, mesh_), mu_r_cell_, psi_, options_.threads);
  } else {
    psi_.swap(psi);
    mu_r_cell_.swap(mu_cell);
  }
}

// 3+4 with B-H parts (nonlinear.hpp). The load f (the magnet's, constant: the
// nonlinear cells carry the total potential) is assembled once; every iterate psi
// gets the stiffness K(mu(psi)) of its secant permeability and the residual
// r = |f - K(mu(psi)) psi| / |f|, recorded after each iteration. Iteration 1 is the
// fixed-point step from the curves' initial permeability; then Newton steps
// (options_.newton) or fixed-point steps psi <- K(mu(psi))^-1 f.
// Quadrant solve (one magnetization component c): the iteration runs on the quadrant's
// mesh with component c's parity (psi = 0 on x_c = 0 for c = 0, 1; natural elsewhere), then
// psi is mirrored onto the whole mesh and mu_r evaluated there.
void MagnetostaticSolver::solve_nonlinear() {
  auto& hist = stats_.nonlinear_residuals;
  hist.clear();
  stats_.newton_steps = 0;
  const int comp = quadrant_solve_ ? nonlinear_component() : -1;
  const TetMesh& mesh = quadrant_solve_ ? quadrant_->mesh() : mesh_;
  const FeSpace& space = quadrant_solve_ ? quadrant_->space() : *space_;
  const std::vector<const BhCurve*> curves = cell_bh_curves(domain_, mesh);
  const Eigen::VectorXd mu_linear = quadrant_solve_ ? cell_mu_r(domain_, mesh) : mu_r_cell_;
  std::vector<int> fixed = options_.robin ? std::vector<int>{} : boundary_dofs(mesh, space);
  if (quadrant_solve_) {
    const std::vector<int> plane = quadrant_->odd_plane_dofs(comp);
    fixed.insert(fixed.end(), plane.begin(), plane.end());
  }
  auto stiffness = [&](const Eigen::VectorXd& mu) {
    SparseMatrix K = assemble_stiffness(mesh, space, mu, options_.robin, options_.threads);
    Eigen::VectorXd unused = Eigen::VectorXd::Zero(K.rows());
    if (!fixed.empty()) apply_zero_dirichlet(K, unused, fixed);
    return K;
  };
  // K(mu initial), f
  Eigen::VectorXd mu_cell = mu_linear, psi;
  SparseMatrix K = stiffness(mu_cell);
  const Eigen::VectorXd f = nonlinear_load(mesh, space, mu_cell, comp, fixed);
  stats_.nonzeros = K.nonZeros();
  Eigen::setNbThreads(options_.threads);
  long linear_iterations = 0;
  double linear_residual = 0;
  stats_.solves = 0;
  auto fixed_point_step = [&] {  // psi <- K(mu)^-1 f with K = K(mu)
    const LinearSolveResult st = linear_solve(K, f, options_.linear(), psi);
    linear_iterations += st.iterations;
    linear_residual = std::max(linear_residual, st.residual);
    ++stats_.solves;
  };
  const double f_norm = f.norm();
  fixed_point_step();
  Eigen::VectorXd R;
  auto evaluate = [&](const Eigen::VectorXd& p, Eigen::VectorXd& mu, SparseMatrix& Kp, Eigen::VectorXd& res) {
    mu = secant_mu_r(mesh, space, curves, mu_linear, p, options_.threads);
    SparseMatrix k = stiffness(mu);
    Kp.swap(k);
    res = Kp * p - f;
    return res.norm() / f_norm;
  };
  double r = evaluate(psi, mu_cell, K, R);
  Eigen::setNbThreads(options_.threads);
  for (int k = 1;; ++k) {
    hist.push_back(r);
    stats_.nonlinear_iterations = k;
    if (!std::isfinite(r)) throw ComputeError("nonlinear solve: the residual is not finite after " + std::to_string(k) + " iterations");
    if (r < options_.nonlinear_tolerance) break;
    if (k >= options_.nonlinear_max_iterations) throw_not_converged(hist, options_.nonlinear_tolerance);
    bool newton_done = false;
    if (options_.newton) {
      SparseMatrix J = nonlinear_jacobian(mesh, space, curves, K, psi);
      if (!fixed.empty()) {
        Eigen::VectorXd unused = Eigen::VectorXd::Zero(J.rows());
        apply_zero_dirichlet(J, unused, fixed);
      }
      Eigen::VectorXd d;
      if (newton_direction(J, R, r, d, linear_iterations)) {
        // Backtracking: the first of alpha = 1, 1/2, ... 1/32 with r(psi + alpha d) < (1 - 1e-4 alpha) r.
        Eigen::VectorXd mu_t, R_t;
        SparseMatrix K_t;
        for (double alpha = 1.0; alpha > 1.0 / 33; alpha *= 0.5) {
          const Eigen::VectorXd psi_t = psi + alpha * d;
          const double r_t = evaluate(psi_t, mu_t, K_t, R_t);
          if (r_t < (1 - 1e-4 * alpha) * r) {
            psi = psi_t;
            mu_cell.swap(mu_t);
            K.swap(K_t);
            R.swap(R_t);
            r = r_t;
            newton_done = true;
            ++stats_.newton_steps;
            break;
          }
        }
      }
    }
    if (!newton_done) {
      fixed_point_step();  // K holds K(mu(psi)): the secant step
      r = evaluate(psi, mu_cell, K, R);
    }
  }
  SparseMatrix().swap(K);
  SparseMatrix().swap(K_);
  store_nonlinear_solution(psi, mu_cell, comp);
  if (!psi_.allFinite()) throw ComputeError("solution psi contains NaN or Inf");
  stats_.iterations = linear_iterations;
  stats_.residual = linear_residual;
}

// 5. Solution object (recovered gradient) and point locator; B at cell centroids on demand (B_cell()).
void MagnetostaticSolver::compute_cell_fields() {
  FeSolution s;
  s.order = options_.order;
  s.points_mm = space_->dof_points();
  s.cell_dofs = space_->cell_dofs();
  s.psi_Tmm = psi_;
  s.region = mesh_.region;
  s.mu_r = mu_r_cell_;
  s.br_T = br_cell_;
  if (options_.potential != Potential::Total) s.source = std::make_shared<AnalyticField>(domain_.magnet);
  if (!cell_total_.empty()) {
    s.cell_total = cell_total_;
    s.interface_phi_s_Tmm = interface_phi_s_;
  }
  if (options_.recovery) s.recover_gradient();
  {
    const std::lock_guard<std::mutex> lock(B_cell_mutex_);
    B_cell_ready_ = false;
    B_cell_ = Eigen::Matrix3Xd();
  }
  evaluator_ = std::make_unique<FieldEvaluator>(std::move(s));
}

const Eigen::Matrix3Xd& MagnetostaticSolver::B_cell() const {
  if (!evaluator_) throw ComputeError("B at cell centroids asked for before the solve ran");
  const std::lock_guard<std::mutex> lock(B_cell_mutex_);
  if (!B_cell_ready_) {
    Eigen::Matrix3Xd B = evaluator_->B_cell_centroids();
    if (!B.allFinite()) throw ComputeError("B at the cell centroids contains NaN or Inf");
    B_cell_ = std::move(B);
    B_cell_ready_ = true;
  }
  return B_cell_;
}

}  // namespace magenc::fem
