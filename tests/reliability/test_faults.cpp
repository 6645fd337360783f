// Faults: a run killed at any moment leaves only complete files (or none); a second run
// into the same output while one is running is refused and corrupts neither; a CG solve that cannot
// converge, breaks down or diverges stops with a clear error and its residual history.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>
#include <chrono>
#include <regex>
#include <thread>

#include "core/atomic_output.hpp"
#include "core/errors.hpp"
#include "core/fp_trap.hpp"
#include "fields/grid_field.hpp"
#include "field_solver/solve/magnetostatic_solver.hpp"
#include "reliability/run_process.hpp"
#include "field_solver/field_io/vtk_io.hpp"

using namespace magenc_test;

namespace {

const fs::path kBin = MAGENC_BIN_DIR;
const std::string kCoarse = std::string(MAGENC_SOURCE_DIR) + "/meshes/coarse.toml";

bool is_temporary(const std::string& name) {
  return std::regex_search(name, std::regex(R"(\.(tmp|old)\.[0-9]+$)"));
}

// Does `file` parse as what its extension says? "" when it does, else why not.
std::string parse_problem(const fs::path& file) {
  const std::string ext = file.extension().string();
  try {
    if (ext == ".vti") {
      (void)magenc::read_grid_vti(file);
    } else if (ext == ".vtu") {
      (void)magenc::fem::read_solution_vtu(file);
    } else if (ext == ".json") {
      std::ifstream in(file);
      const nlohmann::json parsed = nlohmann::json::parse(in);  // throws on a torn file
      (void)parsed;
    } else if (ext == ".csv") {
      std::ifstream in(file);
      std::string header, line;
      if (!std::getline(in, header) || header.empty()) return "no header";
      const auto cols = std::count(header.begin(), header.end(), ',');
      int rows = 0;
      while (std::getline(in, line)) {
        if (line.empty()) continue;
        ++rows;
        if (std::count(line.begin(), line.end(), ',') != cols) return "row " + std::to_string(rows) + " has other columns";
      }
      const std::string all = slurp(file);
      if (all.back() != '\n') return "last line not terminated";
    } else if (ext == ".png") {
      const std::string all = slurp(file);
      if (all.size() < 20 || all.compare(1, 3, "PNG") != 0 || all.find("IEND") != all.size() - 8) return "not a complete PNG";
    } else {
      const std::string all = slurp(file);
      if (all.empty()) return "empty";
    }
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Removes dir and everything in it. A study killed while gnuplot draws leaves gnuplot running for a
// moment (std::system's child outlives SIGKILL of its parent), still writing its PNG into the study's
// temporary folder, so one remove_all can meet a folder that fills again ("Directory not empty"):
// retried for up to 10 s.
void remove_all_settled(const fs::path& dir) {
  for (int attempt = 0;; ++attempt) {
    try {
      fs::remove_all(dir);
      return;
    } catch (const fs::filesystem_error&) {
      if (attempt >= 100) throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
}

// Every file under dir outside temporaries must parse; returns the problems.
std::vector<std::string> incomplete_files(const fs::path& dir, int& checked) {
  std::vector<std::string> bad;
  if (!fs::exists(dir)) return bad;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
    if (is_temporary(it->path().filename().string())) {
      it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file()) continue;
    // "<out>.lock": the (empty) lock file a killed run could not remove; its flock died with it.
    if (it->path().extension() == ".lock" && fs::file_size(it->path()) == 0) continue;
    ++checked;
    if (const std::string why = parse_problem(it->path()); !why.empty())
      bad.push_back(fs::relative(it->path(), dir).string() + ": " + why);
  }
  return bad;
}

}  // namespace

TEST_CASE("faults: solve_field and a study killed at several moments leave complete files or none",
          "[apps][faults][cli][slow]") {
  ScratchDir s("magenc_kill");
  struct Job {
    std::string exe;
    std::vector<std::string> args;
    std::vector<std::string> files;  // what a complete output has
  };
  const std::vector<Job> jobs = {
      {"solve_field", {"--config", kCoarse, "--set", "output.mesh_vtu=true", "--out", "out/field"},
       {"mesh.vtu", "plane.vti", "box.vti", "solve.json"}},
      {"linear_model", {"--set", "sensor.steps=720", "--out", "out/linear_model"}, {"summary.md", "config.toml"}},
  };
  int kills = 0, checked = 0;
  for (const auto& job : jobs) {
    const fs::path out = s.dir / job.args.back();
    remove_all_settled(s.dir / "out");
    // 1. A complete run: how long it takes, and what it writes.
    const ProcResult full = run(kBin / job.exe, job.args, s.dir);
    INFO(job.exe << ": " << full.err);
    REQUIRE(full.exit_code == 0);
    for (const auto& f : job.files) REQUIRE(fs::exists(out / f));
    // 2. Killed (SIGKILL) at fractions of that time, once without and once with a previous output.
    for (const bool previous : {false, true}) {
      if (previous) REQUIRE(run(kBin / job.exe, job.args, s.dir).exit_code == 0);
      for (const double frac : {0.05, 0.2, 0.4, 0.6, 0.8, 0.95}) {
        if (!previous) remove_all_settled(s.dir / "out");
        Child c(kBin / job.exe, job.args, s.dir, {}, s.dir.parent_path());
        c.kill_after(frac * full.seconds);
        const ProcResult r = c.wait();
        ++kills;
        INFO(job.exe << " killed at " << frac << " x " << full.seconds << " s (previous output: " << previous
                     << "), exit " << r.exit_code);
        const auto bad = incomplete_files(s.dir / "out", checked);
        CHECK(bad.empty());
        for (const auto& b : bad) UNSCOPED_INFO(b);
        if (previous || fs::exists(out))
          for (const auto& f : job.files) CHECK(fs::exists(out / f));  // the old or the new output, whole
      }
    }
    // 3. The next run completes and removes what the killed runs left (temporaries, no lock file).
    const ProcResult again = run(kBin / job.exe, job.args, s.dir);
    REQUIRE(again.exit_code == 0);
    for (const auto& e : fs::directory_iterator(out.parent_path())) {
      INFO(e.path());
      CHECK_FALSE(is_temporary(e.path().filename().string()));
      CHECK(e.path().extension() != ".lock");
    }
  }
  WARN("kill tests: " << kills << " runs killed, " << checked << " files checked after the kills");
}

TEST_CASE("faults: a second run into the same output while one is running is refused and neither is corrupted",
          "[apps][faults][cli][slow]") {
  ScratchDir s("magenc_lock");
  // A run long enough (about 1 s) for the second one to start while the first holds the lock.
  const std::vector<std::string> args = {"--config", kCoarse, "--set", "fem.order=2", "--set", "mesh.h_zone_mm=0.25",
                                         "--set", "fem.solver=eigen-pcg", "--set", "output.mesh_vtu=true", "--out", "field"};
  Child first(kBin / "solve_field", args, s.dir, {}, s.dir.parent_path());
  // Wait until the first run holds the lock (it takes it before meshing).
  for (int i = 0; i < 500 && !fs::exists(s.dir / "field.lock"); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE(fs::exists(s.dir / "field.lock"));
  const ProcResult second = run(kBin / "solve_field", args, s.dir, {}, s.dir.parent_path());
  const ProcResult r = first.wait();
  INFO("first: " << r.err << "second: " << second.err);
  CHECK(second.exit_code == 2);
  CHECK(count_lines(second.err) == 1);
  CHECK_THAT(second.err, Catch::Contains("another magenc run is writing there") && Catch::Contains("field"));
  REQUIRE(r.exit_code == 0);
  int checked = 0;
  CHECK(incomplete_files(s.dir / "field", checked).empty());
  CHECK(checked == 4);
  CHECK_FALSE(fs::exists(s.dir / "field.lock"));
  // error_spectrum's single-file output takes the same lock (held here by this process).
  {
    magenc::OutputLock held(s.dir / "spectra.csv");
    const ProcResult e = run(kBin / "error_spectrum", {"--field", "analytic", "--array", "two", "--r0", "2.4", "--out",
                                                      "spectra.csv"}, s.dir, {}, s.dir.parent_path());
    CHECK(e.exit_code == 2);
    CHECK_THAT(e.err, Catch::Contains("another magenc run is writing there"));
    CHECK_FALSE(fs::exists(s.dir / "spectra.csv"));
  }
}

TEST_CASE("faults: a CG solve that cannot converge stops with a clear error and its residual history",
          "[field_solver][faults]") {
  SECTION("solve_field with fem.max_iterations = 3 (PETSc GAMG, the default backend): exit 3, one line, no output") {
    ScratchDir s("magenc_cg_petsc");
    const ProcResult r =
        run(kBin / "solve_field", {"--config", kCoarse, "--set", "fem.max_iterations=3", "--out", "field"}, s.dir);
    INFO(r.err);
    CHECK(r.exit_code == 3);
    CHECK(count_lines(r.err) == 1);
    CHECK_THAT(r.err, Catch::Contains("CG did not converge") && Catch::Contains("fem.max_iterations = 3") &&
                          Catch::Contains("relative residual"));
    CHECK(s.entries_except({}).empty());
  }
  SECTION("solve_field with fem.max_iterations = 3 (Eigen PCG): exit 3, one line with the residual history") {
    ScratchDir s("magenc_cg");
    const ProcResult r = run(kBin / "solve_field", {"--config", kCoarse, "--set", "fem.solver=eigen-pcg", "--set",
                                                    "fem.max_iterations=3", "--out", "field"}, s.dir);
    INFO(r.err);
    CHECK(r.exit_code == 3);
    CHECK(count_lines(r.err) == 1);
    CHECK_THAT(r.err, Catch::Contains("CG did not converge") && Catch::Contains("fem.max_iterations = 3") &&
                          Catch::Contains("residual history (iteration: |r|/|f|) 0: 1, 1: ") &&
                          Catch::Contains(", 3: "));
    CHECK(s.entries_except({}).empty());
  }
  SECTION("an indefinite system: CG breaks down (p.Kp = 0) and stops at once") {
    // K = [[0, 1], [1, 0]] (eigenvalues +-1), f = (1, 0): the first search direction has p.Kp = 0.
    magenc::fem::SparseMatrix K(2, 2);
    K.insert(0, 1) = 1;
    K.insert(1, 0) = 1;
    K.makeCompressed();
    Eigen::VectorXd f(2), psi;
    f << 1, 0;
    magenc::fem::LinearSolveSettings o;
    o.progress_every = 0;
    const magenc::FpTrapPause breakdown_divides_by_zero;  // Debug builds: 1/0 is this test's point
    try {
      magenc::fem::eigen_pcg_solve(K, f, o, psi);
      FAIL("no error");
    } catch (const magenc::ComputeError& e) {
      CHECK_THAT(e.what(), Catch::Contains("CG broke down at iteration 1") && Catch::Contains("residual history"));
    }
  }
  SECTION("a symmetric positive definite system converges; its history starts at 1") {
    const int n = 50;  // 1-D Laplacian
    magenc::fem::SparseMatrix K(n, n);
    for (int i = 0; i < n; ++i) {
      K.insert(i, i) = 2;
      if (i > 0) K.insert(i, i - 1) = -1;
      if (i + 1 < n) K.insert(i, i + 1) = -1;
    }
    K.makeCompressed();
    Eigen::VectorXd f = Eigen::VectorXd::Ones(n), psi;
    magenc::fem::LinearSolveSettings o;
    o.progress_every = 0;
    const magenc::fem::LinearSolveResult st = magenc::fem::eigen_pcg_solve(K, f, o, psi);
    CHECK(st.residual <= o.tolerance);
    CHECK((K * psi - f).norm() <= 1e-8 * f.norm());
    o.max_iterations = 5;
    try {
      magenc::fem::eigen_pcg_solve(K, f, o, psi);
      FAIL("no error");
    } catch (const magenc::ComputeError& e) {
      CHECK_THAT(e.what(), Catch::Contains("after 5 iterations") && Catch::Contains("0: 1, 1: ") &&
                               Catch::Contains(", 4: ") && Catch::Contains(", 5: "));
    }
  }
}
