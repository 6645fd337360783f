// Study fem_convergence: the FEM's Bz on the sensing plane against the exact
// field (mu_r = 1), for several mesh sizes and orders 1 and 2; then, at one
// mesh, the effect of the faceting of the curved face (segments, equal-area
// radius) and of the truncation radius (Robin vs psi = 0); then the total
// potential against the reduced one (permeable magnet) and the split one
// (permeable shaft). The solves are studies/fem_convergence/fem_convergence_solves.* (results and
// rates: studies/fem_convergence/fem_convergence_engine.*), the outputs
// studies/fem_convergence/fem_convergence_report.*. Writes
//   convergence.csv, faceting.csv, truncation.csv, potential.csv, shaft_potential.csv,
//   convergence.png, summary.md
//   fem_convergence [--config studies/fem_convergence/fem_convergence.toml] [--set convergence.orders=2] [--out DIR]
#include "studies/fem_convergence/fem_convergence_solves.hpp"
#include "studies/fem_convergence/fem_convergence_report.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

void run(const Config& cfg, StudyOutput& out) {
  const FemConvergenceResult result = fem::run_fem_convergence(cfg);  // field_solver/
  write_fem_convergence_report(out, result);                          // report/
}

}  // namespace

int main(int argc, char** argv) {
  return run_study("fem_convergence", "FEM Bz on the sensing plane vs the exact field: mesh size, order, faceting, truncation",
                   fem::fem_convergence_keys(), argc, argv, run);
}
