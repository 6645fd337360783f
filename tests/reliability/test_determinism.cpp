// Determinism: the same inputs and seed give the same results for 1 and 2 OpenMP threads.
// - The radius study (seeded Monte Carlo, OpenMP sampling): every CSV byte-identical.
// - solve_field: if the parallel assembly or reductions summed in a thread-dependent order, the FE
//   system would differ in the last bits and CG (relative residual fem.tolerance, default 1e-8) could amplify that to
//   ~1e-10 relative in psi. Stated tolerance: |Bz(1 thread) - Bz(2 threads)| <= 1e-8 * max|Bz| on
//   plane.vti. Measured: 0 (the assembly merges thread-local work in a fixed order), so the
//   spectra table of error_spectrum on the two grids is required to be byte-identical.
#include <catch2/catch.hpp>

#include <cmath>

#include "fields/grid_field.hpp"
#include "reliability/run_process.hpp"

using namespace magenc_test;

namespace {
const fs::path kBin = MAGENC_BIN_DIR;
const std::string kCoarse = std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml";

std::vector<std::vector<std::string>> csv_cells(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream ss(text);
  for (std::string line; std::getline(ss, line);) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}
}  // namespace

TEST_CASE("determinism: radius study CSVs are byte-identical for 1 and 2 threads", "[studies][determinism][cli][slow]") {
  ScratchDir s("magenc_det_radius");
  const std::vector<std::string> tiny = {"--set", "radius.fem_dir=",         "--set", "radius.r0_min_mm=1.0",
                                         "--set", "radius.r0_max_mm=3.0",    "--set", "radius.r0_step_mm=0.5",
                                         "--set", "radius.samples=300",      "--set", "radius.validate_radii=2",
                                         "--set", "radius.validate_samples=1", "--set", "sensor.steps=720"};
  for (const std::string threads : {"1", "2"}) {
    auto args = tiny;
    args.insert(args.end(), {"--out", "t" + threads});
    const ProcResult r = run(kBin / "radius", args, s.dir, {{"OMP_NUM_THREADS", threads}});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  int compared = 0;
  for (const auto& e : fs::directory_iterator(s.dir / "t1")) {
    if (e.path().extension() != ".csv") continue;
    INFO(e.path().filename());
    const std::string a = slurp(e.path()), b = slurp(s.dir / "t2" / e.path().filename());
    CHECK(!a.empty());
    CHECK(a == b);
    ++compared;
  }
  CHECK(compared >= 4);
}

TEST_CASE("determinism: solve_field and error_spectrum on 1 and 2 threads agree within the stated tolerance",
          "[apps][determinism][cli]") {
  ScratchDir s("magenc_det_fem");
  for (const std::string threads : {"1", "2"}) {
    const ProcResult r =
        run(kBin / "solve_field", {"--config", kCoarse, "--out", "f" + threads}, s.dir, {{"OMP_NUM_THREADS", threads}});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
  }
  const auto g1 = magenc::read_grid_vti(s.dir / "f1" / "plane.vti");
  const auto g2 = magenc::read_grid_vti(s.dir / "f2" / "plane.vti");
  REQUIRE(g1.Bz_T.size() == g2.Bz_T.size());
  double max_bz = 0, max_diff = 0;
  for (std::size_t i = 0; i < g1.Bz_T.size(); ++i) {
    max_bz = std::max(max_bz, std::abs(g1.Bz_T[i]));
    max_diff = std::max(max_diff, std::abs(g1.Bz_T[i] - g2.Bz_T[i]));
  }
  WARN("solve_field 1 vs 2 threads: max |dBz| = " << max_diff << " T of max |Bz| = " << max_bz << " T");
  CHECK(max_bz > 0.01);
  CHECK(max_diff <= 1e-8 * max_bz);

  std::string csv[2];
  for (int t = 0; t < 2; ++t) {
    const std::string dir = t == 0 ? "f1" : "f2";
    const ProcResult r = run(kBin / "error_spectrum",
                             {"--field", "grid:" + dir + "/plane.vti", "--array", "diff4", "--r0", "2.0", "--sx", "0.05",
                              "--dy", "0.03", "--steps", "720", "--out", "s" + dir + ".csv"},
                             s.dir, {{"OMP_NUM_THREADS", t == 0 ? "1" : "2"}});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    csv[t] = slurp(s.dir / ("s" + dir + ".csv"));
  }
  const auto a = csv_cells(csv[0]), b = csv_cells(csv[1]);
  REQUIRE(a.size() == 2);
  REQUIRE(b.size() == 2);
  REQUIRE(a[1].size() == b[1].size());
  double worst = 0;
  for (std::size_t c = 0; c < a[0].size(); ++c) {
    if (a[0][c].find("_deg") == std::string::npos || a[0][c].find("_mm") != std::string::npos) continue;
    worst = std::max(worst, std::abs(std::stod(a[1][c]) - std::stod(b[1][c])));
  }
  WARN("error_spectrum on the 1- and 2-thread grids: largest coefficient difference " << worst << " deg");
  CHECK(csv[0] == csv[1]);
}
