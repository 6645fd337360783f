// Magnetostatic FEM for a permanent magnet (fem.potential: the total scalar
// potential below; or the reduced potential / total-reduced split of
// reduced_potential.hpp, which add the magnet's exact field analytically).
//
// PDE (scaled units, units.hpp: psi = mu0*phi_m in T*mm, Br = mu0*M0 in T):
//   -div(mu_r grad psi) = -div(Br)   in the ball Omega of radius R_out,
//   B = mu_r*(-grad psi) + Br        (Br = 0 outside the magnet),
// Boundary: dipole Robin condition d psi/dn = -2 psi/r on |x| = R_out
// (or psi = 0 with robin = false).
// Discretization: Lagrange P1 or P2 tetrahedra on a TetGen mesh (regions
// magnet / air / refinement zone / shaft), weak form
//   Int mu_r grad psi . grad v + Int_Gamma (2/r) psi v = Int_magnet Br . grad v,
// CG through linear_solver.hpp (fem.solver).
// Sample: build/bin/solve_field --set fem.order=2 --out output/field
#pragma once
#include <Eigen/Core>
#include <array>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "field_solver/fe/assembly.hpp"
#include "field_solver/fe/fe_solution.hpp"
#include "field_solver/fe/fe_space.hpp"
#include "field_solver/mesh/geometry.hpp"
#include "field_solver/solve/linear_solver.hpp"
#include "field_solver/solve/quadrant_solve.hpp"

namespace magenc::fem {

// fem.potential: "total", "reduced", "split" (reduced_potential.hpp) or "auto": split with a shaft, else reduced.
enum class Potential { Auto, Total, Reduced, Split };
std::string to_string(Potential p);
const std::vector<std::string>& potential_names();
// InputError naming fem.potential for an unknown name.
Potential potential_from_string(const std::string& name);

// The solver's options; the defaults are the fem.* keys' (fem_config.cpp), except tolerance (below).
struct SolverOptions {
  int order = 2;                          // Lagrange order, 1 or 2
  bool robin = true;                      // dipole Robin condition; false: psi = 0 on the sphere
  LinearSolverKind solver = LinearSolverKind::Auto;     // fem.solver (linear_solver.hpp)
  Potential potential = Potential::Auto;                // fem.potential
  Preconditioner preconditioner = Preconditioner::Jacobi;  // fem.preconditioner (eigen-pcg)
  double tolerance = 1e-10;               // CG stop: |f - K psi| / |f| below this (fem.tolerance: 1e-8)
  int max_iterations = 20000;             // CG iteration cap (ComputeError when reached)
  int threads = 0;                        // OpenMP threads (0: omp_get_max_threads)
  int progress_every = 500;               // stderr progress line every N CG iterations (0: quiet)
  bool recovery = true;                   // B from the recovered (node-averaged) gradient of psi
  // With mesh.symmetric: solve on the quadrant x, y >= 0 only (psi = 0 on the
  // plane across which the magnetization component is odd, natural condition
  // on the other; one solve per non-zero component) and mirror the solution
  // onto the whole mesh. Same discrete solution as the whole symmetric mesh
  // (to the CG tolerance) with 1/4 of the unknowns. false: solve the whole mesh.
  bool quadrant = true;
  // Parts with a B-H curve (nonlinear.hpp): iterate until |f - K(mu(psi)) psi| / |f| <
  // nonlinear_tolerance. newton = true: one fixed-point step from the curves' initial
  // permeability, then Newton steps with the exact Jacobian (BiCGSTAB, forcing term
  // min(0.1, max(r, 0.5 tol / r)), backtracking on the residual; a fixed-point step when
  // the backtracking fails). newton = false: fixed-point (secant permeability, Picard)
  // iterations only (fem.nonlinear_method).
  double nonlinear_tolerance = 1e-6;
  int nonlinear_max_iterations = 300;
  bool newton = true;

  // The linear solver's part (solver resolved by the MagnetostaticSolver's constructor).
  LinearSolveSettings linear() const { return {solver, preconditioner, tolerance, max_iterations, progress_every}; }
};

// What a solve cost and reached.
struct SolveStats {
  long nodes = 0, elements = 0, boundary_faces = 0, dofs = 0, nonzeros = 0;
  long solved_dofs = 0;  // unknowns of the system(s) solved (the quadrant's with a quadrant solve)
  int solves = 0;        // linear solves (quadrant: one per magnetization component)
  int order = 0, threads = 0;
  long iterations = 0;  // CG iterations, summed over the solves
  double residual = 0;  // relative residual reported by CG
  int nonlinear_iterations = 0;              // nonlinear iterations, fixed-point and Newton (0: linear problem)
  int newton_steps = 0;                      // of which Newton steps
  std::vector<double> nonlinear_residuals;   // |f - K(mu(psi_k)) psi_k| / |f| after each iteration
  double t_mesh_s = 0, t_setup_s = 0, t_assemble_s = 0, t_solve_s = 0, t_post_s = 0, t_total_s = 0;
};

class MagnetostaticSolver {
 public:
  MagnetostaticSolver(DomainSpec domain, SolverOptions options);
  // make_mesh -> setup_system -> assemble_system -> solve -> compute_cell_fields, each timed
  // into stats() (t_mesh_s, t_setup_s, t_assemble_s, t_solve_s, t_post_s; t_total_s for all).
  void run();

  const DomainSpec& domain() const { return domain_; }
  const SolverOptions& options() const { return options_; }
  const TetMesh& mesh() const { return mesh_; }
  const SolveStats& stats() const { return stats_; }
  // How the domain was meshed: "symmetric DN mesh", "whole domain", or the
  // whole domain with the reason when a part off the axis forbids the symmetry.
  const std::string& mesh_layout() const { return mesh_layout_; }
  // Solution with materials (valid after run()).
  const FeSolution& solution() const { return evaluator_->solution(); }
  // Point evaluation of B (valid after run()).
  const FieldEvaluator& evaluator() const { return *evaluator_; }
  // B (T) at cell centroids, 3 x n_cells (valid after run()): computed on the first call (only
  // mesh.vtu and tests need it); throws ComputeError if it is not finite.
  const Eigen::Matrix3Xd& B_cell() const;

 private:
  void make_mesh();
  void setup_system();
  void assemble_system();
  void solve();
  void compute_cell_fields();
  void solve_nonlinear();
  Eigen::VectorXd nonlinear_load(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_cell, int comp,
                                 const std::vector<int>& fixed);
  [[noreturn]] static void throw_not_converged(const std::vector<double>& hist, double tolerance);
  bool newton_direction(const SparseMatrix& J, const Eigen::VectorXd& R, double r, Eigen::VectorXd& d,
                        long& linear_iterations) const;
  void store_nonlinear_solution(Eigen::VectorXd& psi, Eigen::VectorXd& mu_cell, int comp);
  int nonlinear_component() const;
  PotentialLoad potential_load(const TetMesh& mesh, const FeSpace& space, const Eigen::VectorXd& mu_r,
                               const Eigen::Vector3d& br_T, const Magnet& source, int odd_axis) const;

  DomainSpec domain_;
  SolverOptions options_;
  TetMesh mesh_;                           // tets, region ids, outer boundary faces (mm)
  TetMesh quad_;                           // mesh.symmetric: the quadrant mesh_ mirrors, until setup_system
  bool quadrant_solve_ = false;            // solve on the quadrant and mirror (mesh.symmetric and options.quadrant)
  std::unique_ptr<QuadrantSolve> quadrant_;  // the quadrant's system (quadrant solve)
  std::unique_ptr<FeSpace> space_;         // P1/P2 dofs on mesh_
  Eigen::VectorXd mu_r_cell_;              // relative permeability per cell
  Eigen::Matrix3Xd br_cell_;               // remanence Br per cell (T), 0 outside the magnet
  std::vector<char> cell_total_;           // split potential: 1 in the cells with the total potential (empty: none)
  Eigen::VectorXd interface_phi_s_;        // split potential: phi_s at the interface dofs (T*mm), else empty
  SparseMatrix K_;                         // stiffness + Robin (dofs x dofs, 1/mm*mm^3 scaled: mm)
  Eigen::VectorXd f_;                      // load Int Br . grad v (T*mm^2)
  Eigen::VectorXd psi_;                    // solution psi at dofs (T*mm)
  std::unique_ptr<FieldEvaluator> evaluator_;
  mutable std::mutex B_cell_mutex_;        // guards the lazy B_cell_
  mutable bool B_cell_ready_ = false;      // B_cell_ holds this run's B at centroids
  mutable Eigen::Matrix3Xd B_cell_;        // B at centroids (T), on the first B_cell() call
  SolveStats stats_;
  std::string mesh_layout_;
};

}  // namespace magenc::fem
