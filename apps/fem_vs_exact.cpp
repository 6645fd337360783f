// fem_vs_exact: developer check. Solves with the given key=value overrides
// (solve_field keys) and prints the Bz error on the plane grid (-5..5 mm,
// 0.1 mm) against the exact AnalyticField, plus sizes and timings.
// Usage: fem_vs_exact [--config F] [--set k=v]... [--out DIR] [mesh.h_zone_mm=0.3 fem.order=2 ...]
// With --out=DIR it also writes solve_field's outputs (mesh.vtu, plane.vti,
// box.vti, solve.json) to DIR, so one solve feeds error_spectrum --field fem:DIR.
// Bad input (unknown key, value out of range): one line, exit 2 (run_main).
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include "fields/analytic_field.hpp"
#include "fem_config.hpp"
#include "validation.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/atomic_output.hpp"
#include "field_outputs.hpp"
#include <optional>
#include <string>
#include <vector>
int main(int argc, char** argv) {
  // run_main: one-line errors, exit codes, and the Debug builds' FP trap.
  return magenc::run_main("fem_vs_exact", [&]() -> int {
  auto schema = magenc::fem::solve_field_schema();
  magenc::CommonOptions o;
  // The common options (--config, --set, --out, --help with the key table) and, as before, bare
  // key=value arguments (applied after --set).
  CLI::App app{"fem_vs_exact: solve, then the Bz error on the plane against the exact field"};
  magenc::add_common_options(app, o, schema);
  std::vector<std::string> bare_sets;
  app.add_option("assignments", bare_sets, "section.key=value overrides (same as --set)");
  magenc::parse_cli(app, argc, argv);
  o.sets.insert(o.sets.end(), bare_sets.begin(), bare_sets.end());
  const std::string out_dir = o.out;
  // With --out, mesh.vtu too (fem:DIR reads it), unless output.mesh_vtu=false is given.
  if (!out_dir.empty()) o.sets.insert(o.sets.begin(), "output.mesh_vtu=true");
  auto cfg = magenc::load_config(schema, o);
  auto s = magenc::fem::fem_settings_from_config(cfg);
  std::optional<magenc::AtomicDir> out;  // opened before the solve: a bad --out fails at once
  if (!out_dir.empty()) out.emplace(out_dir);
  magenc::fem::MagnetostaticSolver solver(s.domain, s.solver);
  solver.run();
  if (out) {
    magenc::fem::write_field_outputs(out->path(), s, solver, cfg.to_json());
    out->commit();
  }
  magenc::AnalyticField exact(s.domain.magnet);
  auto g = magenc::GridData::from_range({-5, -5, s.plane_z_mm}, {5, 5, s.plane_z_mm}, {0.1, 0.1, 1});
  auto e = magenc::fem::bz_error_on_grid(solver.evaluator(), exact, g);
  auto& st = solver.stats();
  {
    auto P = g.points_mm();
    auto B = solver.evaluator().B_T(P);
    auto bz = exact.Bz_T(P);
    Eigen::Index im = 0; double em = 0;
    for (Eigen::Index i = 0; i < P.cols(); ++i) if (std::abs(B(2,i)-bz[i]) > em) { em = std::abs(B(2,i)-bz[i]); im = i; }
    std::printf("max err at (%g,%g,%g): fem %.6f exact %.6f\n", P(0,im), P(1,im), P(2,im), B(2,im), bz[im]);
    for (double x : {0.0, 1.0, 2.4, 4.0}) {
      Eigen::Vector3d q(x, 0, s.plane_z_mm);
      std::printf("  x=%g fem %.6f exact %.6f\n", x, solver.evaluator().B_T(q)->z(), exact.Bz_T(q));
    }
  }
  int cnt[8] = {0};
  for (int t = 0; t < solver.mesh().num_tets(); ++t) cnt[solver.mesh().region[t]]++;
  std::printf("tets per region: magnet %d air %d zone %d shaft %d\n", cnt[1], cnt[2], cnt[3], cnt[4]);
  std::printf("P%d el=%ld dofs=%ld it=%ld mesh=%.2f asm=%.2f solve=%.2f post=%.2f | peak=%.5f max_rel=%.3e rms_rel=%.3e\n",
    st.order, st.elements, st.dofs, st.iterations, st.t_mesh_s, st.t_assemble_s, st.t_solve_s, st.t_post_s, e.peak_T, e.max_rel(), e.rms_rel());
  std::printf("t_total=%.2f peak_rss_mib=%.0f\n", st.t_total_s, magenc::fem::peak_rss_mib());
  return 0;
  });
}
