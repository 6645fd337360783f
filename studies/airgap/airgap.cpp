// Study airgap: the air-gap offset dz on the FEM field of the configured
// (default) magnet, beside the exact field. dz is swept over
// dz_sweep.min_mm..max_mm (default -0.5..+0.5 mm) with
//   "dz alone"  the base mount (ideal by default): docs/physics.md expects no error
//               at any dz on the exact field (a common scale cancels in atan2);
//               on the FEM field whatever appears is an artefact;
//   "dz, sx"    with a residual static eccentricity (residual.sx_mm),
//   "dz, dx"    with a residual dynamic eccentricity (residual.dx_mm),
//   "dz, sx+dx" with both,
// which shows how dz moves the 1st and 3rd harmonics (slopes dc1/ddz, dc3/ddz
// at dz = 0 from cubic fits). The FE solution comes from a solve_field
// directory (fem_field.dir; run solve_field first) through
// fem_field.sources: "grid" (grid:DIR/box.vti, cubic) and/or "fem" (fem:DIR).
// Writes spectra.csv (extra columns sweep, source), comparison.csv (FEM beside
// exact), fits.csv, eps.png, coefficients_<case>.png, differences_<case>.png,
// summary.md. The computation is src/analysis/fem_field_studies.*, the outputs
// src/report/fem_field_reports.*.
//   airgap [--config studies/airgap/airgap.toml] [--set fem_field.dir=/tmp/field] [--out DIR]
#include "analysis/fem_field_studies.hpp"
#include "field_solver/field_io/solved_field.hpp"
#include "report/fem_field_reports.hpp"
#include "report/study_output.hpp"

using namespace magenc;

namespace {

const char* kStudy = "airgap";

std::vector<KeySpec> study_keys() {
  std::vector<KeySpec> k = {study_arrays_key()};
  for (auto& s : dz_sweep_keys(" (inside the box.vti height)")) k.push_back(s);
  k.push_back(string_list_key("dz_sweep.coefs", {"a0_deg", "c1_deg", "c2_deg", "c3_deg", "c4_deg", "pp_deg"}, {},
                         "spectra columns fitted with a cubic in dz"));
  k.push_back(real_key("residual.sx_mm", 0.05, -100, 100, "mm", "residual static eccentricity sx of the 'sx' cases"));
  k.push_back(real_key("residual.dx_mm", 0.05, -100, 100, "mm", "residual dynamic eccentricity dx of the 'dx' cases"));
  for (auto& s : fem_field_keys("box.vti")) k.push_back(s);
  return k;
}

void run(const Config& cfg, StudyOutput& out) {
  const AirgapResult result = run_airgap(cfg, kStudy, fem_sources_from_config(cfg));
  write_airgap_report(out, result);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy,
                   "airgap: angle-error spectra vs the air-gap offset dz on the FEM field (grid:DIR/box.vti, "
                   "fem:DIR), alone and with residual eccentricities, beside the exact field",
                   study_keys(), argc, argv, run);
}
