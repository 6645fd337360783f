// Study design: which magnet (radius, height, material), air gap, Bz array and probe radius r0 meet the
// requirements (p99 target uncalibrated or after calibration with drift, the chip's field window at the
// temperature extremes, stray fields) with the smallest magnet (docs/studies/design.md). Per design: p99
// uncalibrated and calibrated, field margin, magnet volume, pass/fail with the reason; Pareto fronts of p99
// against volume per sensor; the recommended design and its error budget. The computation lives in
// studies/design/design_study.*, the outputs in studies/design/design_report.*.
//   design [--config studies/design/design.toml] [--set design.samples=10000] [--out DIR]
//   mpirun -n N design ...   splits the designs over N ranks (contiguous blocks of design indices); rank 0
//                            gathers the results and writes the outputs, byte-identical to one process
//                            (every design is seeded from design.seed and its index).
#include <chrono>
#include <iostream>

#include <CLI/CLI.hpp>

#include "studies/design/design_study.hpp"
#include "core/cli.hpp"
#include "core/errors.hpp"
#include "core/mpi_launch.hpp"
#include "core/third_party_leaks.hpp"
#include "probe/common_keys.hpp"
#include "studies/design/design_report.hpp"
#include "report/study_output.hpp"

#ifdef MAGENC_DESIGN_MPI
#include <mpi.h>
#endif

using namespace magenc;

namespace {

const char* kDescription =
    "Design search: magnet, air gap, sensor and r0 from the requirements; Pareto fronts of p99 against magnet volume";

int g_rank = 0, g_size = 1;

// The designs of `rank`: a contiguous block of indices.
std::pair<std::size_t, std::size_t> block(std::size_t n, int rank, int size) {
  return {n * static_cast<std::size_t>(rank) / static_cast<std::size_t>(size),
          n * static_cast<std::size_t>(rank + 1) / static_cast<std::size_t>(size)};
}

// This rank's block evaluated; on rank 0 every rank's results in index order.
std::vector<DesignResult> evaluate_all(const DesignOptions& o) {
  const std::size_t n = o.space.size();
  const auto [b, e] = block(n, g_rank, g_size);
  std::vector<DesignResult> mine;
  try {
    mine = evaluate_designs(o, b, e);
  } catch (const std::exception& ex) {
#ifdef MAGENC_DESIGN_MPI
    if (g_size > 1) {  // the other ranks would wait for this one's results: end them all
      std::cerr << "design: rank " << g_rank << ": " << ex.what() << "\n";
      MPI_Abort(MPI_COMM_WORLD, 3);
    }
#endif
    throw;
  }
  if (g_size == 1) return mine;
#ifdef MAGENC_DESIGN_MPI
  const int K = DesignResult::kValues;
  std::vector<double> send(mine.size() * K);
  for (std::size_t i = 0; i < mine.size(); ++i) mine[i].to(send.data() + i * K);
  std::vector<int> counts(static_cast<std::size_t>(g_size)), displs(static_cast<std::size_t>(g_size));
  for (int r = 0; r < g_size; ++r) {
    const auto [rb, re] = block(n, r, g_size);
    counts[static_cast<std::size_t>(r)] = static_cast<int>((re - rb) * K);
    displs[static_cast<std::size_t>(r)] = static_cast<int>(rb * K);
  }
  std::vector<double> all(g_rank == 0 ? n * K : 0);
  MPI_Gatherv(send.data(), static_cast<int>(send.size()), MPI_DOUBLE, all.data(), counts.data(), displs.data(),
              MPI_DOUBLE, 0, MPI_COMM_WORLD);
  std::vector<DesignResult> out;
  for (std::size_t i = 0; g_rank == 0 && i < n; ++i) out.push_back(DesignResult::from(all.data() + i * K));
  return out;
#else
  return mine;
#endif
}

void run(const Config& cfg, StudyOutput& out) {
  const DesignOptions opt = DesignOptions::from_config(cfg);
  std::cout << "design: " << opt.space.size() << " designs x " << opt.samples << " samples on " << g_size << " rank"
            << (g_size == 1 ? "" : "s") << "\n";
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<DesignResult> results = evaluate_all(opt);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const DesignStudyResult r = summarize_designs(opt, std::move(results));
  out.write_text("design.csv", design_csv(opt, r));
  out.write_text("design_pareto.csv", design_pareto_csv(opt, r));
  out.write_text("design_budget.csv", design_budget_csv(opt, r));
  write_design_plots(opt, r, out.dir());
  out.write_text("summary.md", design_summary_md(opt, r, g_size, wall_s));
  std::cout << "design: " << design_verdict(opt, r) << "\n";
}

// Ranks > 0: the same command line and configuration, their block of designs, no output folder. Their
// input errors are rank 0's (the same configuration): rank 0 reports them, these ranks exit alike, silently.
int worker(int argc, char** argv) {
  try {
    const auto schema = merge_schemas(common_keys(), DesignOptions::keys());
    CLI::App app{kDescription, "design"};
    CommonOptions opts;
    add_common_options(app, opts, schema);
    parse_cli(app, argc, argv);
    const Config cfg = load_config(schema, opts);
    evaluate_all(DesignOptions::from_config(cfg));
    return 0;
  } catch (const InputError&) {
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "design: rank " << g_rank << ": " << e.what() << "\n";
    return 3;
  }
}

}  // namespace

int main(int argc, char** argv) {
#ifdef MAGENC_DESIGN_MPI
  // Without a launcher: one rank, and no MPI at all.
  const bool mpi = started_by_mpi_launcher();
  if (mpi) {
    {
      MAGENC_IGNORE_THIRD_PARTY_LEAKS;  // OpenMPI's start-up allocations are its own
      MPI_Init(&argc, &argv);
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  }
#endif
  const int rc = g_rank == 0 ? run_study("design", kDescription, DesignOptions::keys(), argc, argv, run)
                             : worker(argc, argv);
#ifdef MAGENC_DESIGN_MPI
  if (mpi) {
    MAGENC_IGNORE_THIRD_PARTY_LEAKS;
    MPI_Finalize();
  }
#endif
  return rc;
}
