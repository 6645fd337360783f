// FEM convergence against the exact field: the typed result of the study
// fem_convergence and the rate estimate over a mesh refinement. The solves
// are studies/fem_convergence/fem_convergence_solves.hpp's (run_fem_convergence), the outputs
// studies/fem_convergence/fem_convergence_report.hpp's; this header holds only numbers, so
// report/ (library magenc) can format them.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace magenc {

// Observed rate p of e ~ x^(-p) between two runs a and b: log(e_a / e_b) / log(x_b / x_a)
// (x = 1/h gives the rate in h, x = DOFs the rate in DOFs).
double observed_rate(double x_a, double e_a, double x_b, double e_b);

// One solve of the mesh refinement, its Bz error on the plane relative to the peak |Bz|.
struct RefinementRun {
  double h_zone_mm = 0, h_magnet_mm = 0;
  long elements = 0, dofs = 0, iterations = 0;
  double rms_rel = 0, max_rel = 0;
  double rate_h = 0, rate_dofs = 0;  // observed rates against the previous run (NaN for the first)
  double t_mesh_s = 0, t_assemble_s = 0, t_solve_s = 0, t_total_s = 0;
  double peak_rss_mib = 0;  // process peak RSS after the solve
};

// The runs of one element order, coarse to fine.
struct RefinementSeries {
  int order = 1;
  std::vector<RefinementRun> runs;
};

// Sets rate_h (x = 1/h_zone) and rate_dofs (x = DOFs) of every run of the RMS error from the
// run before it; the first run's rates are NaN.
void estimate_rates(std::vector<RefinementRun>& runs);

// One solve with a faceted curved face (P2).
struct FacetingRun {
  int segments = 0;
  bool equal_area = false;
  long dofs = 0;
  double rms_rel = 0, max_rel = 0;
};

// One solve with a truncation radius and boundary condition (P2).
struct TruncationRun {
  double outer_radius_mm = 0;
  bool robin = false;  // Robin, else psi = 0
  long dofs = 0;
  double rms_rel = 0, max_rel = 0;
  double rms_vec_rel = 0;  // RMS of the full vector error relative to peak |B|
};

// Total against another potential (reduced, split) at one zone edge, both against the reference solve.
struct PotentialSolve {
  long dofs = 0, iterations = 0;
  double rms_rel = 0, max_rel = 0;
};
struct PotentialRow {
  double h_zone_mm = 0;
  PotentialSolve total;
  std::optional<PotentialSolve> other;  // empty at the reference's zone edge
};
struct PotentialComparison {
  double mu_r = 0;        // the permeability compared (magnet or shaft); 0: skipped
  std::string other;      // "reduced" or "split"
  double h_ref_mm = 0;    // zone edge of the reference (the other potential's solve)
  std::vector<PotentialRow> rows;
  bool ran() const { return mu_r > 0; }
};

struct FemConvergenceResult {
  // The sensing plane and how B is recovered.
  double plane_z_mm = 0, plane_step_mm = 0;
  int plane_nx = 0, plane_ny = 0;
  bool recovery = false;
  double h_magnet_factor = 0;  // magnet edge = factor x zone edge
  double side_h_zone_mm = 0;   // zone edge of the faceting and truncation runs
  std::vector<RefinementSeries> refinement;  // one per element order
  std::vector<FacetingRun> faceting;         // empty: skipped
  std::vector<TruncationRun> truncation;     // empty: skipped
  PotentialComparison reduced;               // total vs reduced, permeable magnet
  PotentialComparison shaft;                 // total vs split, permeable shaft
};

}  // namespace magenc
