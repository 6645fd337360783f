// Study harmonic_provenance: which harmonics of the angle error are physical
// and which are artefacts of how the field is sampled.
//  1. The exact field is sampled on Cartesian plane grids of spacing h and
//     interpolated (nearest, linear, cubic); every
//     case (ideal mount, sx, dx at provenance.offset_mm) runs through the
//     probe pipeline beside the exact field. Artefact = |c_n(grid) - c_n(exact)|.
//  2. FE solutions: the variants of provenance.fem_variants, solved here with
//     magnet.mu_r = 1 (field_solver/field_io/fem_variant.hpp; default coarse P1, coarse
//     P2, medium P2, medium P2 D16: seconds each), and the solve_field output directories of
//     provenance.fem_dirs; each evaluated directly and, unless
//     provenance.fem_grid_interp = none, through its plane grid.
// Writes provenance.csv (spectra table + columns source, variant, h_mm,
// interp, case), artefacts_vs_h.png, ideal_harmonics.png, fem_artefacts.png
// (when FE solutions ran), summary.md. The computation is
// studies/harmonic_provenance/provenance.* (the FE solves field_solver/solve/fem_variant.*), the
// outputs studies/harmonic_provenance/provenance_report.*.
//   harmonic_provenance [--config studies/harmonic_provenance/harmonic_provenance.toml] [--out DIR]
#include <iostream>
#include <filesystem>
#include <future>
#include <memory>
#include <vector>

#include "studies/harmonic_provenance/provenance.hpp"
#include "core/format.hpp"
#include "field_solver/field_io/fem_variant.hpp"
#include "studies/harmonic_provenance/provenance_report.hpp"
#include "report/study_output.hpp"
#include "field_solver/field_io/solved_field.hpp"

using namespace magenc;

namespace {

const char* kStudy = "harmonic_provenance";

void run(const Config& cfg, StudyOutput& out) {
  // 1. Inputs. FE variants and directories are all checked before anything is solved.
  const ProvenanceOptions options = ProvenanceOptions::from_config(cfg);
  for (const auto& dir : options.fem_dirs) SolvedFieldDir(dir).require_complete_solve_of(cfg, "provenance.fem_dirs");
  const auto variants = fem::fem_variants_from_config(cfg, kFemVariantsKey, {".", MAGENC_SOURCE_DIR});

  // 2. Grid sampling of the exact field, then the FE solutions (directly and through their plane grids). The
  // solve_field directories (mesh.vtu, its point locator, plane.vti) load on a second thread meanwhile: the
  // same reads as after the variants, on the core the variants' serial solves leave idle.
  struct LoadedDir {
    std::shared_ptr<const FemField> field;
    GridData plane;
  };
  std::future<std::vector<LoadedDir>> loading = std::async(std::launch::async, [&options] {
    std::vector<LoadedDir> loaded;
    for (const auto& dir : options.fem_dirs) {
      const SolvedFieldDir solved(dir);
      loaded.push_back({solved.fem(), options.via_grid() ? read_grid_vti(solved.dir() / "plane.vti") : GridData{}});
    }
    return loaded;
  });
  ProvenanceRun run = run_grid_provenance(cfg, options);
  for (const auto& v : variants) {
    const fem::SolvedFemField s = fem::solve_fem_field(v.solve_cfg);
    std::cerr << "harmonic_provenance: " << v.label << ": P" << s.facts.order << ", " << s.facts.elements << " tets, "
              << s.facts.dofs << " dofs, " << s.facts.iterations << " CG iterations, " << fmt(s.facts.t_total_s, 2) << " s\n";
    add_fe_solution(run, {v.label, "solved here", s.facts}, *s.field, options.via_grid() ? &s.plane : nullptr);
  }
  const std::vector<LoadedDir> loaded = loading.get();
  for (std::size_t i = 0; i < loaded.size(); ++i) {
    const std::string& dir = options.fem_dirs[i];
    add_fe_solution(run, {dir, dir, SolvedFieldDir(dir).facts()}, *loaded[i].field,
                    options.via_grid() ? &loaded[i].plane : nullptr);
  }

  // 3. Table, plots, summary.
  write_provenance_report(out, run);
}

}  // namespace

int main(int argc, char** argv) {
  return run_study(kStudy, "harmonic_provenance: physical harmonics vs grid-sampling and FE artefacts",
                   provenance_keys(), argc, argv, run);
}
