// The FEM-driven probe studies real_field and airgap as library calls:
// configuration in, typed result out (the reports are report/fem_field_reports.hpp's).
// Both run every mounting case on each FEM field source of fem_field.dir and on
// the exact field of the same magnet (run_comparison, fem_comparison.hpp).
//   real_field  ideal mount; each offset of sweep.offsets at sweep.reference_mm
//               and swept 0..sweep.max_mm; the acceptance check at the reference
//               offset (AcceptanceRule, cell by cell)
//   airgap      dz swept over dz_sweep.min_mm..max_mm alone and with residual
//               eccentricities sx, dx and both; eps(theta) at three air gaps
// The FEM sources come opened (field_solver/field_io/solved_field.hpp fem_sources_from_config).
#pragma once
#include <string>
#include <vector>

#include "analysis/fem_comparison.hpp"
#include "analysis/offset_sweeps.hpp"
#include "core/config.hpp"

namespace magenc {

// The [acceptance] keys of real_field: acceptance.arrays, acceptance.coefs.
std::vector<KeySpec> acceptance_keys();

// One judged (or listed) cell of the acceptance table: a coefficient of one FEM
// source at one reference offset on one array.
struct AcceptanceCell {
  std::size_t offset = 0;  // index into the offsets (ComparisonPlan::points)
  std::string array;       // probe array name
  std::string source;      // FEM source label
  std::string coef;        // "c1_deg", ...
  double value_deg = 0, exact_deg = 0, tolerance_deg = 0;
  bool judged = false;     // the array is one of the judged arrays
  bool pass = false;       // judged and within tolerance
};
struct AcceptanceResult {
  AcceptanceRule rule;
  std::vector<std::string> arrays, coefs;  // what is judged
  std::vector<AcceptanceCell> cells;       // per offset, per array, per FEM source, per coefficient
  int judged() const;
  int passed() const;
};
// Judges the single mounts (run.plan.points, one per offset) of every FEM source
// against the exact field: arrays not in `arrays` are listed, not judged.
AcceptanceResult judge_acceptance(const ComparisonRun& run, const std::vector<std::string>& arrays,
                                  const std::vector<std::string>& coefs, const AcceptanceRule& rule);

struct RealFieldResult {
  ComparisonInputs inputs;        // FEM sources, exact field, base mount, setups
  OffsetSweepOptions options;     // [sweep]
  ComparisonRun run;              // ideal mount, points = offsets at the reference, sweeps = offsets swept
  AcceptanceResult acceptance;
  double solve_mu_r = 0;          // magnet.mu_r of the solve (NaN if not recorded)
  std::string interp;             // fem_field.interp
};
// The real_field study: dz_mm is not an allowed offset (plane.vti has no dz).
RealFieldResult run_real_field(const Config& cfg, const std::string& study, FemSources fem);

// One residual-eccentricity case of the dz sweep.
struct GapCase {
  std::string label;     // sweep label in tables (no commas): "dz alone", "dz with sx=0.05", ...
  std::string tag;       // file-name part: "alone", "sx", "dx", "sxdx"
  std::string residual;  // "none", "sx=0.05", "dx=0.05", "sx=0.05 dx=0.05"
  Mount base;            // mount with the residual offsets (dz overwritten by the sweep)
};

struct AirgapResult {
  ComparisonInputs inputs;
  std::vector<double> dz_mm;              // the swept air gaps
  double residual_sx_mm = 0, residual_dx_mm = 0;
  std::vector<GapCase> cases;             // alone, sx, dx, sx+dx
  std::vector<std::string> diff_coefs;    // fitted coefficients without a0 and pp (difference plots, table)
  ComparisonRun run;                      // one sweep per case
  // eps(theta) of the last case on the first FEM source, per array, at
  // dz_mm[eps_index[j]]: the sweep start, the value nearest 0, the sweep end.
  std::size_t eps_index[3] = {0, 0, 0};
  std::vector<std::vector<AngleErrorResult>> eps;  // per array: three results
  double solve_mu_r = 0;
  std::string interp;
};
AirgapResult run_airgap(const Config& cfg, const std::string& study, FemSources fem);

}  // namespace magenc
