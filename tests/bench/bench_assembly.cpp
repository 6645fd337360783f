// bench_assembly: wall time of the stiffness assembly (field_solver/fe/assembly.cpp) on
// solve_field's default domain meshed whole (the quadrant mirrored into four, as with
// fem.quadrant_solve = false: ~1.8M P2 tets, ~2.4M dofs), not a ctest test.
//   build/bin/bench_assembly [--threads N] [--repeat R] [--order 1|2] [--chunk CELLS] [--set key=value ...]
// Prints the mesh size, then each repetition's assemble_stiffness wall time, their
// minimum and median, and the process's peak RSS. One mesh, built once (its time is
// printed too). Issue 14's target: the 1.8M-tet P2 assembly well under 3 s on one core.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "field_solver/fe/assembly.hpp"
#include "core/format.hpp"
#include "field_solver/solve/fem_config.hpp"

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Peak RSS of this process (kB). Not field_outputs' peak_rss_mib: linking that object pulls in
// PETSc and Open MPI, and with them linked the repeated runs got faster (1.29 against 1.65 s
// from the 2nd run on, 1st run 1.93 s) and peak RSS larger (1512 against 1225 MiB): freed
// memory is reused differently. solve_field assembles once, so the bench stays without them.
long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace magenc;
  int threads = 1, repeat = 5, order = 2;
  int chunk = 0;  // 0: assemble_stiffness's default
  Config cfg(fem::solve_field_schema());
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--threads" && has_value) {
      threads = std::atoi(argv[++i]);
    } else if (a == "--repeat" && has_value) {
      repeat = std::atoi(argv[++i]);
    } else if (a == "--order" && has_value) {
      order = std::atoi(argv[++i]);
    } else if (a == "--chunk" && has_value) {
      chunk = std::atoi(argv[++i]);
    } else if (a == "--set" && has_value) {
      cfg.set(argv[++i]);
    } else {
      std::cerr << "bench_assembly: unknown argument " << a
                << " (allowed --threads N, --repeat R, --order 1|2, --chunk CELLS, --set key=value)\n";
      return 2;
    }
  }
  if (threads < 1 || repeat < 1 || chunk < 0 || (order != 1 && order != 2)) {
    std::cerr << "bench_assembly: --threads and --repeat must be >= 1, --chunk >= 1, --order 1 or 2\n";
    return 2;
  }
  const fem::FemSettings s = fem::fem_settings_from_config(cfg);
  auto t0 = Clock::now();
  const fem::TetMesh mesh = fem::mesh_domain(s.domain);
  const double t_mesh = since(t0);
  t0 = Clock::now();
  const fem::FeSpace space(mesh, order);
  const double t_space = since(t0);
  Eigen::VectorXd mu(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) mu[t] = s.domain.mu_r(mesh.region[t]);
  std::cout << "mesh: " << mesh.num_tets() << " tets, " << mesh.num_nodes() << " nodes (" << fmt(t_mesh, 2)
            << " s); P" << order << " space: " << space.num_dofs() << " dofs (" << fmt(t_space, 2) << " s)\n";
  std::vector<double> times;
  long long nnz = 0;
  for (int r = 0; r < repeat; ++r) {
    t0 = Clock::now();
    const fem::SparseMatrix K = chunk > 0 ? fem::assemble_stiffness(mesh, space, mu, s.solver.robin, threads, chunk)
                                          : fem::assemble_stiffness(mesh, space, mu, s.solver.robin, threads);
    times.push_back(since(t0));
    nnz = K.nonZeros();
    std::cout << "assemble_stiffness, " << threads << " thread(s), run " << r + 1 << ": " << fmt(times.back(), 3)
              << " s\n";
  }
  std::sort(times.begin(), times.end());
  std::cout << "nonzeros " << nnz << "; min " << fmt(times.front(), 3) << " s, median "
            << fmt(times[times.size() / 2], 3) << " s; peak RSS " << peak_rss_kb() << " kB\n";
  return 0;
}
