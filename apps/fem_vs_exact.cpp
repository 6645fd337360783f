// fem_vs_exact: developer check. Solves with the given key=value overrides
// (solve_field keys) and prints the Bz error on the plane grid (-5..5 mm,
// 0.1 mm) against the exact AnalyticField, plus sizes and timings.
// Usage: fem_vs_exact [--config F] [--set k=v]... [--out DIR] [mesh.h_zone_mm=0.3 fem.order=2 ...]
// With --out=DIR it also writes solve_field's outputs (mesh.vtu, plane.vti,
// box.vti, solve.json) to DIR, so one solve feeds error_spectrum --field fem:DIR.
// --plane-half-mm H --plane-step-mm S: the error grid is -H..H in x and y
// with step S (default 5 and 0.1: 101 x 101; scripts/bench_getdp.sh uses 4 and
// 0.1: 81 x 81). --other-bz FILE: also the error of another solver's Bz at the
// points of FILE (whitespace-separated rows "x y z ... Bz", mm and T, e.g.
// GetDP's SimpleTable; '#' comments), against the same exact field.
// Bad input (unknown key, value out of range): one line, exit 2 (run_main).
#include <cstdlib>
#include <cmath>
#include <iostream>
#include "fields/analytic_field.hpp"
#include "field_solver/solve/fem_config.hpp"
#include "field_solver/field_io/validation.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "core/text_table.hpp"
#include "core/atomic_output.hpp"
#include "field_solver/field_io/field_outputs.hpp"
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>
#include <string>
#include <vector>
namespace {
// Numbers of the printed lines: fixed decimals (magenc::fmt) or significant digits (fmt_sig).
using magenc::fmt;
std::string sig(double v, int significant = 6) { return magenc::fmt_sig(v, significant); }
// --other-bz: rows "x y z ... Bz" (mm and T; blank lines and # comments skipped) into points and Bz.
void read_other_bz(const std::string& other_bz, Eigen::Matrix3Xd& other_p, Eigen::VectorXd& other_bz_T) {
  // Lines, cells and numbers as other tools write them (core/text_table.hpp); no header row.
  const std::string where = "--other-bz " + other_bz;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(other_bz, ec)) throw magenc::InputError(where + ": cannot open the file");
  const std::string text = magenc::read_text_file(other_bz, where);
  magenc::TextTableReader reader(text, where);
  std::vector<double> xs, bz;
  for (magenc::TextRow row; reader.next(row);) {
    std::vector<double> v;
    for (const auto& cell : row.cells) {
      const magenc::CellNumber n = magenc::parse_number(cell);
      if (!n.ok()) break;
      v.push_back(n.value);
    }
    if (v.size() != row.cells.size() || v.size() < 4)
      throw magenc::InputError(where + " row " + std::to_string(row.line) +
                               ": expected finite numbers x y z ... Bz (at least 4 columns)");
    xs.insert(xs.end(), v.begin(), v.begin() + 3);
    bz.push_back(v.back());
  }
  if (bz.empty()) throw magenc::InputError(where + ": no rows (allowed: at least 1)");
  other_p = Eigen::Map<Eigen::Matrix3Xd>(xs.data(), 3, static_cast<Eigen::Index>(bz.size()));
  other_bz_T = Eigen::Map<Eigen::VectorXd>(bz.data(), static_cast<Eigen::Index>(bz.size()));
}
}  // namespace

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
  double half_mm = 5.0, step_mm = 0.1;
  std::string other_bz;
  app.add_option("--plane-half-mm", half_mm, "error grid: x and y from -H to H (mm)")->check(CLI::Range(0.01, 50.0));
  app.add_option("--plane-step-mm", step_mm, "error grid step (mm)")->check(CLI::Range(0.001, 10.0));
  app.add_option("--other-bz", other_bz, "table of another solver's Bz (rows x y z ... Bz, mm and T) to compare too");
  app.add_option("assignments", bare_sets, "section.key=value overrides (same as --set)");
  magenc::parse_cli(app, argc, argv);
  o.sets.insert(o.sets.end(), bare_sets.begin(), bare_sets.end());
  const std::string out_dir = o.out;
  // With --out, mesh.vtu too (fem:DIR reads it), unless output.mesh_vtu=false is given.
  if (!out_dir.empty()) o.sets.insert(o.sets.begin(), "output.mesh_vtu=true");
  auto cfg = magenc::load_config(schema, o);
  // The other solver's table is read before the solve: a bad file fails at once.
  Eigen::Matrix3Xd other_p;
  Eigen::VectorXd other_bz_T;
  if (!other_bz.empty()) read_other_bz(other_bz, other_p, other_bz_T);
  auto s = magenc::fem::fem_settings_from_config(cfg);
  std::optional<magenc::AtomicDir> out;  // opened before the solve: a bad --out fails at once
  if (!out_dir.empty()) out.emplace(out_dir);
  magenc::fem::MagnetostaticSolver solver(s.domain, s.solver);
  solver.run();
  if (out) {
    magenc::fem::write_field_outputs(out->path(), s, solver, cfg.to_json());
    out->commit();
  }
  const auto exact_field = magenc::fem::exact_field_of(s.domain.magnet);  // analytic or the sector pattern's
  const magenc::FieldSource& exact = *exact_field;
  auto g = magenc::GridData::from_range({-half_mm, -half_mm, s.plane_z_mm}, {half_mm, half_mm, s.plane_z_mm},
                                        {step_mm, step_mm, 1});
  auto e = magenc::fem::bz_error_on_grid(solver.evaluator(), exact, g);
  auto& st = solver.stats();
  {
    auto P = g.points_mm();
    auto B = solver.evaluator().B_T(P);
    auto bz = exact.Bz_T(P);
    Eigen::Index im = 0; double em = 0;
    for (Eigen::Index i = 0; i < P.cols(); ++i) if (std::abs(B(2,i)-bz[i]) > em) { em = std::abs(B(2,i)-bz[i]); im = i; }
    std::cout << "max err at (" << sig(P(0, im)) << "," << sig(P(1, im)) << "," << sig(P(2, im)) << "): fem "
              << fmt(B(2, im), 6) << " exact " << fmt(bz[im], 6) << "\n";
    for (double x : {0.0, 1.0, 2.4, 4.0}) {
      Eigen::Vector3d q(x, 0, s.plane_z_mm);
      std::cout << "  x=" << sig(x) << " fem " << fmt(solver.evaluator().B_T(q)->z(), 6) << " exact "
                << fmt(exact.Bz_T(q), 6) << "\n";
    }
  }
  int cnt[8] = {0};
  for (int t = 0; t < solver.mesh().num_tets(); ++t) cnt[solver.mesh().region[t]]++;
  std::cout << "tets per region: magnet " << cnt[1] << " air " << cnt[2] << " zone " << cnt[3] << " shaft " << cnt[4]
            << "\n";
  std::cout << "P" << st.order << " el=" << st.elements << " dofs=" << st.dofs << " it=" << st.iterations
            << " mesh=" << fmt(st.t_mesh_s, 2) << " asm=" << fmt(st.t_assemble_s, 2) << " solve=" << fmt(st.t_solve_s, 2)
            << " post=" << fmt(st.t_post_s, 2) << " | peak=" << fmt(e.peak_T, 5) << " max_rel=" << sig(e.max_rel(), 4)
            << " rms_rel=" << sig(e.rms_rel(), 4) << "\n";
  std::cout << "t_total=" << fmt(st.t_total_s, 2) << " peak_rss_mib=" << fmt(magenc::fem::peak_rss_mib(), 0) << "\n";
  std::cout << "grid " << g.dims[0] << "x" << g.dims[1] << ": magenc peak=" << fmt(e.peak_T, 5)
            << " T rms_rel=" << sig(e.rms_rel(), 5) << " max_rel=" << sig(e.max_rel(), 5) << "\n";
  if (other_bz_T.size() > 0) {
    const Eigen::VectorXd ex = exact.Bz_T(other_p);
    double peak = 0, mx = 0, ss = 0;
    for (Eigen::Index i = 0; i < ex.size(); ++i) {
      const double d = other_bz_T[i] - ex[i];
      peak = std::max(peak, std::abs(ex[i]));
      mx = std::max(mx, std::abs(d));
      ss += d * d;
    }
    std::cout << "other (" << other_bz << ", " << ex.size() << " points): peak=" << fmt(peak, 5)
              << " T rms_rel=" << sig(std::sqrt(ss / double(ex.size())) / peak, 5) << " max_rel=" << sig(mx / peak, 5)
              << "\n";
  }
  return 0;
  });
}
