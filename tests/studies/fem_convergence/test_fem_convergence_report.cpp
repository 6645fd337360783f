// studies/fem_convergence/fem_convergence_report.cpp on a synthetic FemConvergenceResult (no solve):
//   - convergence.csv: the header of the study, numbers with 6 significant digits,
//     "nan" for the first run's rates;
//   - potential.csv: total and the other potential per zone edge, no line for the
//     reference solve itself.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "studies/fem_convergence/fem_convergence_report.hpp"

using namespace magenc;

TEST_CASE("fem_convergence report: convergence.csv rows with fmt_sig 6 digits and nan first rates", "[studies][contract]") {
  FemConvergenceResult r;
  RefinementSeries s;
  s.order = 2;
  s.runs.push_back({1.0, 2.0, 100, 200, 7, 0.0123456789, 0.1, NAN, NAN, 0.5, 0.25, 1.0 / 3.0, 2.0, 150.125});
  s.runs.push_back({0.7, 1.4, 300, 600, 9, 1.5e-7, 0.05, 2.25, 0.75, 0.5, 0.25, 0.125, 1.0, 1234567.0});
  r.refinement.push_back(s);
  CHECK(convergence_csv(r) ==
        "order,h_zone_mm,h_magnet_mm,elements,dofs,iterations,rms_rel,max_rel,rate_rms_h,rate_rms_dofs,t_mesh_s,"
        "t_assemble_s,t_solve_s,t_total_s,peak_rss_mib\n"
        "2,1,2,100,200,7,0.0123457,0.1,nan,nan,0.5,0.25,0.333333,2,150.125\n"
        "2,0.7,1.4,300,600,9,1.5e-07,0.05,2.25,0.75,0.5,0.25,0.125,1,1.23457e+06\n");
}

TEST_CASE("fem_convergence report: potential.csv has no line for the reference solve", "[studies][contract]") {
  PotentialComparison pc;
  pc.mu_r = 1.05;
  pc.other = "reduced";
  pc.h_ref_mm = 0.7;
  pc.rows.push_back({1.0, {1000, 20, 0.01, 0.05}, PotentialSolve{1000, 22, 0.001, 0.004}});
  pc.rows.push_back({0.7, {3000, 25, 0.005, 0.02}, std::nullopt});
  CHECK(potential_csv(pc) ==
        "h_zone_mm,dofs,potential,rms_rel,max_rel,iterations\n"
        "1,1000,total,0.01,0.05,20\n"
        "1,1000,reduced,0.001,0.004,22\n"
        "0.7,3000,total,0.005,0.02,25\n");
}
